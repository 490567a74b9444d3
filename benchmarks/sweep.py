"""Sweep cost per point against the obvious alternative, a plain loop over simulate.

    python benchmarks/sweep.py [--points 200] [--repeats 3]

Per scene, the same grid of one parameter is run

* by a plain loop: ``mech.simulate(scene, {**params, name: value})`` for every value;
* by ``md.sweep(..., workers=1)``: one local worker process (started, sent the job once,
  ended: all inside the time), rows collected in the parent;
* the same with ``out=`` a CSV file (locked, each row written and flushed);

and, for the record, the dense 1001-point evaluation of states and outputs that each
point paid before (``plotting.dense_series``), now done only for scenes with outputs.
Times are wall-clock minima over repeats (the machine is shared); the compiled scene is
in memory before the first timing, so neither side derives nor compiles.
"""
from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

import mechdyn as md  # noqa: E402
from mechdyn.plotting import dense_series  # noqa: E402

# (model, scene, swept parameter, its range)
CASES = [("shoe_brake", "braking", "P", (10.0, 100.0)),
         ("two_mass_drive", "start", "k", (1000.0, 4000.0)),
         ("motor_startup", "startup", "J_f", (1.0, 9.0))]


def best(repeats, run):
    times = []
    for _ in range(repeats):
        started = time.perf_counter()
        run()
        times.append(time.perf_counter() - started)
    return min(times)


def measure(model_name, scene_name, name, bounds, points, repeats):
    model = md.load_model(ROOT / "models" / f"{model_name}.py")
    mech, scene = model.mechanism, model.scenes[scene_name]
    values = list(np.linspace(*bounds, points))
    params = {str(k): v for k, v in model.params.items()}
    mech.simulate(scene, params)                       # compiled once, in memory

    def loop():
        return [mech.simulate(scene, {**params, name: v}) for v in values]

    def swept(out=None):
        if out is not None:
            Path(out).unlink(missing_ok=True)
        table = md.sweep(mech, scene, params, {name: values}, workers=1, out=out,
                         progress=False, fresh=True)
        assert not table.failed, table.failed[0]["error"]

    results = loop()
    plain = best(repeats, loop)
    with tempfile.TemporaryDirectory() as folder:
        sweep_time = best(repeats, swept)
        filed = best(repeats, lambda: swept(Path(folder) / "rows.csv"))
    dense = best(repeats, lambda: [dense_series(r) for r in results])
    return {"case": f"{model_name} / {scene_name}", "outputs": len(scene.outputs),
            "plain": plain / points, "sweep": sweep_time / points,
            "file": filed / points, "dense": dense / points}


def report(rows, points):
    lines = [f"{points} points per scene; ms per point (ratio to the plain loop)", "",
             "| scene (outputs) | plain loop | sweep, 1 worker | sweep, 1 worker, out= | "
             "dense grid paid per point before |", "|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['case']} ({r['outputs']}) | {r['plain'] * 1e3:.2f} | "
                     f"{r['sweep'] * 1e3:.2f} ({r['sweep'] / r['plain']:.2f}x) | "
                     f"{r['file'] * 1e3:.2f} ({r['file'] / r['plain']:.2f}x) | "
                     f"{r['dense'] * 1e3:.2f} |")
    return "\n".join(lines)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--points", type=int, default=200)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args(argv)
    rows = [measure(*case, args.points, args.repeats) for case in CASES]
    print(report(rows, args.points))
    return rows


if __name__ == "__main__":
    main()

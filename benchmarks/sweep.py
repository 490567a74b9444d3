"""Sweep cost per point against the obvious alternative, a plain loop over simulate.

    python benchmarks/sweep.py [--points 200] [--repeats 5]

Per scene, the same grid of one parameter is run

* by a plain loop: ``mech.simulate(scene, {**params, name: value})`` for every value;
* by the same loop that also finds each output's peak as the sweep does
  (the ``peak:OUTPUT`` measure), for scenes with outputs;
* by ``md.sweep(..., workers=1)``: one local worker process (started, sent the job once,
  ended: all inside the time), rows collected in the parent;
* the same with ``out=`` a CSV file (locked, recorded, each row written and flushed);
* ``md.sweep(..., workers=2)``: two local worker processes (throughput on 2 cores);

and, for the record, the dense 1001-point evaluation of states and outputs each point
paid before (``plotting.dense_series`` on fresh results), now done only for scenes with
outputs. The runs of one repeat are interleaved and each figure is the minimum over the
repeats (the machine is shared); the compiled scene is in memory before the first
timing, so neither side derives nor compiles.
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


def peaks(result):
    """Each output's value of largest magnitude (the sweep's ``peak:OUTPUT`` measure)."""
    return {label: md.measure(f"peak:{label}")(result) for label in result.output_labels}


def measure(model_name, scene_name, name, bounds, points, repeats):
    model = md.load_model(ROOT / "models" / f"{model_name}.py")
    mech, scene = model.mechanism, model.scenes[scene_name]
    values = list(np.linspace(*bounds, points))
    params = {str(k): v for k, v in model.params.items()}
    mech.simulate(scene, params)                       # compiled once, in memory

    def loop():
        return [mech.simulate(scene, {**params, name: v}) for v in values]

    def loop_with_peaks():
        return [peaks(r) for r in loop()] if scene.outputs else loop()

    def swept(out=None, workers=1):
        table = md.sweep(mech, scene, params, {name: values}, workers=workers, out=out,
                         progress=False, fresh=True)
        assert not table.failed, table.failed[0]["error"]

    times = {"plain": [], "peaks": [], "sweep": [], "file": [], "two": [], "dense": []}
    with tempfile.TemporaryDirectory() as folder:
        for _ in range(repeats):
            for key, run in (("plain", loop), ("peaks", loop_with_peaks),
                             ("sweep", swept),
                             ("file", lambda: swept(Path(folder) / "rows.csv")),
                             ("two", lambda: swept(workers=2))):
                started = time.perf_counter()
                run()
                times[key].append(time.perf_counter() - started)
            fresh = loop()
            started = time.perf_counter()
            for result in fresh:
                dense_series(result)
            times["dense"].append(time.perf_counter() - started)
    return {"case": f"{model_name} / {scene_name}", "outputs": len(scene.outputs),
            **{key: min(values_) / points for key, values_ in times.items()}}


TARGET = 1.2


def report(rows, points):
    lines = [f"{points} points per scene; ms per point (ratio to the loop computing the "
             "same columns); throughput in points per second", "",
             "| scene (outputs) | plain loop | loop with the peaks | sweep, 1 worker | "
             "sweep, 1 worker, out= | sweep, 2 workers | points/s: loop, 1 worker, "
             "2 workers | dense grid each point paid before |",
             "|---|---|---|---|---|---|---|---|"]
    worst = 0.0
    for r in rows:
        same = r["peaks"]
        worst = max(worst, r["sweep"] / same)
        lines.append(f"| {r['case']} ({r['outputs']}) | {r['plain'] * 1e3:.2f} | "
                     f"{same * 1e3:.2f} | {r['sweep'] * 1e3:.2f} ({r['sweep'] / same:.2f}x) | "
                     f"{r['file'] * 1e3:.2f} ({r['file'] / same:.2f}x) | "
                     f"{r['two'] * 1e3:.2f} ({r['two'] / same:.2f}x) | "
                     f"{1 / same:.0f}, {1 / r['sweep']:.0f}, {1 / r['two']:.0f} | "
                     f"{r['dense'] * 1e3:.2f} |")
    lines += ["", f"Sweep with 1 worker against the loop computing the same columns: worst "
              f"{worst:.2f}x (target <= {TARGET}x: {'met' if worst <= TARGET else '**missed**'})."]
    return "\n".join(lines)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--points", type=int, default=200)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args(argv)
    rows = [measure(*case, args.points, args.repeats) for case in CASES]
    print(report(rows, args.points))
    return rows


if __name__ == "__main__":
    main()

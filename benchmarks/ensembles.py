"""Ensembles on the compiled path: points per second of a sweep at defaults.

    python benchmarks/ensembles.py [--points 1000] [--repeats 3]

The shoe brake (models/shoe_brake.py, scene ``braking``) over ``--points`` shoe forces,
in one run:

* ``md.sweep`` at defaults (``backend="auto"``: the compiled kernels; the points run in
  the calling process for the first second, then on local processes);
* the same with every point in the calling process (``HERE_SECONDS`` unbounded: what
  the default does on an idle machine, where 1,000 points take well under a second);
* ``md.sweep(..., workers=2)``: two local worker processes (started, sent the job,
  ended: all inside the time);
* a plain loop over ``simulate`` on the compiled kernels, and one on scipy's solvers
  (``backend="scipy"``, what ``auto`` ran before issue 24);

and the one-time costs outside those figures: the scene's numba compilation (an empty
disk cache) and its load from the disk cache in a fresh process. Times are minima over
the repeats (the median wall time beside), wall clock and CPU time of this process (the
machine is shared: on a loaded one the wall time is inflated, the CPU time of work done
in this process much less); the target is 1,000 points through ``sweep`` in under 1 s,
excluding the one compile.
"""
from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

import mechdyn as md  # noqa: E402
from mechdyn.analyse import sweeps  # noqa: E402

TARGET = 1.0          # s for 1,000 points through sweep


def one_time_costs():
    """Seconds: the scene's numba compilation with an empty cache, and a fresh process
    loading it from the disk cache (process start and imports included)."""
    script = ("import time, mechdyn as md; m = md.load_model({path!r}); "
              "s = m.scenes['braking']; c = m.mechanism.compile(s); t = time.perf_counter(); "
              "from mechdyn.compile.numba_model import numba_functions; numba_functions(c); "
              "print(time.perf_counter() - t)")
    path = str(ROOT / "models" / "shoe_brake.py")
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, MECHDYN_CACHE=cache, PYTHONPATH=str(ROOT))
        seconds = []
        for _ in range(2):                   # empty cache, then warm
            done = subprocess.run([sys.executable, "-c", script.format(path=path)],
                                  capture_output=True, text=True, env=env, check=True)
            seconds.append(float(done.stdout.split()[-1]))
    return seconds


def measure(points, repeats):
    model = md.load_model(ROOT / "models" / "shoe_brake.py")
    mech, scene = model.mechanism, model.scenes["braking"]
    params = {str(k): v for k, v in model.params.items()}
    forces = list(np.linspace(10.0, 100.0, points))
    on_scipy = replace(scene, backend="scipy")
    mech.simulate(scene, params)                   # compiled once: outside the timing
    mech.simulate(on_scipy, params)

    def here():
        limit, sweeps.HERE_SECONDS = sweeps.HERE_SECONDS, float("inf")
        try:
            swept()
        finally:
            sweeps.HERE_SECONDS = limit

    def swept(workers=None):
        table = md.sweep(mech, scene, params, {"P": forces}, workers=workers,
                         progress=False)
        assert not table.failed, table.failed[0]["error"]
        np.testing.assert_allclose(table["t_end"], 1000.0 / np.array(forces), rtol=1e-9)

    def loop(which):
        for force in forces:
            mech.simulate(which, {**params, "P": force})

    cases = {"sweep, defaults": swept, "sweep, all points in this process": here,
             "sweep, 2 worker processes": lambda: swept(2),
             "loop over simulate, compiled": lambda: loop(scene),
             "loop over simulate, scipy": lambda: loop(on_scipy)}
    times = {name: [] for name in cases}
    for _ in range(repeats):
        for name, run in cases.items():
            started, cpu = time.perf_counter(), time.process_time()
            run()
            times[name].append((time.perf_counter() - started, time.process_time() - cpu))
    return {name: (min(w for w, _ in values), min(c for _, c in values),
                   statistics.median(w for w, _ in values))
            for name, values in times.items()}


def report(times, points, compile_seconds, load_seconds):
    lines = [f"shoe brake, {points} points; minimum (median) of the repeats", "",
             "| path | wall s | CPU s (this process) | ms per point (wall) | points per "
             "second (wall) |", "|---|---|---|---|---|"]
    for name, (seconds, cpu, median) in times.items():
        lines.append(f"| {name} | {seconds:.3f} ({median:.3f}) | {cpu:.3f} | "
                     f"{seconds / points * 1e3:.3f} | {points / seconds:,.0f} |")
    per_thousand = times["sweep, defaults"][0] * 1000 / points
    lines += ["", f"one-time: the scene's numba compilation {compile_seconds:.2f} s (empty "
              f"cache), its load in a fresh process {load_seconds:.2f} s (warm cache)",
              f"1,000 points through sweep at defaults: {per_thousand:.2f} s (target < "
              f"{TARGET:.0f} s: {'met' if per_thousand < TARGET else '**missed**'})"]
    return "\n".join(lines)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--points", type=int, default=1000)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args(argv)
    compile_seconds, load_seconds = one_time_costs()
    print(report(measure(args.points, args.repeats), args.points, compile_seconds,
                 load_seconds))


if __name__ == "__main__":
    main()

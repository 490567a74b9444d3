"""What the backend rule costs: ``backend="auto"`` (compiled whenever numba is importable
and the scene has a compiled form) against ``backend="scipy"``, per scene, in one run.

    python benchmarks/backend_rule.py [--repeats 3]

For the slider-crank (1 s start-up, rtol 1e-8), the two-mass drive
(0.5 s) and the shoe brake (50 s to the stop), each at its scene's defaults otherwise:

* a fresh process that loads the model and simulates once (``python -c``, the whole
  process timed): with an empty disk cache (derivation, code generation and, for auto,
  the scene's numba compilation; minimum over ``--repeats``) and with the cache filled
  (auto and scipy run in turn ``--pairs`` times, A B A B ...: median wall time and
  median CPU time, user + system from the operating system's accounting of the child,
  and the median of the pairwise CPU ratios);
* in one process, the second run of the same call (the compiled form in memory;
  minimum over the repeats).

The machine is shared: CPU times move less with its load than wall times. The kernels
themselves are compiled once per installation before the first figure (announced on
stderr).
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

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

import mechdyn as md  # noqa: E402

CASES = [("slider_crank", "startup", {"rtol": 1e-8, "atol": 1e-10}),
         ("two_mass_drive", "start", {}), ("shoe_brake", "braking", {})]
SCRIPT = """
import mechdyn as md
from dataclasses import replace
model = md.load_model({path!r})
scene = replace(model.scenes[{scene!r}], backend={backend!r}, **{changes!r})
res = model.mechanism.simulate(scene, model.params)
assert set(res.stats["backends"]) == {{{backend!r}}} or {backend!r} == "auto", res.stats
"""


def process_seconds(model, scene, changes, backend, cache):
    """(wall s, CPU s) of a fresh process running the scene once."""
    code = SCRIPT.format(path=str(ROOT / "models" / f"{model}.py"), scene=scene,
                         backend=backend, changes=changes)
    env = dict(os.environ, MECHDYN_CACHE=cache, PYTHONPATH=str(ROOT))
    with tempfile.TemporaryFile() as errors:
        started = time.perf_counter()
        process = subprocess.Popen([sys.executable, "-c", code], env=env,
                                   stdout=subprocess.DEVNULL, stderr=errors)
        _, status, usage = os.wait4(process.pid, 0)
        wall = time.perf_counter() - started
        if os.waitstatus_to_exitcode(status):
            errors.seek(0)
            raise RuntimeError(f"{model} / {scene} ({backend}): {errors.read().decode()}")
    return wall, usage.ru_utime + usage.ru_stime


def measure(model_name, scene_name, changes, repeats, pairs):
    row = {"case": f"{model_name} / {scene_name}"}
    with tempfile.TemporaryDirectory() as cache:
        for backend in ("auto", "scipy"):        # fills the cache for both
            process_seconds(model_name, scene_name, changes, backend, cache)
        warm = [[process_seconds(model_name, scene_name, changes, backend, cache)
                 for backend in ("auto", "scipy")] for _ in range(pairs)]
    row["warm cpu ratio"] = statistics.median(a[1] / s[1] for a, s in warm)
    for side, backend in enumerate(("auto", "scipy")):
        cold = []
        for _ in range(repeats):
            with tempfile.TemporaryDirectory() as cache:
                cold.append(process_seconds(model_name, scene_name, changes, backend,
                                            cache)[0])
        model = md.load_model(ROOT / "models" / f"{model_name}.py")
        scene = replace(model.scenes[scene_name], backend=backend, **changes)
        result = model.mechanism.simulate(scene, model.params)
        again = []
        for _ in range(max(repeats, 5)):
            started = time.perf_counter()
            model.mechanism.simulate(scene, model.params)
            again.append(time.perf_counter() - started)
        row[backend] = {"cold": min(cold), "second": min(again),
                        "warm": statistics.median(pair[side][0] for pair in warm),
                        "warm cpu": statistics.median(pair[side][1] for pair in warm),
                        "backends": "+".join(result.stats["backends"])}
    return row


def report(rows):
    lines = ["| scene | backend taken by auto | fresh process, empty cache: auto / scipy | "
             "fresh process, warm cache: auto / scipy, wall (CPU) | CPU auto / scipy, "
             "paired | second run in a process: auto / scipy |", "|---|---|---|---|---|---|"]
    for r in rows:
        a, s = r["auto"], r["scipy"]
        lines.append(f"| {r['case']} | {a['backends']} | {a['cold']:.2f} s / {s['cold']:.2f} s"
                     f" | {a['warm']:.2f} s ({a['warm cpu']:.2f} s) / {s['warm']:.2f} s "
                     f"({s['warm cpu']:.2f} s) | {r['warm cpu ratio']:.2f} | "
                     f"{a['second'] * 1e3:.2f} ms / {s['second'] * 1e3:.2f} ms "
                     f"({s['second'] / a['second']:.0f}x) |")
    return "\n".join(lines)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=1, help="empty-cache runs")
    parser.add_argument("--pairs", type=int, default=7, help="warm-cache pairs")
    args = parser.parse_args(argv)
    import mechdyn.kernels  # noqa: F401  (the one-time kernel compilation, announced)
    print(report([measure(*case, args.repeats, args.pairs) for case in CASES]))


if __name__ == "__main__":
    main()

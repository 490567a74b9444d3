"""Segments with stuck elements, impacts, one-way clutches, lossy gears, switches and
closed loops: the default backend (compiled kernels) against ``backend="scipy"``, per
scene, in one process (issue 25).

    python benchmarks/segments.py [--repeats 3]

Each scene runs once per backend to warm up (the default compiles or loads the scene's
mode functions then, cached on disk), then the *second run* is timed, and the minimum
over ``--repeats`` runs is shown beside it (the machine is shared). The table names
the backends the default's steps took and the ratios of the second runs, of the fastest runs and of
the least CPU times. Garbage is collected before each timed run (for both backends
alike).
"""
from __future__ import annotations

import argparse
import gc
import sys
import time
from dataclasses import replace
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

import mechdyn as md  # noqa: E402

SCENES = [("clutch_engagement", "engage"), ("hard_stop", "bounce"), ("freewheel", "ride"),
          ("worm_hoist", "lift"), ("press_cycle", "startup"),
          ("fourbar_flywheel", "startup"), ("quick_return", "startup"),
          ("watt_sixbar", "startup"), ("shoe_brake", "braking"),
          ("hoist_drive", "lower_brake")]


def timed_runs(model, scene, repeats):
    """The backends of the second run, its seconds, the fastest of ``repeats`` and the
    least CPU time of one (the process's own seconds: what other users of a shared
    machine do not inflate)."""
    model.mechanism.simulate(scene, model.params)                   # warm-up
    times, cpu, backends = [], [], {}
    for _ in range(repeats):
        gc.collect()                   # the warm-up's garbage is not the run's cost
        started, started_cpu = time.perf_counter(), time.process_time()
        res = model.mechanism.simulate(scene, model.params)
        times.append(time.perf_counter() - started)
        cpu.append(time.process_time() - started_cpu)
        backends = res.stats["backends"]
    return backends, times[0], min(times), min(cpu)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args(argv)
    print(f"{'scene':34} {'default backends':20} {'2nd run':>9} {'min':>9} {'cpu':>8} "
          f"{'scipy 2nd':>10} {'min':>9} {'cpu':>8} {'ratio':>6} {'min':>5} {'cpu':>5}")
    for name, scene_name in SCENES:
        model = md.load_model(str(ROOT / "models" / f"{name}.py"))
        scene = model.scenes[scene_name]
        backends, second, fastest, cpu = timed_runs(model, scene, args.repeats)
        _, scipy_second, scipy_fastest, scipy_cpu = timed_runs(
            model, replace(scene, backend="scipy"), args.repeats)
        used = ", ".join(f"{k} {v}" for k, v in backends.items())
        print(f"{name + ' / ' + scene_name:34} {used:20} {second * 1e3:7.1f}ms "
              f"{fastest * 1e3:7.1f}ms {cpu * 1e3:6.1f}ms {scipy_second * 1e3:8.1f}ms "
              f"{scipy_fastest * 1e3:7.1f}ms {scipy_cpu * 1e3:6.1f}ms "
              f"{scipy_second / second:5.0f}x {scipy_fastest / fastest:4.0f}x "
              f"{scipy_cpu / cpu:4.0f}x", flush=True)


if __name__ == "__main__":
    main()

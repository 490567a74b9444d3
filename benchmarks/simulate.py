"""Simulation speed: mechdyn versus the obvious path, at matched accuracy.

    python benchmarks/simulate.py [--repeats 3]

Two machines: the exact slider-crank start-up (models/slider_crank.py, crank 0.1 m,
rod 0.4 m, 1 s) and a three-mass elastic drive start-up (benchmarks/elastic_drive.py,
0.5 s). The obvious path is benchmarks/obvious.py: LagrangesMethod + lambdify +
solve_ivp(RK45).

* Accuracy: every run is compared with an independent reference, the hand-written
  right-hand side integrated by DOP853 at rtol 1e-13, in mechdyn's work-precision norm:
  the Euclidean norm, over 100 evenly spaced dense-output times, of the largest state
  error relative to that state's largest magnitude. Each path sweeps rtol 1e-3 ... 1e-10;
  at a target error the cheapest run meeting it is compared (min of repeated runs).
* RHS per call: mechdyn's compiled ``rhs(t, y, p)``, the obvious ``lambdify`` + solve,
  and a hand-written Python function (timeit, best of repeats).
* Whole process (fresh Python each time): ``python -m mechdyn.cli simulate`` with an
  empty cache (cold, ``MECHDYN_CACHE`` a fresh directory) and again with the cache filled
  (warm); ``python benchmarks/obvious.py``; bare ``import`` costs for comparison.
"""
from __future__ import annotations

import argparse
import math
import os
import subprocess
import sys
import tempfile
import time
import timeit
from dataclasses import replace
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path[:0] = [str(ROOT), str(HERE)]

import mechdyn as md  # noqa: E402
import obvious  # noqa: E402

MACHINES = {"slider_crank": (ROOT / "models" / "slider_crank.py", "startup",
                             obvious.slider_crank_by_hand),
            "elastic_drive": (HERE / "elastic_drive.py", "start",
                              obvious.elastic_drive_by_hand)}
RTOLS = [10.0 ** -k for k in range(3, 11)]
MD_METHODS = ["auto", "RK45", "DOP853", "LSODA"]
TARGETS = [1e-4, 1e-6, 1e-8]
POINTS = 100


# ----------------------------------------------------------------------- helpers
def best_time(run, repeats):
    """(min seconds over ``repeats`` calls of ``run``, last return value)."""
    times, value = [], None
    for _ in range(repeats):
        started = time.perf_counter()
        value = run()
        times.append(time.perf_counter() - started)
    return min(times), value


def per_call(function, repeats, number=2000):
    return min(timeit.repeat(function, number=number, repeat=repeats)) / number


def l2_error(states, reference, scale):
    pointwise = np.max(np.abs(states - reference) / scale[:, None], axis=0)
    return float(np.sqrt(np.sum(pointwise ** 2)))


def cheapest(runs, target):
    """The fastest (time, rtol, error, label) run meeting ``target``, or None."""
    meeting = [r for r in runs if r[2] <= target]
    return min(meeting) if meeting else None


def run_process(args, env=None, repeats=3):
    """Minimum wall time of a fresh Python process running ``args`` (NaN if it fails)."""
    best = math.inf
    for _ in range(repeats):
        started = time.perf_counter()
        done = subprocess.run([sys.executable, *args], cwd=ROOT, env=env,
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        if done.returncode:
            return math.nan
        best = min(best, time.perf_counter() - started)
    return best


def whole_process(model_path, scene, repeats=3):
    """(cold, warm) seconds of ``python -m mechdyn.cli simulate`` (min over repeats;
    each cold run gets a fresh, empty cache directory)."""
    command = ["-m", "mechdyn.cli", "simulate", str(model_path), "--scene", scene]
    colds = []
    with tempfile.TemporaryDirectory() as base:
        for k in range(repeats):
            env = dict(os.environ, MECHDYN_CACHE=str(Path(base) / f"cache{k}"))
            colds.append(run_process(command, env, repeats=1))
        warm = run_process(command, env, repeats=repeats + 2)
    return min(colds), warm


def import_costs(repeats=5):
    return {what: run_process(["-c", code], repeats=repeats) for what, code in (
        ("python -c pass", "pass"),
        ("import sympy, scipy.integrate", "import sympy, scipy.integrate"),
        ("import mechdyn", "import mechdyn"))}


# ----------------------------------------------------------------------- one machine
def measure(name, repeats):
    path, scene_name, by_hand = MACHINES[name]
    model = md.load_model(path)
    scene = model.scenes[scene_name]
    mech, t_end = model.mechanism, scene.t_end
    times = np.linspace(0.0, t_end, POINTS)
    y0 = np.zeros(2 * len(mech.coordinates))
    exact = solve_ivp(by_hand, (0.0, t_end), y0, method="DOP853", rtol=1e-13, atol=1e-15,
                      dense_output=True).sol(times)
    scale = np.where(np.max(np.abs(exact), axis=1) > 0, np.max(np.abs(exact), axis=1), 1.0)

    setup_started = time.perf_counter()
    rhs = obvious.obvious_rhs(name)
    obvious_setup = time.perf_counter() - setup_started
    obvious_runs = []
    for rtol in RTOLS:
        seconds, solution = best_time(lambda: obvious.simulate(rhs, name, rtol),
                                      max(1, repeats - 1))
        obvious_runs.append((seconds, rtol, l2_error(solution.sol(times), exact, scale),
                             "RK45"))

    compiled = mech.compile(scene)
    md_runs = {}
    for method in MD_METHODS:
        md_runs[method] = []
        for rtol in RTOLS:
            run_scene = replace(scene, method=method, rtol=rtol, atol=rtol / 100)
            seconds, result = best_time(lambda: mech.simulate(run_scene, model.params),
                                        repeats)
            states = np.array(list(result.at(times).values()))
            md_runs[method].append((seconds, rtol, l2_error(states, exact, scale),
                                    result.stats["method"]))
    agreement = md_runs["DOP853"][-1][2]

    p = compiled.parameter_vector(model.params)
    y = list(np.linspace(0.1, 0.6, len(y0)))
    rhs_times = {"mechdyn compiled": per_call(lambda: compiled.rhs(0.0, y, p), repeats),
                 "hand-written Python": per_call(lambda: by_hand(0.0, y), repeats),
                 "obvious (lambdify + solve)": per_call(lambda: rhs(0.0, np.array(y)),
                                                        repeats, number=500)}
    cold, warm = whole_process(path, scene_name, repeats)
    obvious_process = run_process([str(HERE / "obvious.py"), name, "--rtol", "1e-6"],
                                  repeats=max(1, repeats - 1))
    return {"name": name, "obvious_runs": obvious_runs, "md_runs": md_runs,
            "obvious_setup": obvious_setup, "rhs": rhs_times, "cold": cold, "warm": warm,
            "obvious_process": obvious_process, "agreement": agreement}


# ----------------------------------------------------------------------- report
def report(m) -> str:
    lines = [f"### {m['name']}", "",
             "Simulation at matched accuracy (cheapest run meeting each target; the error "
             "is the L2 work-precision norm against the hand-written RHS at rtol 1e-13):",
             "", "| target | obvious RK45 | mechdyn auto | mechdyn best | "
             "obvious/auto | obvious/best |", "|---|---|---|---|---|---|"]
    all_md = [r for runs in m["md_runs"].values() for r in runs]
    for target in TARGETS:
        ob = cheapest(m["obvious_runs"], target)
        auto = cheapest(m["md_runs"]["auto"], target)
        best = cheapest(all_md, target)
        lines.append(f"| {target:.0e} | {_run(ob)} | {_run(auto)} | {_run(best)} | "
                     f"{_ratio(ob, auto)} | {_ratio(ob, best)} |")
    lines += ["", f"mechdyn DOP853 at rtol 1e-10 vs the reference: {m['agreement']:.1e}; "
              f"obvious setup (LagrangesMethod + lambdify, in process): "
              f"{m['obvious_setup']:.2f} s", "",
              "| RHS per call | us | vs hand-written |", "|---|---|---|"]
    hand = m["rhs"]["hand-written Python"]
    for label, seconds in m["rhs"].items():
        lines.append(f"| {label} | {seconds * 1e6:.2f} | {seconds / hand:.2f}x |")
    lines += ["", "| whole process | s |", "|---|---|",
              f"| mechdyn simulate, cold (empty cache) | {m['cold']:.2f} |",
              f"| mechdyn simulate, warm (cache hit) | {m['warm']:.2f} |",
              f"| obvious path (rtol 1e-6) | {m['obvious_process']:.2f} |", ""]
    return "\n".join(lines)


def _run(run):
    return "not met" if run is None else f"{run[0] * 1e3:.1f} ms ({run[3]}, rtol {run[1]:.0e})"


def _ratio(a, b):
    return "-" if a is None or b is None else f"{a[0] / b[0]:.1f}x"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args(argv)
    results = [measure(name, args.repeats) for name in MACHINES]
    imports = import_costs()
    print("\n".join(report(m) for m in results))
    print("| baseline process | s |\n|---|---|")
    for label, seconds in imports.items():
        print(f"| {label} | {seconds:.2f} |")
    return results, imports


if __name__ == "__main__":
    main()

"""Simulation speed at matched accuracy: mechdyn (auto, scipy, compiled), the obvious
path and the compiled floor.

    python benchmarks/simulate.py [--repeats 3] [--machines slider_crank,...]

Three machines: the exact slider-crank start-up (models/slider_crank.py, crank 0.1 m,
rod 0.4 m, 0-5 s), a three-mass elastic drive start-up (benchmarks/elastic_drive.py,
0.5 s) and the shoe brake (models/shoe_brake.py, 100 rad/s to rest, 50 s).

* mechdyn ``method="auto"`` with ``backend="auto"``, ``backend="scipy"`` and
  ``backend="compiled"`` (the compiled functions loaded before the timing), min of
  repeats in one process as for the obvious path. ``auto`` runs each tolerance in a
  fresh process (which has imported numpy and scipy.integrate, as the obvious path
  has; the generated code in the disk cache): the kernels are not loaded until auto
  decides a run is long enough to pay for loading them; "auto, first call" is that
  process's first ``simulate``: what a script pays.
* The obvious path (benchmarks/obvious.py): LagrangesMethod + lambdify + solve_ivp(RK45).
* The compiled floor: the scene's own generated, cse'd right-hand side compiled by numba
  (the function the compiled backend steps), called by a numba fixed-step RK4 loop doing
  as many RHS evaluations as the compiled run (no error control, no output, no events):
  the cost of the arithmetic alone. Acceptance (issue 15): compiled within 3x of it.
* Accuracy: every run is compared with an independent reference (the hand-written
  right-hand side integrated by DOP853 at rtol 1e-13; the brake's closed form) in the
  work-precision norm: the Euclidean norm, over 100 evenly spaced dense-output times, of
  the largest state error relative to that state's largest magnitude (the brake adds
  the error of its stop time). Each path sweeps rtol 1e-3 ... 1e-12 (the obvious path
  stops after a run over 10 s); at a target error the cheapest run meeting it is
  compared.
* RHS per call: mechdyn's generated ``rhs(t, y, p)`` called from Python, the obvious
  ``lambdify`` + solve, and a hand-written Python function (timeit, best of repeats).
"""
from __future__ import annotations

import argparse
import json
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

# name: (model file, scene, end time or None for the scene's stop condition)
MACHINES = {"slider_crank": (ROOT / "models" / "slider_crank.py", "startup", 5.0),
            "elastic_drive": (HERE / "elastic_drive.py", "start", None),
            "shoe_brake": (ROOT / "models" / "shoe_brake.py", "braking", None)}
RTOLS = [10.0 ** -k for k in range(3, 13)]
OBVIOUS_LIMIT = 10.0     # seconds: the obvious path skips tighter rtols after a run this long
TARGETS = [1e-4, 1e-6, 1e-8]
POINTS = 100
VARIANTS = ("auto", "scipy", "compiled")
FLOOR_TARGET = 3.0


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


def reference(name):
    """(times, exact states (n, POINTS), scale, end time) of a machine."""
    if name == "shoe_brake":
        t_end = 50.0
        times = np.linspace(0.0, t_end, POINTS)
        exact = obvious.shoe_brake_exact(times)
    else:
        by_hand = {"slider_crank": obvious.slider_crank_by_hand,
                   "elastic_drive": obvious.elastic_drive_by_hand}[name]
        t_end = obvious.T_END[name]
        times = np.linspace(0.0, t_end, POINTS)
        exact = solve_ivp(by_hand, (0.0, t_end), np.zeros(obvious.STATES[name]),
                          method="DOP853", rtol=1e-13, atol=1e-15,
                          dense_output=True).sol(times)
    magnitude = np.max(np.abs(exact), axis=1)
    return times, exact, np.where(magnitude > 0, magnitude, 1.0), t_end


def run_error(states, t_stop, ref):
    times, exact, scale, t_end = ref
    error = l2_error(states, exact, scale)
    return error if t_stop is None else max(error, abs(t_stop - t_end) / t_end)


def machine_scene(name):
    path, scene_name, t_end = MACHINES[name]
    model = md.load_model(path)
    scene = model.scenes[scene_name]
    return model, (scene if t_end is None else replace(scene, t_end=t_end))


# ----------------------------------------------------------------------- mechdyn runs
def mechdyn_runs(name, variant, rtols, repeats, ref_file, first_only=False):
    """Runs of one variant in this process: dicts of rtol, time, error, nfev, steps,
    method, backends (and the floor's time for the compiled variant)."""
    ref = tuple(np.load(ref_file)[k] for k in ("times", "exact", "scale")) + \
        (float(np.load(ref_file)["t_end"]),)
    import scipy.integrate  # noqa: F401  (imported by every path before its timing)
    model, scene = machine_scene(name)
    mech = model.mechanism
    compiled = mech.compile(scene)
    floor = None
    if variant == "compiled":
        from kernels import rk4_floor
        from mechdyn.compile.numba_model import numba_functions
        functions = numba_functions(compiled)
        floor = rk4_floor(functions.rhs)
        p = np.asarray(compiled.parameter_vector(model.params), dtype=float)
        slots = len(compiled.param_names)          # friction signs: sliding forward
        p[slots:slots + len(compiled.frictions)] = 1.0
    runs = []
    for rtol in rtols:
        run_scene = replace(scene, rtol=rtol, atol=rtol / 100, backend=variant)
        first = first_backends = None
        if first_only:                     # a fresh process: its first call, then more
            first, result = best_time(lambda: mech.simulate(run_scene, model.params), 1)
            first_backends = result.stats["backends"]
        seconds, result = best_time(lambda: mech.simulate(run_scene, model.params), repeats)
        states = np.array(list(result.at(np.minimum(ref[0], result.t_end)).values()))
        stop = result.t_end if name == "shoe_brake" else None
        run = {"rtol": rtol, "time": seconds, "error": run_error(states, stop, ref),
               "nfev": result.stats["nfev"], "steps": result.stats["steps"],
               "method": result.stats["method"], "backends": result.stats["backends"]}
        if first is not None:
            run.update(first=first, first_backends=first_backends)
        if floor is not None:
            y0 = np.ascontiguousarray(result.y[:, 0], dtype=float)
            steps = max(1, result.stats["nfev"] // 4)
            floor(y0, p, result.t_end, 1)                              # compiled
            run["floor"] = best_time(lambda: floor(y0, p, result.t_end, steps),
                                     max(repeats, 3))[0]
        runs.append(run)
    return runs


def child_runs(name, variant, rtols, repeats, ref_file, first_only=False):
    """mechdyn_runs in a fresh process."""
    done = subprocess.run([sys.executable, __file__, "--child", name, variant, ref_file,
                           json.dumps(rtols), str(repeats)] + (["--first"] if first_only
                                                                else []),
                          cwd=ROOT, capture_output=True, text=True)
    if done.returncode:
        raise RuntimeError(f"{name} {variant}: {done.stderr.strip()[-2000:]}")
    return json.loads(done.stdout.strip().splitlines()[-1])


def auto_runs(name, repeats, ref_file):
    """``auto``: each rtol in a fresh process (its first call, then min of repeats)."""
    return [child_runs(name, "auto", [rtol], repeats, ref_file, first_only=True)[0]
            for rtol in RTOLS]


# ----------------------------------------------------------------------- one machine
def measure(name, repeats):
    ref = reference(name)
    with tempfile.TemporaryDirectory() as folder:
        ref_file = str(Path(folder) / "reference.npz")
        np.savez(ref_file, times=ref[0], exact=ref[1], scale=ref[2], t_end=ref[3])
        runs = {"compiled": child_runs(name, "compiled", RTOLS, max(repeats, 5), ref_file)}
        runs["scipy"] = child_runs(name, "scipy", RTOLS, repeats, ref_file)
        runs["auto"] = auto_runs(name, repeats, ref_file)

    setup_started = time.perf_counter()
    rhs = obvious.obvious_rhs(name)
    obvious_setup = time.perf_counter() - setup_started
    obvious_runs = []
    for rtol in RTOLS:
        if obvious_runs and obvious_runs[-1]["time"] > OBVIOUS_LIMIT:
            obvious_runs.append(None)
            continue
        seconds, solution = best_time(lambda: obvious.simulate(rhs, name, rtol),
                                      max(1, repeats - 1))
        stop = solution.t[-1] if name == "shoe_brake" else None
        states = solution.sol(np.minimum(ref[0], solution.t[-1]))
        obvious_runs.append({"rtol": rtol, "time": seconds, "error": run_error(states, stop,
                                                                               ref),
                             "nfev": solution.nfev, "method": "RK45"})

    model, scene = machine_scene(name)
    compiled = model.mechanism.compile(scene)
    p = compiled.parameter_vector(model.params)
    y = list(np.linspace(0.1, 0.6, len(compiled.state_names)))
    by_hand = {"slider_crank": obvious.slider_crank_by_hand,
               "elastic_drive": obvious.elastic_drive_by_hand}.get(name)
    rhs_times = {"mechdyn generated (Python)": per_call(lambda: compiled.rhs(0.0, y, p),
                                                        repeats),
                 "obvious (lambdify + solve)": per_call(lambda: rhs(0.0, np.array(y)),
                                                        repeats, number=500)}
    if by_hand is not None:
        rhs_times["hand-written Python"] = per_call(lambda: by_hand(0.0, y), repeats)
    return {"name": name, "runs": runs, "obvious_runs": obvious_runs,
            "obvious_setup": obvious_setup, "rhs": rhs_times}


# ----------------------------------------------------------------------- report
def cheapest(runs, target):
    meeting = [r for r in runs if r is not None and r["error"] <= target]
    return min(meeting, key=lambda r: r["time"]) if meeting else None


def report(m) -> str:
    lines = [f"### {m['name']}", "",
             "Cheapest run meeting each target error (time, rtol, RHS evaluations); the "
             "floor does the compiled run's RHS evaluations:", "",
             "| target | obvious RK45 | mechdyn auto | mechdyn scipy | mechdyn compiled | "
             "compiled floor | compiled / floor | obvious / auto | auto, first call |",
             "|---|---|---|---|---|---|---|---|---|"]
    for target in TARGETS:
        ob = cheapest(m["obvious_runs"], target)
        auto, scipy_, comp = (cheapest(m["runs"][v], target) for v in VARIANTS)
        floor = comp and comp.get("floor")
        lines.append(f"| {target:.0e} | {_run(ob)} | {_run(auto)} | {_run(scipy_)} | "
                     f"{_run(comp)} | {_ms(floor)} | "
                     f"{_ratio(comp and comp['time'], floor)} | "
                     f"{_ratio(ob and ob['time'], auto and auto['time'])} | "
                     f"{_first(auto)} |")
    lines += ["", "All runs (time ms / error / method used):", "",
              "| rtol | " + " | ".join(("obvious",) + VARIANTS) + " | floor ms |",
              "|---|---|---|---|---|---|"]
    for k, rtol in enumerate(RTOLS):
        cells = [_brief(m["obvious_runs"][k])] + [_brief(m["runs"][v][k]) for v in VARIANTS]
        lines.append(f"| {rtol:.0e} | " + " | ".join(cells) +
                     f" | {_ms(m['runs']['compiled'][k].get('floor'))} |")
    lines += ["", f"obvious setup (LagrangesMethod + lambdify, in process): "
              f"{m['obvious_setup']:.2f} s", "", "| RHS per call | us |", "|---|---|"]
    lines += [f"| {label} | {seconds * 1e6:.2f} |" for label, seconds in m["rhs"].items()]
    return "\n".join(lines + [""])


def verdicts(machines) -> str:
    """Compiled against the floor at each target, per machine, in one line each."""
    out = []
    for m in machines:
        ratios = []
        for target in TARGETS:
            comp = cheapest(m["runs"]["compiled"], target)
            if comp and comp.get("floor"):
                ratios.append(f"{comp['time'] / comp['floor']:.1f}x at {target:.0e}")
        worst = max((cheapest(m["runs"]["compiled"], t)["time"] /
                     cheapest(m["runs"]["compiled"], t)["floor"]
                     for t in TARGETS if cheapest(m["runs"]["compiled"], t)), default=None)
        verdict = "-" if worst is None else ("met" if worst <= FLOOR_TARGET else "**missed**")
        out.append(f"- {m['name']}: compiled / floor {', '.join(ratios) or '-'} "
                   f"(target <= {FLOOR_TARGET:g}x: {verdict})")
    return "\n".join(out)


def _run(run):
    return "not met" if run is None else \
        f"{run['time'] * 1e3:.2f} ms ({run['rtol']:.0e}, {run['nfev']})"


def _first(run):
    if run is None or "first" not in run:
        return "-"
    where = "+".join(run["first_backends"])
    return f"{run['first'] * 1e3:.2f} ms ({where})"


def _brief(run):
    if run is None:
        return "skipped"
    return f"{run['time'] * 1e3:.2f} / {run['error']:.0e} / {run['method']}"


def _ms(seconds):
    return "-" if not seconds else f"{seconds * 1e3:.3f} ms"


def _ratio(a, b):
    return "-" if not a or not b else f"{a / b:.1f}x"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--machines", default=",".join(MACHINES))
    parser.add_argument("--child", nargs=5, help=argparse.SUPPRESS)
    parser.add_argument("--first", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.child:
        name, variant, ref_file, rtols, repeats = args.child
        print(json.dumps(mechdyn_runs(name, variant, json.loads(rtols), int(repeats),
                                      ref_file, args.first)))
        return None
    results = []
    for name in args.machines.split(","):
        started = time.perf_counter()
        results.append(measure(name, args.repeats))
        print(report(results[-1]), f"[{time.perf_counter() - started:.0f} s]", flush=True)
    print(verdicts(results))
    return results


if __name__ == "__main__":
    main()

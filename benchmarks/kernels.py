"""Compiled integration kernels (mechdyn.kernels) versus scipy and a compiled RK4 floor.

    python benchmarks/kernels.py [--repeats 3] [--quick]

Problems: a slider-crank-like 1-DOF machine (I(phi) = J + m l^2 sin^2 phi, constant
moment, 5 s), the stiff two-inertia drive (J1 = 1, J2 = 1e-4, k = 1e6, damping ratio 0.1,
M = 10, 1 s) and its undamped version, Van der Pol with mu = 1000 (3000 s). Every run is
compared with an independent reference (the matrix exponential for the linear drives,
scipy at rtol 1e-13 / Radau at 1e-12 otherwise) in the work-precision norm of
benchmarks/simulate.py: the largest error over 101 evenly spaced times of each state,
relative to that state's largest magnitude.

Rows: the kernels' DOP853, Rodas5P (analytic Jacobian, and finite differences), "auto"
(a Python loop over the kernel that starts with DOP853 and switches on the kernel's
STIFF / NONSTIFF statuses), scipy's solve_ivp (DOP853, Radau, LSODA; the same numba RHS
called from Python, Jacobians where the kernels have them). "floor" is a numba
fixed-step RK4 loop with the RHS compiled in, doing the same number of RHS evaluations
as the row (no error control, no output): the compiled floor of issue 15. Times are the
best of --repeats runs, with dense output stored (kernels) / requested (scipy).

Then the kernel's cost outside the runs: compile time with an empty numba cache, warm
load time in a fresh process (import + first call), and bytes stored per step.
"""
import argparse
import math
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from numba import njit
from scipy.integrate import solve_ivp
from scipy.linalg import expm

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from mechdyn import kernels as mk  # noqa: E402

SIG, JSIG = mk.RHS_SIGNATURE, mk.JAC_SIGNATURE


# ------------------------------------------------------------------------ the problems
@njit(SIG, cache=True)
def crank(t, y, p, out):
    s, c = math.sin(y[0]), math.cos(y[0])
    out[0] = y[1]
    ml2 = p[1] * p[2] ** 2                      # I(phi) = J + m l^2 sin^2 phi
    out[1] = (p[3] - ml2 * s * c * y[1] ** 2) / (p[0] + ml2 * s * s)


@njit(SIG, cache=True)
def drive(t, y, p, out):
    torque = p[2] * (y[0] - y[1]) + p[3] * (y[2] - y[3])
    out[0] = y[2]
    out[1] = y[3]
    out[2] = (p[4] - torque) / p[0]
    out[3] = torque / p[1]


@njit(JSIG, cache=True)
def drive_jac(t, y, p, out):
    out[:, :] = 0.0
    out[0, 2] = out[1, 3] = 1.0
    for row, inertia, sign in ((2, p[0], -1.0), (3, p[1], 1.0)):
        out[row, 0], out[row, 1] = sign * p[2] / inertia, -sign * p[2] / inertia
        out[row, 2], out[row, 3] = sign * p[3] / inertia, -sign * p[3] / inertia


@njit(SIG, cache=True)
def vdp(t, y, p, out):
    out[0] = y[1]
    out[1] = p[0] * (1.0 - y[0] ** 2) * y[1] - y[0]


@njit(JSIG, cache=True)
def vdp_jac(t, y, p, out):
    out[0, 0], out[0, 1] = 0.0, 1.0
    out[1, 0], out[1, 1] = -2.0 * p[0] * y[0] * y[1] - 1.0, p[0] * (1.0 - y[0] ** 2)


@njit(SIG, cache=True)
def robertson(t, y, p, out):
    out[0] = -0.04 * y[0] + 1e4 * y[1] * y[2]
    out[1] = 0.04 * y[0] - 1e4 * y[1] * y[2] - 3e7 * y[1] ** 2
    out[2] = 3e7 * y[1] ** 2


def scipy_fun(rhs, p, n):
    def f(t, y):
        out = np.empty(n)
        rhs(t, np.ascontiguousarray(y), p, out)
        return out
    return f


def scipy_jac(jac, p, n):
    if jac is None:
        return None

    def j(t, y):
        out = np.empty((n, n))
        jac(t, np.ascontiguousarray(y), p, out)
        return out
    return j


def drive_reference(p):
    J1, J2, k, c, M = p
    a = np.zeros((5, 5))
    a[0, 2] = a[1, 3] = 1.0
    a[2, :4] = np.array([-k, k, -c, c]) / J1
    a[3, :4] = np.array([k, -k, c, -c]) / J2
    a[2, 4] = M / J1
    return lambda times: np.array([(expm(a * t) @ [0, 0, 0, 0, 1.0])[:4] for t in times])


def scipy_reference(rhs, jac, p, y0, t_end, method, rtol):
    options = {} if jac is None else {"jac": scipy_jac(jac, p, len(y0))}
    sol = solve_ivp(scipy_fun(rhs, p, len(y0)), (0.0, t_end), y0, method=method, rtol=rtol,
                    atol=rtol * 1e-2, dense_output=True, **options).sol
    return lambda times: sol(times).T


def problems():
    J1, J2, k, M = 1.0, 1e-4, 1e6, 10.0
    c = 2 * 0.1 * math.sqrt(k * J1 * J2 / (J1 + J2))
    crank_p = np.array([0.05, 2.0, 0.1, 1.0])
    vdp_p = np.array([1000.0])
    return [
        dict(name="crank", rhs=crank, jac=None, p=crank_p, y0=np.zeros(2), t_end=5.0,
             reference=scipy_reference(crank, None, crank_p, np.zeros(2), 5.0, "DOP853",
                                       1e-13), stiff=False),
        dict(name="damped pair", rhs=drive, jac=drive_jac, p=np.array([J1, J2, k, c, M]),
             y0=np.zeros(4), t_end=1.0, reference=drive_reference([J1, J2, k, c, M]),
             stiff=True),
        dict(name="undamped pair", rhs=drive, jac=drive_jac,
             p=np.array([J1, J2, k, 0.0, M]), y0=np.zeros(4), t_end=1.0,
             reference=drive_reference([J1, J2, k, 0.0, M]), stiff=False),
        dict(name="van der pol", rhs=vdp, jac=vdp_jac, p=vdp_p, y0=np.array([2.0, 0.0]),
             t_end=3000.0, reference=scipy_reference(vdp, vdp_jac, vdp_p, [2.0, 0.0],
                                                     3000.0, "Radau", 1e-12), stiff=True),
        dict(name="robertson", rhs=robertson, jac=None, p=np.zeros(0),
             y0=np.array([1.0, 0.0, 0.0]), t_end=1e5,
             reference=scipy_reference(robertson, None, np.zeros(0), [1.0, 0.0, 0.0], 1e5,
                                       "Radau", 1e-12), stiff=True),
    ]


# ---------------------------------------------------------------------------- solvers
def kernel_run(problem, method, rtol, use_jac=True, auto=False):
    functions = mk.model_functions(problem["rhs"], problem["jac"] if use_jac else None)
    run = mk.Integration(functions, problem["p"], 0.0, problem["y0"], method=method,
                         rtol=rtol, atol=rtol * 1e-2, autonomous=True, detect_switch=auto)
    chunks = []
    while True:
        chunk = run.advance(problem["t_end"], max_steps=200_000)
        chunks.append(chunk)
        if chunk.status == mk.STIFF:
            run.switch(mk.RODAS5P)
        elif chunk.status == mk.NONSTIFF:
            run.switch(mk.DOP853)
        elif chunk.status != mk.CHUNK_FULL or run.stats["naccept"] >= 1_000_000:
            break

    def solution(times):
        out = np.empty((len(times), len(problem["y0"])))
        for chunk in chunks:
            if len(chunk.ts) > 1:
                inside = (times >= chunk.ts[0]) & (times <= chunk.ts[-1])
                out[inside] = mk.dense_values(chunk.ts, chunk.coefs, times[inside])
        return out
    stats = run.stats
    ok = run.t == problem["t_end"]
    return solution, stats["naccept"], stats["nfev"], ok


def scipy_run(problem, method, rtol):
    n = len(problem["y0"])
    options = {}
    if method != "DOP853" and problem["jac"] is not None:
        options["jac"] = scipy_jac(problem["jac"], problem["p"], n)
    result = solve_ivp(scipy_fun(problem["rhs"], problem["p"], n), (0.0, problem["t_end"]),
                       problem["y0"], method=method, rtol=rtol, atol=rtol * 1e-2,
                       dense_output=True, **options)
    solution = lambda times: result.sol(times).T  # noqa: E731
    return solution, result.t.size - 1, result.nfev, result.success


_floors = {}


def rk4_floor(rhs):
    """A numba RK4 loop with ``rhs`` compiled in: the cost of the RHS evaluations alone."""
    if rhs not in _floors:
        @njit
        def floor(y0, p, t_end, steps):
            n = y0.size
            y, h = y0.copy(), t_end / steps
            k = np.empty((4, n))
            tmp = np.empty(n)
            for i in range(steps):
                t = i * h
                rhs(t, y, p, k[0])
                for j in range(n):
                    tmp[j] = y[j] + 0.5 * h * k[0, j]
                rhs(t + 0.5 * h, tmp, p, k[1])
                for j in range(n):
                    tmp[j] = y[j] + 0.5 * h * k[1, j]
                rhs(t + 0.5 * h, tmp, p, k[2])
                for j in range(n):
                    tmp[j] = y[j] + h * k[2, j]
                rhs(t + h, tmp, p, k[3])
                for j in range(n):
                    y[j] += h / 6.0 * (k[0, j] + 2.0 * k[1, j] + 2.0 * k[2, j] + k[3, j])
            return y
        _floors[rhs] = floor
    return _floors[rhs]


def best_time(run, repeats):
    times, value = [], None
    for _ in range(repeats):
        started = time.perf_counter()
        value = run()
        times.append(time.perf_counter() - started)
    return min(times), value


def error(solution, reference, t_end):
    times = np.linspace(0.0, t_end, 101)
    ref = reference(times)
    scale = np.maximum(np.max(np.abs(ref), axis=0), 1e-300)
    return float(np.max(np.abs(solution(times) - ref) / scale))


# --------------------------------------------------------------------------- tables
def run_table(repeats, quick):
    rtols = [1e-6] if quick else [1e-6, 1e-10]
    print(f"{'problem':14} {'rtol':>6} {'solver':17} {'ms':>9} {'steps':>8} {'nfev':>9} "
          f"{'error':>8} {'floor ms':>9} {'x floor':>8}")
    for problem in problems():
        floor = rk4_floor(problem["rhs"])
        floor(problem["y0"], problem["p"], problem["t_end"], 1)     # compile
        for rtol in rtols:
            rows = [("kernel DOP853", lambda: kernel_run(problem, mk.DOP853, rtol)),
                    ("kernel Rodas5P", lambda: kernel_run(problem, mk.RODAS5P, rtol)),
                    ("kernel Rodas5P fd", lambda: kernel_run(problem, mk.RODAS5P, rtol,
                                                             use_jac=False)),
                    ("kernel auto", lambda: kernel_run(problem, mk.DOP853, rtol,
                                                       auto=True)),
                    ("scipy Radau", lambda: scipy_run(problem, "Radau", rtol)),
                    ("scipy LSODA", lambda: scipy_run(problem, "LSODA", rtol))]
            if not problem["stiff"]:
                rows.append(("scipy DOP853", lambda: scipy_run(problem, "DOP853", rtol)))
            for label, run in rows:
                if label.startswith("scipy") and problem["name"] == "undamped pair" \
                        and rtol < 1e-8:
                    print(f"{problem['name']:14} {rtol:6.0e} {label:17} "
                          "(skipped: about a million steps in Python)")
                    continue
                seconds, (solution, steps, nfev, ok) = best_time(
                    run, 1 if label.startswith("scipy") else repeats)
                err = error(solution, problem["reference"], problem["t_end"]) if ok \
                    else math.nan
                floor_seconds, _ = best_time(lambda: floor(problem["y0"], problem["p"],
                                                           problem["t_end"],
                                                           max(1, nfev // 4)), repeats)
                print(f"{problem['name']:14} {rtol:6.0e} {label:17} {seconds * 1e3:9.2f} "
                      f"{steps:8d} {nfev:9d} {err:8.1e} {floor_seconds * 1e3:9.2f} "
                      f"{seconds / floor_seconds:8.1f}" + ("" if ok else "  (failed)"))


def robustness_table():
    """Rodas5P's step count when the inputs change in their last bits (where Radau's
    Newton iteration made the step count of the damped pair vary from 550 to 501,227)."""
    print("\nRodas5P at rtol 1e-10, parameters scaled by (1 + k eps), k = 0..19: "
          "accepted steps min / max, largest error")
    for problem in problems():
        if problem["name"] not in ("damped pair", "van der pol", "robertson"):
            continue
        steps, errors = [], []
        for k in range(20):
            perturbed = dict(problem, p=problem["p"] * (1.0 + k * np.finfo(float).eps))
            solution, accepted, _, ok = kernel_run(perturbed, mk.RODAS5P, 1e-10)
            steps.append(accepted)
            errors.append(error(solution, problem["reference"], problem["t_end"]) if ok
                          else math.inf)
        print(f"  {problem['name']:14} {min(steps):7d} / {max(steps):7d}   "
              f"{max(errors):.1e}")


MODEL = '''
from numba import njit
@njit("void(float64, float64[::1], float64[::1], float64[::1])", cache=True)
def decay(t, y, p, out):
    out[0] = -p[0] * y[0]
'''

PROBE = '''
import sys, time
sys.path[:0] = [{root!r}, {tmp!r}]
started = time.perf_counter()
import numpy, numba
numba_done = time.perf_counter()
import mechdyn
mechdyn_done = time.perf_counter()
from mechdyn import kernels
import model
run = kernels.Integration(kernels.model_functions(model.decay), [1.0], 0.0, [1.0])
run.advance(1.0)
done = time.perf_counter()
print(numba_done - started, mechdyn_done - numba_done, done - mechdyn_done)
'''


def process_table(repeats):
    """Fresh processes: an empty numba cache (compiles the kernel and the model), then
    the filled cache (best of ``repeats``); and, for scale, the process that only
    imports numpy and scipy.integrate (issue 15's reference for a warm CLI run)."""
    with tempfile.TemporaryDirectory() as tmp:
        Path(tmp, "model.py").write_text(MODEL)
        env = {**os.environ, "NUMBA_CACHE_DIR": str(Path(tmp, "cache")),    # the model's
               "MECHDYN_CACHE": str(Path(tmp, "mechdyn"))}                  # the kernels'
        probe = PROBE.format(root=str(ROOT), tmp=tmp)

        def measure(code=probe):
            started = time.perf_counter()
            out = subprocess.run([sys.executable, "-c", code], env=env, check=True,
                                 capture_output=True, text=True).stdout.split()
            return [float(x) for x in out] + [time.perf_counter() - started]
        cold = measure()
        warm = min((measure() for _ in range(repeats)), key=lambda r: r[-1])
        scipy_only = min(measure("import numpy, scipy.integrate")[-1]
                         for _ in range(repeats))
    print("\nprocess (s)                 import numpy+numba  import mechdyn  "
          "kernels import + first call  whole process")
    for label, row in (("cold (empty numba cache)", cold), ("warm (cache filled)", warm)):
        print(f"{label:27} {row[0]:18.2f} {row[1]:15.2f} {row[2]:28.2f} {row[3]:14.2f}")
    reference = 'python -c "import numpy, scipy.integrate"'
    print(f"{reference:75} {scipy_only:14.2f}")
    print("\nbytes stored per step (n states): DOP853 8 + 72 n (t, y, 8 coefficients), "
          "Rodas5P 8 + 48 n (t, y, 5 coefficients)")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--quick", action="store_true", help="rtol 1e-6 only")
    parser.add_argument("--process-only", action="store_true",
                        help="only compile and load times")
    args = parser.parse_args()
    if not args.process_only:
        run_table(args.repeats, args.quick)
        robustness_table()
    process_table(args.repeats)


if __name__ == "__main__":
    main()

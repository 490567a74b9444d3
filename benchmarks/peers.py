"""The slider-crank beside its peers, in one run: mechdyn at its defaults (and on scipy)
against sympy's LagrangesMethod + lambdify + solve_ivp (LSODA, RK45). PyDy (Cython) and
CasADi (cvodes) are not wired in yet: neither is installed where this was written, so
no code for them could be checked; they are listed as rows not run.

    python benchmarks/peers.py [--repeats 5] [--rtol 1e-8]

The exact slider-crank of models/slider_crank.py (the same parameters in
benchmarks/obvious.py), started from rest, 0-5 s, rtol 1e-8, atol rtol / 100. Each
peer's warm run is timed (minimum over the repeats; the setup, derivation and
compilation, once before and reported apart), with the machine's default BLAS threading.
Every run's final crank angle is compared with mechdyn's at rtol 1e-12, so a fast wrong
answer shows.
"""
from __future__ import annotations

import argparse
import sys
import time
from dataclasses import replace
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path[:0] = [str(ROOT), str(HERE)]

import mechdyn as md  # noqa: E402
import obvious  # noqa: E402

T_END = 5.0


def timed(run, repeats):
    best, value = float("inf"), None
    for _ in range(repeats):
        started = time.perf_counter()
        value = run()
        best = min(best, time.perf_counter() - started)
    return best, value


def mechdyn_rows(rtol, repeats):
    model = md.load_model(ROOT / "models" / "slider_crank.py")
    scene = replace(model.scenes["startup"], t_end=T_END, rtol=rtol, atol=rtol / 100)
    rows = []
    for backend in ("auto", "scipy"):
        run_scene = replace(scene, backend=backend)
        started = time.perf_counter()
        first = model.mechanism.simulate(run_scene, model.params)
        setup = time.perf_counter() - started
        seconds, res = timed(lambda: model.mechanism.simulate(run_scene, model.params),
                             repeats)
        rows.append((f"mechdyn, backend={backend!r} ({'+'.join(first.stats['backends'])})",
                     setup, seconds, float(res.y[0, -1])))
    exact = model.mechanism.simulate(replace(scene, rtol=1e-12, atol=1e-14),
                                     model.params).y[0, -1]
    return rows, float(exact)


def lambdify_rows(rtol, repeats):
    started = time.perf_counter()
    rhs = obvious.obvious_rhs("slider_crank")
    setup = time.perf_counter() - started
    rows = []
    for method in ("LSODA", "RK45"):
        seconds, sol = timed(lambda: obvious.simulate(rhs, "slider_crank", rtol, method),
                             repeats)
        rows.append((f"sympy LagrangesMethod + lambdify + solve_ivp {method}", setup,
                     seconds, float(sol.y[0, -1])))
    return rows


def missing_rows():
    return [(name, None, None, None) for name in ("PyDy (Cython) + odeint",
                                                  "CasADi + cvodes")]


def report(rows, exact, rtol):
    lines = [f"slider-crank 0-{T_END:g} s at rtol {rtol:g}; warm run = minimum over the "
             "repeats", "", "| path | setup s | warm run ms | vs mechdyn default | final "
             "angle error |", "|---|---|---|---|---|"]
    default = rows[0][2]
    for name, setup, seconds, final in rows:
        if seconds is None:
            lines.append(f"| {name} | not run (not wired in yet) | - | - | - |")
            continue
        lines.append(f"| {name} | {setup:.2f} | {seconds * 1e3:.2f} | "
                     f"{seconds / default:.0f}x | {abs(final - exact) / abs(exact):.1e} |")
    return "\n".join(lines)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--rtol", type=float, default=1e-8)
    args = parser.parse_args(argv)
    rows, exact = mechdyn_rows(args.rtol, args.repeats)
    rows += lambdify_rows(args.rtol, args.repeats) + missing_rows()
    print(report(rows, exact, args.rtol))


if __name__ == "__main__":
    main()

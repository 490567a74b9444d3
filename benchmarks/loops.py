"""Closed loops: derivation and compilation time of a four-bar declared with a loop, its
simulation against the same four-bar written as an explicit closed form, and the drift
of the loop constraints over 100 crank revolutions with three ways of controlling it.

    python benchmarks/loops.py [--repeats 3] [--revolutions 100]

The four-bar (crank a = 0.1, coupler b = 0.35, rocker c = 0.3, ground d = 0.4 m; coupler
and rocker uniform bars of 1.5 and 1.2 kg, crank J = 0.002 kg m^2; gravity) turns freely
from phi = 0 at 30 rad/s: conservative, so T + V must stay constant.

* loop: coordinates phi, theta_2, theta_3 and ``mech.loop`` (mechdyn's KKT right-hand
  side, DOP853 at the default rtol 1e-10 / atol 1e-12).
* closed form: one coordinate phi, theta_2(phi) and theta_3(phi) written out by
  Freudenstein's solution (atan2 and acos of the crank angle), the same links and scene.

Derivation + compilation: ``mech.equations()`` and ``compile_scene`` on a freshly
declared mechanism, sympy's cache cleared, the disk cache off; CPU time, minimum of the
repeats. Simulation: wall time of ``mech.simulate`` (compiled already), minimum of the
repeats. Drift (max |g| over the run, in m, and the relative change of T + V):

* none: the KKT right-hand side alone (the driver's drift check switched off here);
* Baumgarte: the bias replaced by ``bias + 2 alpha g' + alpha^2 g`` (alpha = 30 1/s, the
  crank speed; numpy KKT), no projection;
* projection (mechdyn's default): after a step where |g| or |g'| exceeds rtol times the
  loop's size, the state is projected back onto the loops and the segment restarts.
"""
from __future__ import annotations

import argparse
import dataclasses
import sys
import time
from pathlib import Path

import numpy as np
import sympy as sp
from sympy.core.cache import clear_cache

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

import os  # noqa: E402

os.environ["MECHDYN_CACHE"] = "off"

import mechdyn as md  # noqa: E402
from mechdyn.compile import compiler as md_compile  # noqa: E402
from mechdyn.simulate import simulation as md_simulate  # noqa: E402
from mechdyn.simulate.assembly import closure_parts  # noqa: E402

A, B, C, D = 0.1, 0.35, 0.3, 0.4
J1, M2, M3 = 0.002, 1.5, 1.2
OMEGA = 30.0


def links(mech, phi, th2, th3):
    pin = (A * sp.cos(phi), A * sp.sin(phi))
    mech.link("crank", J=J1, angle=phi)
    mech.link("coupler", m=M2, J=M2 * B**2 / 12, x=pin[0] + B / 2 * sp.cos(th2),
              y=pin[1] + B / 2 * sp.sin(th2), angle=th2)
    mech.link("rocker", m=M3, J=M3 * C**2 / 12, x=D + C / 2 * sp.cos(th3),
              y=C / 2 * sp.sin(th3), angle=th3)
    mech.gravity()


def loop_four_bar(t_end):
    phi, th2, th3 = md.coordinates("phi theta_2 theta_3")
    mech = md.Mechanism("four-bar (loop)", [phi, th2, th3])
    links(mech, phi, th2, th3)
    mech.loop("ABCD", (A, phi), (B, th2), (-C, th3), (-D, 0))
    scene = md.Scene("free", initial={phi: 0, md.speed(phi): OMEGA, th2: 1.2, th3: 1.9},
                     t_end=t_end)
    return mech, scene, phi


def closed_four_bar(t_end):
    """Freudenstein: P cos th3 + Q sin th3 = R, th3 = atan2(Q, P) + acos(R / |(P, Q)|)."""
    phi = md.coordinate("phi")
    p = 2 * C * (D - A * sp.cos(phi))
    q = -2 * A * C * sp.sin(phi)
    r = B**2 - A**2 - C**2 - D**2 + 2 * A * D * sp.cos(phi)
    th3 = sp.atan2(q, p) + sp.acos(r / sp.sqrt(p**2 + q**2))
    th2 = sp.atan2(C * sp.sin(th3) - A * sp.sin(phi), D + C * sp.cos(th3) - A * sp.cos(phi))
    mech = md.Mechanism("four-bar (closed form)", [phi])
    links(mech, phi, th2, th3)
    scene = md.Scene("free", initial={phi: 0, md.speed(phi): OMEGA}, t_end=t_end)
    return mech, scene, phi


def build_time(make, repeats):
    best = np.inf
    for _ in range(repeats):
        clear_cache()
        md_compile._memory_cache.clear()
        start = time.process_time()
        mech, scene, _ = make(1.0)
        mech.equations(scene)
        mech.compile(scene)
        best = min(best, time.process_time() - start)
    return best


def simulate(make, t_end, repeats):
    mech, scene, phi = make(t_end)
    mech.compile(scene)
    best, result = np.inf, None
    for _ in range(repeats):
        start = time.perf_counter()
        result = mech.simulate(scene, {})
        best = min(best, time.perf_counter() - start)
    return best, result, phi


def drift(result):
    """Max |g| of the loop over the run, relative change of T + V."""
    compiled = result.compiled
    worst = max(np.max(np.abs(closure_parts(compiled, t, y, [])[0]))
                for t, y in zip(result.t, result.y.T))
    kinetic, potential = result.energy()
    total = kinetic + potential
    return worst, np.max(np.abs(total - total[0])) / kinetic[0]


def baumgarte(compiled, alpha):
    """A numpy KKT right-hand side with Baumgarte's stabilised bias."""
    n = compiled.dof

    def rhs(t, y, p):
        v = compiled.terms(t, y, p)
        mass = np.array(v[:n * n]).reshape(n, n)
        forcing = np.array(v[n * n:n * n + n])
        g, grads, rate_t, bias = closure_parts(compiled, t, y, p)
        speed = grads @ np.asarray(y[n:]) + rate_t
        m = len(g)
        system = np.block([[mass, -grads.T], [grads, np.zeros((m, m))]])
        rhs_vector = np.concatenate([forcing, -(bias + 2 * alpha * speed + alpha**2 * g)])
        return list(y[n:]) + list(np.linalg.solve(system, rhs_vector)[:n])
    return rhs


def drift_table(t_end):
    rows = []
    original = md_simulate._Run._drifted
    try:
        md_simulate._Run._drifted = lambda self, t, y, p: False
        mech, scene, _ = loop_four_bar(t_end)
        start = time.perf_counter()
        result = mech.simulate(scene, {})
        rows.append(("none", *drift(result), result.stats["steps"],
                     time.perf_counter() - start))
        compiled = mech.compile(scene)
        fast_rhs = compiled.rhs
        compiled.rhs = baumgarte(compiled, OMEGA)
        try:
            start = time.perf_counter()
            result = mech.simulate(scene, {})
            rows.append((f"Baumgarte (alpha = {OMEGA:g}/s)", *drift(result),
                         result.stats["steps"], time.perf_counter() - start))
        finally:
            compiled.rhs = fast_rhs
    finally:
        md_simulate._Run._drifted = original
    mech, scene, _ = loop_four_bar(t_end)
    start = time.perf_counter()
    result = mech.simulate(scene, {})
    rows.append((f"projection ({result.stats.get('projections', 0)} restarts)",
                 *drift(result), result.stats["steps"], time.perf_counter() - start))
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--revolutions", type=int, default=100)
    args = parser.parse_args()
    t_end = args.revolutions * 2 * np.pi / 25.0     # mean crank speed about 25 rad/s

    print("derivation + compilation (CPU s, min of repeats, caches off)")
    print("| four-bar | derive + compile |")
    print("| --- | --- |")
    for name, make in (("loop", loop_four_bar), ("closed form", closed_four_bar)):
        print(f"| {name} | {build_time(make, args.repeats):.3f} s |")

    print(f"\nsimulation, {args.revolutions} crank revolutions ({t_end:.1f} s), defaults")
    loop_time, loop_result, phi = simulate(loop_four_bar, t_end, args.repeats)
    closed_time, closed_result, _ = simulate(closed_four_bar, t_end, args.repeats)
    mech, scene, _ = loop_four_bar(t_end)
    reference = mech.simulate(dataclasses.replace(scene, rtol=1e-13, atol=1e-14), {})
    print("| four-bar | wall time | steps | RHS calls | final phi | its error |")
    print("| --- | --- | --- | --- | --- | --- |")
    for name, seconds, result in (("loop", loop_time, loop_result),
                                  ("closed form", closed_time, closed_result)):
        print(f"| {name} | {seconds:.3f} s | {result.stats['steps']} | "
              f"{result.stats['nfev']} | {result.final(phi):.9f} | "
              f"{abs(result.final(phi) - reference.final(phi)):.1e} |")
    print(f"loop / closed form: {loop_time / closed_time:.2f}x the time (errors against "
          "the loop at rtol 1e-13)")

    print(f"\ndrift of the loop over {args.revolutions} revolutions (default tolerances)")
    print("| drift control | max abs g [m] | max rel. change of T + V | steps | wall |")
    print("| --- | --- | --- | --- | --- |")
    for name, worst, energy, steps, seconds in drift_table(t_end):
        print(f"| {name} | {worst:.2e} | {energy:.2e} | {steps} | {seconds:.2f} s |")


if __name__ == "__main__":
    main()

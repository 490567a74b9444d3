"""Derivation time: mechdyn versus sympy.physics.mechanics.LagrangesMethod.

    python benchmarks/derive.py [--repeats 3]

Two workloads, the same physical system both ways:

* a chain of N inertias J_i joined by torsional springs k_i and dampers c_i, driven by a
  moment M on the first (N = 2, 4, 8, 16, 32);
* the six bundled models (worked examples 1-6). Their LagrangesMethod equivalent is
  built from the model's own declaration by ``lagranges_method_of`` below: T and V from
  the link positions, springs and gravity, each load, damper and friction as a force on a
  point that moves along the load's ``along`` expression (so its generalized force is
  value * d(along)/dq, as in mechdyn).

Timed as CPU time of this process (``time.process_time``, so a busy shared machine
disturbs it less than wall time), minimum over repeats, sympy's cache cleared before
every run:

* mechdyn: ``mech.equations()`` on a freshly declared mechanism, plus reading
  ``mass_matrix`` and ``forcing`` (declaring it is timed separately and shown);
* LagrangesMethod: ``LagrangesMethod(L, q, forcelist, frame)``,
  ``form_lagranges_equations()``, ``mass_matrix`` and ``forcing`` (building L and the
  force list is not timed).

Before timing, both results are checked equal: ``simplify(M_md - M_lm) == 0`` and the
same for the forcing, for the chains with N <= 4 and for every model.
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import sympy as sp
from sympy.core.cache import clear_cache
from sympy.physics.mechanics import (LagrangesMethod, Point, ReferenceFrame,
                                     dynamicsymbols)

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

import mechdyn as md  # noqa: E402

MODELS = ["shoe_brake", "gear_pair", "cam_follower", "scotch_yoke", "planetary_2kh",
          "rope_hoist"]
CHAIN_SIZES = [2, 4, 8, 16, 32]


# ----------------------------------------------------------------------- the chain
def chain_symbols(n):
    J = sp.symbols(f"J_1:{n + 1}", positive=True)
    k = sp.symbols(f"k_1:{n}", positive=True)
    c = sp.symbols(f"c_1:{n}", positive=True)
    return J, k, c, sp.Symbol("M", real=True)


def md_chain(n):
    """The chain declared in mechdyn."""
    J, k, c, M = chain_symbols(n)
    phi = md.coordinates(" ".join(f"phi_{i + 1}" for i in range(n)))
    mech = md.Mechanism(f"chain of {n}", phi)
    for i in range(n):
        mech.link(f"disc {i + 1}", J=J[i], angle=phi[i])
    for i in range(n - 1):
        twist = phi[i + 1] - phi[i]
        mech.spring(f"shaft {i + 1}", k[i], stretch=twist)
        mech.damper(f"damping {i + 1}", c[i], stretch=twist)
    mech.load("drive", M, along=phi[0])
    return mech


def lm_chain(n):
    """The same chain for LagrangesMethod: L = T - V, damper and drive torques on frames."""
    J, k, c, M = chain_symbols(n)
    q = dynamicsymbols(f"phi_1:{n + 1}")
    qd = [qi.diff(dynamicsymbols._t) for qi in q]
    N = ReferenceFrame("N")
    frames = [N.orientnew(f"A{i + 1}", "Axis", [q[i], N.z]) for i in range(n)]
    T = sum(J[i] * qd[i] ** 2 / 2 for i in range(n))
    V = sum(k[i] * (q[i + 1] - q[i]) ** 2 / 2 for i in range(n - 1))
    torque = {i: sp.S.Zero for i in range(n)}
    torque[0] += M
    for i in range(n - 1):
        damping = c[i] * (qd[i + 1] - qd[i])
        torque[i + 1] -= damping
        torque[i] += damping
    forces = [(frames[i], torque[i] * N.z) for i in range(n)]
    return (T - V, q, forces, N), q


# ---------------------------------------------------- a model for LagrangesMethod
def lagranges_method_of(mechanism):
    """T - V, coordinates, force list and frame for LagrangesMethod, from a mechdyn
    mechanism's declaration (links, loads, springs, dampers, gravity, friction)."""
    t = dynamicsymbols._t
    q = [dynamicsymbols(c.func.__name__) for c in mechanism.coordinates]
    speeds = {md.speed(c): qi.diff(t) for c, qi in zip(mechanism.coordinates, q)}
    coords = dict(zip(mechanism.coordinates, q))

    def dyn(expr):
        return sp.sympify(expr).xreplace(speeds).xreplace(coords).xreplace({md.t: t})

    N = ReferenceFrame("N")
    origin = Point("O")
    origin.set_vel(N, 0)
    T, V, forces = sp.S.Zero, sp.S.Zero, []

    def force_along(name, along, value):
        point = origin.locatenew(f"P_{len(forces)}", along * N.x)
        point.set_vel(N, point.pos_from(origin).dt(N))
        forces.append((point, value * N.x))

    for e in mechanism.elements.values():
        if isinstance(e, md.Link):
            x, y, angle = dyn(e.x), dyn(e.y), dyn(e.angle)
            T += e.m * (x.diff(t) ** 2 + y.diff(t) ** 2) / 2 + e.J * angle.diff(t) ** 2 / 2
    for e in mechanism.elements.values():
        if isinstance(e, md.Load):
            along, value = dyn(e.along), dyn(e.value)
            if e.efficiency is not None:
                power = value * along.diff(t)
                value = value * sp.Piecewise((e.efficiency, power > 0),
                                             (1 / e.efficiency, True))
            force_along(e.name, along, value)
        elif isinstance(e, md.Spring):
            V += dyn(e.k) * dyn(e.stretch) ** 2 / 2
        elif isinstance(e, md.Damper):
            stretch = dyn(e.stretch)
            force_along(e.name, stretch, -dyn(e.c) * stretch.diff(t))
        elif isinstance(e, md.Friction):
            along = dyn(e.along)
            force_along(e.name, along, -dyn(e.moment) * sp.sign(along.diff(t)))
        elif isinstance(e, md.Gravity):
            V += sum(l.m * e.g * dyn(l.y) for l in mechanism.elements.values()
                     if isinstance(l, md.Link))
    return (T - V, q, forces or None, N), q


def run_lagranges_method(args):
    L, q, forces, frame = args
    lm = LagrangesMethod(L, q, forcelist=forces, frame=frame)
    lm.form_lagranges_equations()
    return lm.mass_matrix, lm.forcing


def run_mechdyn(mech):
    eqs = mech.equations()
    return eqs.mass_matrix, eqs.forcing


# ------------------------------------------------------------------- comparing
def to_plain(matrix, q, coordinates):
    """LagrangesMethod output in mechdyn's plain symbols."""
    t = dynamicsymbols._t
    subs = {qi.diff(t): md.plain(md.speed(c)) for qi, c in zip(q, coordinates)}
    matrix = matrix.xreplace(subs)
    matrix = matrix.xreplace({qi: md.plain(c) for qi, c in zip(q, coordinates)})
    return matrix.xreplace({t: md.t})


def check_same(label, mech, lm_args, q):
    m_md, f_md = run_mechdyn(mech)
    m_lm, f_lm = run_lagranges_method(lm_args)
    m_lm, f_lm = (to_plain(m, q, mech.coordinates) for m in (m_lm, f_lm))
    same_m = (m_md - m_lm).applyfunc(sp.simplify) == sp.zeros(*m_md.shape)
    same_f = (f_md - f_lm).applyfunc(sp.simplify) == sp.zeros(*f_md.shape)
    if not (same_m and same_f):
        raise SystemExit(f"{label}: mechdyn and LagrangesMethod disagree "
                         f"(mass matrix {'ok' if same_m else 'DIFFERS'}, "
                         f"forcing {'ok' if same_f else 'DIFFERS'})")
    return "same M, f"


# --------------------------------------------------------------------- timing
def best_of(repeats, setup, run):
    best = float("inf")
    for _ in range(repeats):
        clear_cache()
        arg = setup()
        start = time.process_time()
        run(arg)
        best = min(best, time.process_time() - start)
    return best


def declare_time(repeats, build):
    return best_of(repeats, lambda: None, lambda _: build())


def row(label, build_md, build_lm, repeats, lm_repeats, check):
    declare = declare_time(repeats, build_md)
    t_md = best_of(repeats, build_md, run_mechdyn)
    t_lm = best_of(lm_repeats, lambda: build_lm()[0], run_lagranges_method)
    checked = check() if check else "-"
    print(f"{label:16s} {declare * 1e3:10.1f} {t_md * 1e3:10.1f} {t_lm * 1e3:12.1f} "
          f"{t_lm / t_md:8.1f}x   {checked}", flush=True)
    return t_md, t_lm


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args(argv)
    print(f"sympy {sp.__version__}, python {sys.version.split()[0]}; "
          f"CPU time, min of {args.repeats} runs, sympy cache cleared before each\n")
    header = (f"{'system':16s} {'md declare':>10s} {'md derive':>10s} {'LagrangesM.':>12s} "
              f"{'LM/md':>9s}   check")
    print(header + "\n" + f"{'':16s} {'ms':>10s} {'ms':>10s} {'ms':>12s}\n" + "-" * len(header))
    results = {}
    for n in CHAIN_SIZES:
        check = (lambda n=n: check_same(f"chain {n}", md_chain(n), *lm_chain(n))) \
            if n <= 4 else None
        results[n] = row(f"chain N={n}", lambda n=n: md_chain(n), lambda n=n: lm_chain(n),
                         args.repeats, args.repeats if n < 32 else max(1, args.repeats - 1),
                         check)
    print()
    for name in MODELS:
        path = ROOT / "models" / f"{name}.py"

        def build(path=path):
            return md.load_model(path).mechanism

        def check(name=name, build=build):
            mech = build()
            return check_same(name, mech, *lagranges_method_of(build()))

        row(name, build, lambda build=build: lagranges_method_of(build()), args.repeats,
            args.repeats, check)
    print()
    for n in (16, 32):
        t_md, t_lm = results[n]
        verdict = "met" if t_lm / t_md >= 10 else "NOT met"
        print(f"target >= 10x at N={n}: {t_lm / t_md:.1f}x ({verdict})")


if __name__ == "__main__":
    main()

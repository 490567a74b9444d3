"""Stiff large models (issue 39): the chain of N discs on stiff shafts against CasADi +
cvodes (BDF, equations written by hand) in the same process, and a tree of discs
numbered along its branches against the same tree numbered at random.

    python benchmarks/stiff_large.py [--sizes 100] [--tree 100] [--repeats 3]
    python benchmarks/stiff_large.py --sizes 10 30 100 300 1000 --scaling 1e6 1e3

The chain: discs J_i = 0.01 (1 + i mod 3) on shafts k = 1e6 N m/rad with dampers
c = 5 N m s/rad, a drive of 5 N m on the first disc, a load -0.02 phidot on the last,
0-1 s from rest, rtol 1e-8, atol 1e-10 (issue 39's acceptance). mechdyn runs at its
defaults (``method="auto"``: DOP853 until the kernel sees stiffness, then Rodas5P with
the banded iteration matrix of ``mechdyn.kernels.band``). Columns: the first run (an
empty cache: derivation, code generation, numba), the warm run (best of ``--repeats``),
right-hand-side evaluations, the steps of each method, and the largest error of the
end state against a tight reference (the same equations written by hand, scipy's DOP853
at rtol 1e-13).

The tree: a binary tree of discs on the same shafts and dampers, driven at the root and
loaded at every leaf; its coordinates declared level by level (along the branches) and
in a random order. The warm runs' ratio is the acceptance's (within 1.5x).
"""
from __future__ import annotations

import argparse
import os
import random
import subprocess
import sys
import tempfile

import numpy as np

from peer_models import timed

K, C, DRIVE, LOAD = 1e6, 5.0, 5.0, 0.02
RTOL, ATOL, T_END = 1e-8, 1e-10, 1.0


def inertias(n):
    return [0.01 * (1 + i % 3) for i in range(n)]


def tree_parents(n):
    """parent[i] of disc i (None for the root) of a binary tree numbered by levels."""
    return [None] + [(i - 1) // 2 for i in range(1, n)]


def mechanism(parents, declared_order):
    """Discs ``0..n-1`` joined to their parents by damped shafts; coordinates declared in
    ``declared_order``; the drive on disc 0, the load on every disc without children."""
    import sympy as sp
    import mechdyn as md
    n = len(parents)
    names = [f"phi{i}" for i in range(n)]
    symbols = dict(zip([names[i] for i in declared_order],
                       md.coordinates(" ".join(names[i] for i in declared_order))))
    phi = [symbols[name] for name in names]
    k, c, m, b = sp.symbols("k c M b", positive=True)
    mech = md.Mechanism(f"{n} discs", [phi[i] for i in declared_order])
    for i, inertia in enumerate(inertias(n)):
        mech.link(f"disc {i}", J=inertia, angle=phi[i])
    for i, parent in enumerate(parents):
        if parent is not None:
            mech.spring(f"shaft {i}", k, stretch=phi[i] - phi[parent])
            mech.damper(f"damper {i}", c, stretch=phi[i] - phi[parent])
    mech.load("drive", m, along=phi[0])
    leaves = set(range(n)) - {p for p in parents if p is not None}
    for i in sorted(leaves):
        mech.load(f"load {i}", -b * md.speed(phi[i]), along=phi[i])
    scene = md.Scene("start", initial={**{q: 0 for q in phi}, **{md.speed(q): 0 for q in phi}},
                     t_end=T_END, rtol=RTOL, atol=ATOL)
    return mech, scene, {"k": K, "c": C, "M": DRIVE, "b": LOAD}, names


def by_hand(parents):
    """The right-hand side written by hand (numpy): J_i phi_i'' = the shafts' moments."""
    n = len(parents)
    inertia = np.array(inertias(n))
    child = np.array([i for i, p in enumerate(parents) if p is not None])
    parent = np.array([p for p in parents if p is not None])
    leaves = np.array(sorted(set(range(n)) - set(parent.tolist())))

    def rhs(t, y):
        q, u = y[:n], y[n:]
        shaft = K * (q[child] - q[parent]) + C * (u[child] - u[parent])
        moment = np.zeros(n)
        np.add.at(moment, parent, shaft)
        np.add.at(moment, child, -shaft)
        moment[0] += DRIVE
        moment[leaves] -= LOAD * u[leaves]
        return np.concatenate([u, moment / inertia])
    return rhs


def reference(parents):
    from scipy.integrate import solve_ivp
    n = len(parents)
    return solve_ivp(by_hand(parents), (0.0, T_END), np.zeros(2 * n), method="DOP853",
                     rtol=1e-13, atol=1e-14).y[:, -1]


def mechdyn_row(parents, declared_order, repeats):
    mech, scene, values, names = mechanism(parents, declared_order)
    first, _ = timed(lambda: mech.simulate(scene, values), 1)
    warm, result = timed(lambda: mech.simulate(scene, values), repeats)
    n, states = len(names), result.state_names            # speeds follow the positions
    rows = [states.index(name) for name in names]
    end = np.array([result[states[i]][-1] for i in rows] +
                   [result[states[n + i]][-1] for i in rows])
    return {"first": first, "warm": warm, "nfev": result.stats["nfev"],
            "methods": result.stats.get("methods"), "end": end}


def casadi_row(parents, repeats):
    """CasADi's cvodes (BDF, its defaults) on the chain or tree written by hand, set up
    as benchmarks/peers.py's chain (``peer_models._casadi_run``)."""
    import casadi as ca
    import peer_models
    n = len(parents)
    q, u = ca.SX.sym("q", n), ca.SX.sym("u", n)
    moments = [0] * n
    for i, p in enumerate(parents):
        if p is not None:
            shaft = K * (q[i] - q[p]) + C * (u[i] - u[p])
            moments[p] += shaft
            moments[i] -= shaft
    moments[0] += DRIVE
    for i in set(range(n)) - {p for p in parents if p is not None}:
        moments[i] -= LOAD * u[i]
    inertia = inertias(n)
    ode = ca.vertcat(u, ca.vertcat(*[moments[i] / inertia[i] for i in range(n)]))
    _, run = peer_models._casadi_run(ca.vertcat(q, u), ca.SX.sym("p", 0), ode, [], T_END,
                                     RTOL, ATOL)
    run()                                          # the first call sets cvodes up
    warm, (end, nfev) = timed(run, repeats)
    return {"first": None, "warm": warm, "nfev": nfev, "methods": None, "end": end}


def line(name, row, exact):
    first = "-" if row["first"] is None else f"{row['first']:.2f}"
    methods = ", ".join(f"{k} {v}" for k, v in (row["methods"] or {}).items()) or "BDF"
    error = np.max(np.abs(row["end"] - exact))
    return (f"| {name} | {first} | {row['warm']:.3f} | {row['nfev']} | {methods} | "
            f"{error:.1e} |")


HEAD = ["| path | first run s | warm run s | RHS evals | steps | end error |",
        "|---|---|---|---|---|---|"]


def chain_table(n, repeats):
    parents = [None] + list(range(n - 1))
    exact = reference(parents)
    rows = [f"chain of {n} discs (stiff shafts), 0-{T_END:g} s, rtol {RTOL:g}, atol {ATOL:g}; "
            f"end error: largest |difference| from the reference (scale "
            f"{np.max(np.abs(exact)):.2f})", "", *HEAD,
            line("mechdyn defaults", mechdyn_row(parents, range(n), repeats), exact)]
    try:
        rows.append(line("CasADi + cvodes BDF, by hand", casadi_row(parents, repeats), exact))
    except ImportError:
        rows.append("| CasADi: not installed | - | - | - | - | - |")
    return rows


def tree_table(n, repeats, seed=1):
    parents = tree_parents(n)
    exact = reference(parents)
    shuffled = list(range(n))
    random.Random(seed).shuffle(shuffled)
    along = mechdyn_row(parents, range(n), repeats)
    scattered = mechdyn_row(parents, shuffled, repeats)
    return [f"binary tree of {n} discs (stiff shafts), the same run", "", *HEAD,
            line("numbered along its branches", along, exact),
            line("numbered at random", scattered, exact), "",
            f"random / along the branches: {scattered['warm'] / along['warm']:.2f}x"]


SCALING_HEAD = ["| N | shafts k N m/rad | mechdyn first run s | mechdyn warm s | CasADi warm s | "
                "mechdyn / CasADi | end error mechdyn | end error CasADi |",
                "|---|---|---|---|---|---|---|---|"]


def scaling_rows(sizes, stiffnesses, repeats):
    """One row per chain size and shaft stiffness, each in a fresh process with an empty
    cache (the kernels compiled before): mechdyn's first run (derivation, code
    generation, numba) and warm run beside CasADi's."""
    for k in stiffnesses:
        for n in sizes:
            if len(sizes) * len(stiffnesses) > 1:
                empty = {**os.environ, "MECHDYN_CACHE": tempfile.mkdtemp(prefix="mechdyn-")}
                row = subprocess.run([sys.executable, __file__, "--sizes", str(n),
                                      "--scaling", str(k), "--repeats", str(repeats)],
                                     capture_output=True, text=True, check=True, env=empty)
                print(row.stdout.strip().splitlines()[-1], flush=True)
            else:
                print(scaling_row(n, k, repeats), flush=True)


def scaling_row(n, k, repeats):
    global K
    K = k
    parents = [None] + list(range(n - 1))
    exact = reference(parents)
    ours = mechdyn_row(parents, range(n), repeats)
    peer = casadi_row(parents, repeats)
    return (f"| {n} | {k:g} | {ours['first']:.2f} | {ours['warm']:.3f} | "
            f"{peer['warm']:.3f} | {ours['warm'] / peer['warm']:.2f}x | "
            f"{np.max(np.abs(ours['end'] - exact)):.1e} | "
            f"{np.max(np.abs(peer['end'] - exact)):.1e} |")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--sizes", type=int, nargs="*", default=[100])
    parser.add_argument("--tree", type=int, default=100, help="discs in the tree (0: none)")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--scaling", type=float, nargs="*", metavar="K",
                        help="instead: the scaling table over --sizes for these shaft "
                             "stiffnesses (e.g. --scaling 1e6 1e3)")
    args = parser.parse_args(argv)
    os.environ.setdefault("MECHDYN_CACHE", tempfile.mkdtemp(prefix="mechdyn-stiff-"))
    import mechdyn.kernels  # noqa: F401  (the kernels' own numba cache, not timed)
    print(f"load average at the start: {os.getloadavg()[0]:.2f}; mechdyn's cache: "
          f"{os.environ['MECHDYN_CACHE']}")
    if args.scaling:
        print("\n".join(SCALING_HEAD), flush=True)
        scaling_rows(args.sizes, args.scaling, args.repeats)
        return
    for n in args.sizes:
        print("\n".join(["", *chain_table(n, args.repeats)]), flush=True)
    if args.tree:
        print("\n".join(["", *tree_table(args.tree, args.repeats)]), flush=True)


if __name__ == "__main__":
    main()

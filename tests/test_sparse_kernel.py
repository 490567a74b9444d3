"""The stiff step's sparse iteration matrix (issue 39): a tree of discs, which no band
fits, numbered at random, is factored in a minimum-degree order without fill, and its
solves equal numpy's dense solve (LAPACK, an independent route); a pivot the sparse
order cannot take turns the factorisation dense; and Rodas5P runs a stiff tree to the
solution of its equations written by hand."""
import random

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp

import mechdyn as md
from mechdyn.kernels import iteration
from mechdyn.kernels.sparse import SPARSE

DISCS = 63
PARENT = [None] + [(i - 1) // 2 for i in range(1, DISCS)]      # a binary tree
K, C = 1e6, 5.0


def inertias():
    return 0.01 * (1.0 + np.arange(DISCS) % 3)


def tree_jacobian(numbering):
    """[[0, I], [A, B]] of the tree on shafts k and dampers c, disc i being coordinate
    numbering[i]."""
    m = DISCS
    J = np.zeros((2 * m, 2 * m))
    inertia = inertias()
    for i in range(m):
        J[numbering[i], m + numbering[i]] = 1.0
        if PARENT[i] is not None:
            for a, b in ((i, PARENT[i]), (PARENT[i], i)):
                x, y = numbering[a], numbering[b]
                J[m + x, y] += K / inertia[a]
                J[m + x, x] -= K / inertia[a]
                J[m + x, m + y] += C / inertia[a]
                J[m + x, m + x] -= C / inertia[a]
    return J


def planned(J):
    n = J.shape[0]
    plan = np.zeros(iteration.plan_size(n), np.int64)
    order, position = np.zeros(n, np.int64), np.zeros(n, np.int64)
    W, core, pivots = np.zeros((n, n)), np.zeros((n // 2, n // 2)), np.zeros(n, np.int64)
    iteration.plan(J, plan, order, position, np.zeros(n, np.int64), core, W, False)
    return plan, order, position, W, core, pivots


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("c", [1e-1, 1e2, 1e5])
def test_a_tree_numbered_at_random_is_factored_sparse_and_solved_as_numpy_solves_it(seed, c):
    numbering = list(range(DISCS))
    random.Random(seed).shuffle(numbering)
    J = tree_jacobian(numbering)
    plan, order, position, W, core, pivots = planned(J)
    assert plan[:2].tolist() == [1, SPARSE]               # reduced, then sparse
    starts = plan[3:3 + DISCS + 1]
    assert starts[-1] - starts[0] == DISCS - 1            # U holds the edges: no fill
    b = np.random.default_rng(seed).normal(size=2 * DISCS)
    whole = c * np.eye(2 * DISCS) - J
    expected = np.linalg.solve(whole, b)
    assert iteration.factor(J, c, plan, order, W, core, pivots)
    assert plan[1] == SPARSE                              # the pivots passed the test
    iteration.solve(J, c, plan, order, position, W, pivots, b, np.zeros(2 * DISCS))
    bound = 1e-12 * np.linalg.cond(whole) * np.max(np.abs(expected))
    assert np.max(np.abs(b - expected)) <= bound


def test_a_pivot_the_sparse_order_cannot_take_turns_the_factorisation_dense():
    """A star whose hub has a zero on the diagonal and whose leaves are weakly tied:
    eliminated leaves first, the hub's pivot is far below its column (and zero without
    the leaves): the factorisation goes dense with row interchanges, and solves right."""
    n = 40
    A = np.zeros((n, n))
    A[0, 1:] = A[1:, 0] = 1.0
    A[range(1, n), range(1, n)] = 1e-9
    J = -A                                      # the matrix factored is 0 I - J = A
    plan = np.zeros(iteration.plan_size(n), np.int64)
    order, position = np.zeros(n, np.int64), np.zeros(n, np.int64)
    W, pivots = np.zeros((n, n)), np.zeros(n, np.int64)
    iteration.plan(J, plan, order, position, np.zeros(n, np.int64), np.zeros((n // 2, n // 2)),
                   W, False)
    assert plan[:2].tolist() == [0, SPARSE]
    assert iteration.factor(J, 0.0, plan, order, W, np.zeros((n // 2, n // 2)), pivots)
    assert plan[1] == -1
    x = np.arange(n, dtype=float)
    b = A @ x
    iteration.solve(J, 0.0, plan, order, position, W, pivots, b, np.zeros(n))
    assert np.max(np.abs(b - x)) <= 1e-12 * np.linalg.cond(A) * n


@pytest.mark.slow
def test_a_stiff_tree_declared_in_random_order_runs_to_the_hand_written_motion():
    numbering = list(range(DISCS))
    random.Random(7).shuffle(numbering)
    names = [f"q{i}" for i in range(DISCS)]
    declared = [names[numbering.index(k)] for k in range(DISCS)]   # coordinate k's disc
    phi = dict(zip(declared, md.coordinates(" ".join(declared))))
    q = [phi[name] for name in names]
    k, c, drive = sp.symbols("k c M", positive=True)
    mech = md.Mechanism("tree", [phi[name] for name in declared])
    for i, inertia in enumerate(inertias()):
        mech.link(f"disc {i}", J=float(inertia), angle=q[i])
        if PARENT[i] is not None:
            mech.spring(f"shaft {i}", k, stretch=q[i] - q[PARENT[i]])
            mech.damper(f"damper {i}", c, stretch=q[i] - q[PARENT[i]])
    mech.load("drive", drive, along=q[0])
    scene = md.Scene("start", initial={**{x: 0 for x in q}, **{md.speed(x): 0 for x in q}},
                     t_end=0.05, method="Rodas5P", rtol=1e-6, atol=1e-9)
    result = mech.simulate(scene, {"k": K, "c": C, "M": 5.0})
    inertia = inertias()

    def by_hand(t, y):
        x, u = y[:DISCS], y[DISCS:]
        moment = np.zeros(DISCS)
        moment[0] += 5.0
        for i in range(1, DISCS):
            shaft = K * (x[i] - x[PARENT[i]]) + C * (u[i] - u[PARENT[i]])
            moment[PARENT[i]] += shaft
            moment[i] -= shaft
        return np.concatenate([u, moment / inertia])

    reference = solve_ivp(by_hand, (0.0, 0.05), np.zeros(2 * DISCS), method="Radau",
                          rtol=1e-12, atol=1e-14).y[:, -1]
    states = result.state_names
    speeds = np.array([result[states[DISCS + states.index(n)]][-1] for n in names])
    assert set(result.stats["methods"]) == {"Rodas5P"}
    # A solve that is not exact still ends near the motion, the error control shrinking
    # the steps (a sign flipped in the back substitution: 3,620 steps): 419 when exact.
    assert result.stats["methods"]["Rodas5P"] < 1000
    assert np.max(np.abs(speeds - reference[DISCS:])) <= 1e-4 * np.max(np.abs(reference[DISCS:]))

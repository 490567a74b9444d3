"""The stiff step's banded iteration matrix (issue 39): a renumbering that finds the band
of a sparse Jacobian numbered in any order, a banded LU whose solves equal a dense
solve (numpy's LAPACK, an independent route), and a stiff chain declared in shuffled
order that Rodas5P runs to the solution of its equations written by hand."""
import math
import random

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp

import mechdyn as md
from mechdyn.kernels.band import (band_lu_factor, band_lu_solve, bandwidths, fill_band, is_narrow,
                                  order_states)


def banded_solve(J, diagonal, b):
    """Solve (diagonal I - J) x = b through the band kernels; also the band found."""
    n = J.shape[0]
    order, position = np.zeros(n, np.int64), np.zeros(n, np.int64)
    order_states(J, order, position, np.zeros(n, np.int64))
    kl, ku = bandwidths(J, position)
    ab, piv = np.zeros((n, 2 * kl + ku + 1)), np.zeros(n, np.int64)
    fill_band(J, order, diagonal, ab, kl, ku)
    if not band_lu_factor(ab, kl, ku, piv):
        return None, (kl, ku)
    x = b[order].copy()
    band_lu_solve(ab, kl, ku, piv, x)
    return x[np.argsort(order)], (kl, ku)


def chain_jacobian(n_discs, numbering):
    """The first-order Jacobian [[0, I], [-K/J, -C/J]] of a disc chain, coordinate i of the
    chain being state numbering[i] (and its speed n_discs + numbering[i])."""
    n = 2 * n_discs
    J = np.zeros((n, n))
    for i in range(n_discs):
        q, u = numbering[i], n_discs + numbering[i]
        J[q, u] = 1.0
        for j in (i - 1, i + 1):
            if 0 <= j < n_discs:
                J[u, numbering[j]] += 1e6
                J[u, q] -= 1e6
                J[u, n_discs + numbering[j]] += 5.0
                J[u, u] -= 5.0
    return J


@pytest.mark.parametrize("seed", range(12))
def test_a_shuffled_band_matrix_is_solved_as_numpy_solves_it(seed):
    """Random band matrices (bandwidths 0-4, diagonals from tiny to large so that rows
    must be interchanged) with their states shuffled."""
    rng = np.random.default_rng(seed)
    n = int(rng.integers(16, 60))
    kl, ku = (int(v) for v in rng.integers(0, 5, 2))
    W = np.zeros((n, n))
    while not np.linalg.cond(W) < 1e8:       # the reference solve must be accurate too
        band = np.zeros((n, n))
        for i in range(n):
            for j in range(max(0, i - kl), min(n, i + ku + 1)):
                band[i, j] = rng.normal() * 10.0 ** rng.integers(-3, 3)
        shuffle = rng.permutation(n)
        J = band[np.ix_(shuffle, shuffle)]
        diagonal = float(rng.choice([0.0, 1e-3, 1.0, 1e4]))
        W = diagonal * np.eye(n) - J
    b = rng.normal(size=n)
    x, (found_kl, found_ku) = banded_solve(J, diagonal, b)
    expected = np.linalg.solve(W, b)
    assert found_kl + found_ku <= n - 1
    assert np.max(np.abs(x - expected)) <= 1e-9 * np.linalg.cond(W) * np.max(np.abs(expected))


def test_a_chain_numbered_at_random_gets_the_band_of_a_chain():
    """100 discs: [q, u] order puts the speeds 100 places off the diagonal, a random
    numbering anywhere; the renumbering brings both within three places of it, which is
    worth a banded factorisation (a dense one is not)."""
    numbering = list(range(100))
    random.Random(3).shuffle(numbering)
    for order_of_discs in (list(range(100)), numbering):
        J = chain_jacobian(100, order_of_discs)
        order, position = np.zeros(200, np.int64), np.zeros(200, np.int64)
        order_states(J, order, position, np.zeros(200, np.int64))
        assert sorted(order.tolist()) == list(range(200))
        kl, ku = bandwidths(J, position)
        assert max(kl, ku) <= 3 and is_narrow(200, kl, ku)
    assert not is_narrow(200, 199, 199)


def test_a_tree_numbered_at_random_keeps_a_narrow_band():
    """A binary tree of 63 discs (a shaft to each child), numbered at random: its band
    after renumbering is at most that of the tree numbered level by level."""
    parent = [None] + [(i - 1) // 2 for i in range(1, 63)]
    rng = random.Random(5)

    def jacobian(numbering):
        J = np.zeros((126, 126))
        for i in range(63):
            J[numbering[i], 63 + numbering[i]] = 1.0
            if parent[i] is not None:
                a, b = numbering[i], numbering[parent[i]]
                for x, y in ((a, b), (b, a)):
                    J[63 + x, y] += 1.0
                    J[63 + x, x] -= 1.0
        return J

    def width(J):
        order, position = np.zeros(126, np.int64), np.zeros(126, np.int64)
        order_states(J, order, position, np.zeros(126, np.int64))
        return sum(bandwidths(J, position))

    levels = width(jacobian(list(range(63))))
    shuffled = list(range(63))
    rng.shuffle(shuffled)
    assert width(jacobian(shuffled)) <= levels


def test_a_singular_band_matrix_is_refused():
    J = chain_jacobian(10, list(range(10)))
    J[:, 3] = 0.0
    J[3, :] = 0.0
    x, _ = banded_solve(J, 0.0, np.ones(20))
    assert x is None


def test_a_stiff_chain_declared_in_shuffled_order_runs_to_the_hand_written_motion():
    """12 discs (24 states: the banded step) on stiff damped shafts, their coordinates
    declared in a random order, driven on the first disc, braked on the last; Rodas5P
    on the compiled kernels against the equations written by hand (J_i phi_i'' = moments
    of the neighbouring shafts), integrated by scipy's DOP853 at rtol 1e-12."""
    n, k, c, drive, brake = 12, 1e5, 2.0, 5.0, 0.02
    inertia = [0.01 * (1 + i % 3) for i in range(n)]
    names = [f"phi{i}" for i in range(n)]
    shuffled = names[:]
    random.Random(11).shuffle(shuffled)
    declared = dict(zip(shuffled, md.coordinates(" ".join(shuffled))))
    phi = [declared[name] for name in names]
    K, C, M, B = sp.symbols("K C M B", positive=True)
    mech = md.Mechanism("shuffled chain", [declared[name] for name in shuffled])
    for i in range(n):
        mech.link(f"disc {i}", J=inertia[i], angle=phi[i])
    for i in range(n - 1):
        mech.spring(f"shaft {i}", K, stretch=phi[i + 1] - phi[i])
        mech.damper(f"damper {i}", C, stretch=phi[i + 1] - phi[i])
    mech.load("drive", M, along=phi[0])
    mech.load("brake", -B * md.speed(phi[-1]), along=phi[-1])
    scene = md.Scene("start", initial={**{q: 0 for q in phi}, **{md.speed(q): 0 for q in phi}},
                     t_end=0.2, rtol=1e-8, atol=1e-10, method="Rodas5P", backend="compiled")
    result = mech.simulate(scene, {"K": k, "C": c, "M": drive, "B": brake})

    def by_hand(t, y):
        q, u = y[:n], y[n:]
        moment = np.zeros(n)
        for i in range(n - 1):
            shaft = k * (q[i + 1] - q[i]) + c * (u[i + 1] - u[i])
            moment[i] += shaft
            moment[i + 1] -= shaft
        moment[0] += drive
        moment[-1] -= brake * u[-1]
        return np.concatenate([u, moment / inertia])

    reference = solve_ivp(by_hand, (0.0, 0.2), np.zeros(2 * n), method="DOP853", rtol=1e-12,
                          atol=1e-14).y[:, -1]
    end = np.array([result[name][-1] for name in names])
    states = result.state_names                         # the speeds follow the positions
    speeds = np.array([result[states[n + states.index(name)]][-1] for name in names])
    assert set(result.stats["backends"]) == {"compiled"}
    assert np.max(np.abs(end - reference[:n])) <= 1e-6 * max(1.0, np.max(np.abs(reference[:n])))
    assert math.isclose(end[0], reference[0], rel_tol=1e-6)
    assert np.max(np.abs(speeds - reference[n:])) <= 1e-6 * np.max(np.abs(reference[n:]))


@pytest.mark.parametrize("seed", range(8))
def test_the_reduced_second_order_solve_equals_numpy_on_the_whole_matrix(seed):
    """J = [[0, I], [A, B]] with A and B sparse (a random graph of springs and dampers,
    numbered at random) and c from small to large: plan/factor/solve of
    mechdyn.kernels.iteration against numpy's dense solve of c I - J."""
    from mechdyn.kernels import iteration
    rng = np.random.default_rng(seed)
    m = int(rng.integers(8, 40))
    n = 2 * m
    J = np.zeros((n, n))
    J[range(m), range(m, n)] = 1.0
    for _ in range(2 * m):
        i, j = rng.integers(0, m, 2)
        J[m + i, j] += rng.normal() * 10.0 ** rng.integers(0, 6)
        J[m + i, m + j] += rng.normal() * 10.0 ** rng.integers(-2, 2)
    c = float(rng.choice([1e-2, 1.0, 1e3, 1e6]))
    plan, order, position = (np.zeros(iteration.plan_size(n), np.int64),
                             np.zeros(n, np.int64), np.zeros(n, np.int64))
    W, core, pivots = np.zeros((n, n)), np.zeros((m, m)), np.zeros(n, np.int64)
    iteration.plan(J, plan, order, position, np.zeros(n, np.int64), np.zeros((m, m)), W,
                   False)
    assert plan[0] == 1
    whole = c * np.eye(n) - J
    b = rng.normal(size=n)
    expected = np.linalg.solve(whole, b)
    assert iteration.factor(J, c, plan, order, W, core, pivots)
    iteration.solve(J, c, plan, order, position, W, pivots, b, np.zeros(n))
    assert np.max(np.abs(b - expected)) <= 1e-8 * np.linalg.cond(whole) * np.max(np.abs(expected))

"""A mass matrix of the parameters alone is factored once per parameter set, not at every
right-hand side (issue 26), on the unrolled path (<= 8 coordinates) and the banded one.

Reference, none of it from mechdyn's code: a chain of discs in relative angles
(``disc i`` turns by ``b_0 + ... + b_i``), so ``M_ij = sum_{k >= max(i, j)} J_k`` is dense
and constant; shafts ``k`` on the twists ``b_1..``, a damper ``c`` on ``b_0`` and a
drive moment 3 N m on ``b_0``: ``M a = f``, ``f_0 = 3 - c u_0``, ``f_i = -k b_i``,
solved by numpy and integrated by scipy at tight tolerances.
"""
import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp

import mechdyn as md

k, c = sp.symbols("k c", positive=True)


def relative_chain(n):
    twists = md.coordinates(" ".join(f"b{i}" for i in range(n)))
    mech = md.Mechanism("relative chain", twists)
    inertias = sp.symbols(f"J0:{n}", positive=True)
    for i in range(n):
        mech.link(f"disc {i}", J=inertias[i], angle=sum(twists[:i + 1]))
        if i:
            mech.spring(f"shaft {i}", k, stretch=twists[i])
    mech.damper("bearing", c, stretch=twists[0])
    mech.load("drive", 3, along=twists[0])
    return mech, twists


def values_for(n, scale=1.0):
    return {f"J{i}": scale * (1.0 + 0.1 * i) for i in range(n)} | {"k": 40.0, "c": 0.3}


def by_hand(n, values):
    jays = np.array([values[f"J{i}"] for i in range(n)])
    mass = np.array([[jays[max(i, j):].sum() for j in range(n)] for i in range(n)])

    def rhs(t, y):
        q, u = y[:n], y[n:]
        force = -values["k"] * q
        force[0] = 3.0 - values["c"] * u[0]
        return np.concatenate([u, np.linalg.solve(mass, force)])
    return rhs, mass


def solve_tolerance(mass, x):
    """How far two backward-stable solves of mass @ x = f may differ (the generated
    factor's and LAPACK's): each is off by up to about n eps cond(mass) |x|."""
    return 4 * len(mass) * np.finfo(float).eps * np.linalg.cond(mass) * np.abs(x).max()


def scene_for(twists, backend):
    initial = {**{b: 0.05 * i for i, b in enumerate(twists)},
               **{md.speed(b): 0.0 for b in twists}}
    return md.Scene("run", initial=initial, t_end=1.0, rtol=1e-10, atol=1e-12,
                    backend=backend)


@pytest.mark.parametrize("n", [4, 10])        # unrolled factor, banded (dense) factor
def test_a_constant_mass_matrix_is_factored_once_and_solved_as_written_by_hand(n):
    mech, twists = relative_chain(n)
    compiled = mech.compile(scene_for(twists, "scipy"))
    assert "mass_factor" in compiled.meta              # hoisted out of rhs and jac
    assert "mass_factor" not in compiled.source.split("def rhs(")[1].split("\ndef ")[0]
    for scale in (1.0, 2.5):                          # a factor per parameter set
        values = values_for(n, scale)
        rhs, mass = by_hand(n, values)
        p = compiled.parameter_vector(values)
        damping = np.zeros((n, n))
        damping[0, 0] = -values["c"]
        stiffness = -values["k"] * np.diag([0.0] + [1.0] * (n - 1))
        for y in np.random.default_rng(n).normal(size=(3, 2 * n)):
            expected = rhs(0.3, y)
            assert np.allclose(compiled.rhs(0.3, y, p), expected, rtol=0,
                               atol=solve_tolerance(mass, expected[n:]))
            jac = compiled.jac(0.3, y, p)
            for got, right in ((jac[n:, :n], stiffness), (jac[n:, n:], damping)):
                expected = np.linalg.solve(mass, right)
                assert np.allclose(got, expected, rtol=0, atol=solve_tolerance(mass, expected))


@pytest.mark.parametrize("backend", ["scipy", "compiled"])
@pytest.mark.parametrize("n", [4, 10])
def test_a_run_with_a_constant_mass_matrix_reaches_the_hand_written_solution(n, backend):
    mech, twists = relative_chain(n)
    scene = scene_for(twists, backend)
    y0 = np.array([0.05 * i for i in range(n)] + [0.0] * n)
    for scale in (1.0, 2.5):                          # the same compiled scene, two sets
        values = values_for(n, scale)
        result = mech.simulate(scene, values)
        assert set(result.stats["backends"]) == {backend}
        reference = solve_ivp(by_hand(n, values)[0], (0.0, 1.0), y0, method="DOP853",
                              rtol=1e-12, atol=1e-13)
        final = [result.final(b) for b in twists] + [result.final(md.speed(b)) for b in twists]
        assert np.allclose(final, reference.y[:, -1], rtol=0, atol=1e-8)


# --------------------------------------------- the Jacobian's sparsity for scipy's stiff methods
def disc_chain(n):
    angles = md.coordinates(" ".join(f"a{i}" for i in range(n)))
    mech = md.Mechanism("disc chain", angles)
    for i, angle in enumerate(angles):
        mech.link(f"disc {i}", J=sp.Symbol("J", positive=True), angle=angle)
    for i in range(n - 1):
        mech.spring(f"shaft {i}", k, stretch=angles[i + 1] - angles[i])
    return mech, angles


@pytest.mark.parametrize("method", ["Radau", "BDF"])
def test_a_large_chain_runs_with_a_sparse_jacobian_on_scipy_to_its_mode_closed_form(method):
    """Equal discs J on shafts k started in mode m: ``q_i = A v_i cos(w t)``,
    ``v_i = cos(pi m (i + 1/2) / n)``, ``w = 2 sqrt(k/J) sin(pi m / (2n))``."""
    n, mode, amplitude, values = 12, 2, 0.01, {"J": 0.5, "k": 40.0}
    mech, angles = disc_chain(n)
    shape = [np.cos(np.pi * mode * (i + 0.5) / n) for i in range(n)]
    omega = 2 * np.sqrt(values["k"] / values["J"]) * np.sin(np.pi * mode / (2 * n))
    scene = md.Scene("mode", initial={**{a: amplitude * v for a, v in zip(angles, shape)},
                                      **{md.speed(a): 0 for a in angles}},
                     t_end=1.0, rtol=1e-10, atol=1e-13, backend="scipy", method=method)
    compiled = mech.compile(scene)
    p = compiled.parameter_vector(values)
    y = np.random.default_rng(5).normal(size=2 * n)
    sparse = compiled.sparse_jac(0.0, y, p)
    assert sparse.nnz == n + 3 * n - 2                 # identity, then a tridiagonal block
    assert np.array_equal(sparse.toarray(), compiled.jac(0.0, y, p))
    result = mech.simulate(scene, values)
    assert result.stats["nlu"] > 0                     # the implicit method factored it
    for a, v in zip(angles, shape):
        assert result.final(a) == pytest.approx(amplitude * v * np.cos(omega), abs=1e-8)


@pytest.mark.parametrize("backend", ["scipy", "compiled"])
def test_a_brake_sliding_on_a_constant_mass_matrix_gives_the_hand_written_motion(backend):
    """Two discs in relative angles (``M = [[J0 + J1, J1], [J1, J1]]``), a shaft k on the
    twist, a brake of 2 N m on disc 0 spinning forward all along: ``f = [-2, -k b1]``."""
    b0, b1 = md.coordinates("b0 b1")
    mech = md.Mechanism("braked pair", [b0, b1])
    mech.link("disc 0", J=sp.Symbol("J0", positive=True), angle=b0)
    mech.link("disc 1", J=sp.Symbol("J1", positive=True), angle=b0 + b1)
    mech.spring("shaft", k, stretch=b1)
    mech.friction("brake", 2, along=b0)
    values = {"J0": 1.0, "J1": 0.5, "k": 30.0}
    scene = md.Scene("braking", initial={b0: 0, b1: 0.05, md.speed(b0): 5, md.speed(b1): 0},
                     t_end=1.0, rtol=1e-10, atol=1e-12, backend=backend)
    result = mech.simulate(scene, values)
    assert set(result.stats["backends"]) == {backend}      # compiled: the mode modules
    mass = np.array([[1.5, 0.5], [0.5, 0.5]])
    reference = solve_ivp(lambda t, y: np.concatenate([y[2:], np.linalg.solve(
        mass, [-2.0, -values["k"] * y[1]])]), (0.0, 1.0), [0.0, 0.05, 5.0, 0.0],
        method="DOP853", rtol=1e-12, atol=1e-13, dense_output=True)
    assert np.all(reference.sol(np.linspace(0, 1, 201))[2] > 1.0)     # disc 0 slides forward
    final = [result.final(b0), result.final(b1), result.final(md.speed(b0)),
             result.final(md.speed(b1))]
    assert np.allclose(final, reference.y[:, -1], rtol=0, atol=1e-8)

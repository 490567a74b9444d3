"""Models beyond the unrolled solve (more than 8 coordinates), issue 26: the mass matrix is
evaluated in the generated code and factored numerically (banded, dense or diagonal).

References, none of them from mechdyn's code:
- a free chain of equal discs started in one of its modes: ``q_i(t) = A v_i cos(w t)``
  with ``v_i = cos(pi m (i + 1/2) / N)`` and ``w = 2 sqrt(k/J) sin(pi m / (2N))``;
- a chain whose neighbours drive a slider at ``x = r (sin a_i + sin a_j)`` (a banded mass
  matrix that depends on the angles), its equations written by hand below (Lagrange's
  equations of ``T = sum J u_i^2/2 + m v^2/2``, ``v = r (cos a_i u_i + cos a_j u_j)``)
  and integrated by scipy at tight tolerances; its Jacobian by central differences;
- a chain in relative angles (a dense constant mass matrix ``M_ij = sum_{k >= max(i,j)}
  J_k``), written by hand.
"""
import math

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp

import mechdyn as md
from mechdyn.simulate.methods import choose_method

N = 12
J, k, m, r, c = sp.symbols("J k m r c", positive=True)
VALUES = {"J": 0.5, "k": 40.0, "m": 2.0, "r": 0.3, "c": 0.1}


def solve_tolerance(mass, x):
    """How far two backward-stable solves of mass @ x = f may differ (the generated
    factor's and LAPACK's): each is off by up to about n eps cond(mass) |x|."""
    return 4 * len(mass) * np.finfo(float).eps * np.linalg.cond(mass) * np.abs(x).max()


def disc_chain(n):
    angles = md.coordinates(" ".join(f"a{i}" for i in range(n)))
    mech = md.Mechanism("disc chain", angles)
    for i, angle in enumerate(angles):
        mech.link(f"disc {i}", J=J, angle=angle)
    for i in range(n - 1):
        mech.spring(f"shaft {i}", k, stretch=angles[i + 1] - angles[i])
    return mech, angles


def slider_chain():
    mech, angles = disc_chain(N)
    for i in range(N - 1):
        mech.link(f"slider {i}", m=m, x=r * (sp.sin(angles[i]) + sp.sin(angles[i + 1])))
    mech.damper("bearing", c, stretch=angles[0])
    mech.load("drive", 2 * sp.cos(md.t), along=angles[0])
    return mech, angles


def slider_chain_by_hand(t, y):
    q, u = y[:N], y[N:]
    mass, f = np.diag(np.full(N, VALUES["J"])), np.zeros(N)
    f[0] += 2 * math.cos(t) - VALUES["c"] * u[0]
    mr2 = VALUES["m"] * VALUES["r"] ** 2
    for i in range(N - 1):
        j = i + 1
        ci, cj = math.cos(q[i]), math.cos(q[j])
        mass[np.ix_([i, j], [i, j])] += mr2 * np.outer([ci, cj], [ci, cj])
        centripetal = math.sin(q[i]) * u[i] ** 2 + math.sin(q[j]) * u[j] ** 2
        f[[i, j]] += mr2 * centripetal * np.array([ci, cj])
        twist = VALUES["k"] * (q[j] - q[i])
        f[i] += twist
        f[j] -= twist
    return np.concatenate([u, np.linalg.solve(mass, f)])


def slider_scene(angles, backend, method="auto"):
    initial = {**{a: 0.1 * i for i, a in enumerate(angles)},
               **{md.speed(a): 0.0 for a in angles}}
    return md.Scene("run", initial=initial, t_end=2.0, rtol=1e-10, atol=1e-12,
                    backend=backend, method=method)


STATES = np.random.default_rng(26).normal(size=(3, 2 * N))


def test_a_banded_angle_dependent_mass_matrix_gives_the_hand_written_motion():
    mech, angles = slider_chain()
    compiled = mech.compile(slider_scene(angles, "scipy"))
    p = compiled.parameter_vector(VALUES)
    for y in STATES:
        expected = slider_chain_by_hand(0.7, y)
        assert np.allclose(compiled.rhs(0.7, y, p), expected, rtol=1e-12, atol=1e-12)
        step = 1e-6
        columns = [(slider_chain_by_hand(0.7, y + step * e) - slider_chain_by_hand(0.7, y - step * e))
                   / (2 * step) for e in np.eye(2 * N)]
        assert np.allclose(compiled.jac(0.7, y, p), np.array(columns).T, rtol=1e-6, atol=1e-6)


def run_against_hand(backend, method="auto"):
    mech, angles = slider_chain()
    result = mech.simulate(slider_scene(angles, backend, method), VALUES)
    y0 = np.array([0.1 * i for i in range(N)] + [0.0] * N)
    reference = solve_ivp(slider_chain_by_hand, (0.0, 2.0), y0, method="DOP853",
                          rtol=1e-12, atol=1e-13)
    final = [result.final(a) for a in angles] + [result.final(md.speed(a)) for a in angles]
    assert np.allclose(final, reference.y[:, -1], rtol=0, atol=1e-8)
    return result


def test_a_twelve_coordinate_chain_runs_to_the_hand_written_solution():
    run_against_hand("scipy")


@pytest.mark.slow
@pytest.mark.parametrize("method", ["auto", "Rodas5P"])     # Rodas5P: the compiled Jacobian
def test_the_compiled_banded_solve_runs_to_the_hand_written_solution(method):
    result = run_against_hand("compiled", method)
    assert set(result.stats["backends"]) == {"compiled"}


def test_a_free_disc_chain_started_in_a_mode_swings_in_that_mode_compiled():
    mech, angles = disc_chain(N)
    mode, amplitude = 3, 0.01
    shape = [math.cos(math.pi * mode * (i + 0.5) / N) for i in range(N)]
    omega = 2 * math.sqrt(VALUES["k"] / VALUES["J"]) * math.sin(math.pi * mode / (2 * N))
    scene = md.Scene("mode", initial={**{a: amplitude * v for a, v in zip(angles, shape)},
                                      **{md.speed(a): 0 for a in angles}},
                     t_end=1.0, rtol=1e-10, atol=1e-13, backend="compiled")
    result = mech.simulate(scene, {"J": VALUES["J"], "k": VALUES["k"]})
    assert set(result.stats["backends"]) == {"compiled"}
    for a, v in zip(angles, shape):
        assert result.final(a) == pytest.approx(amplitude * v * math.cos(omega), abs=1e-10)
        assert result.final(md.speed(a)) == pytest.approx(
            -amplitude * v * omega * math.sin(omega), abs=1e-9)


def test_a_dense_mass_matrix_from_relative_angles_is_solved_as_written_by_hand():
    n = 10
    twists = md.coordinates(" ".join(f"b{i}" for i in range(n)))
    mech = md.Mechanism("relative chain", twists)
    inertias = sp.symbols(f"J0:{n}", positive=True)
    for i in range(n):
        mech.link(f"disc {i}", J=inertias[i], angle=sum(twists[:i + 1]))
        if i:
            mech.spring(f"shaft {i}", k, stretch=twists[i])
    mech.load("drive", 3, along=twists[0])
    compiled = mech.compile(md.Scene("s", initial={**{b: 0 for b in twists},
                                                  **{md.speed(b): 0 for b in twists}},
                                     t_end=1))
    values = {f"J{i}": 1.0 + 0.1 * i for i in range(n)} | {"k": 40.0}
    p = compiled.parameter_vector(values)
    jays = np.array([values[f"J{i}"] for i in range(n)])
    mass = np.array([[jays[max(i, j):].sum() for j in range(n)] for i in range(n)])
    for y in np.random.default_rng(7).normal(size=(3, 2 * n)):
        force = -values["k"] * y[:n]
        force[0] = 3.0
        expected = np.linalg.solve(mass, force)
        assert np.allclose(compiled.rhs(0.0, y, p)[n:], expected, rtol=0,
                           atol=solve_tolerance(mass, expected))
        expected = np.linalg.solve(mass, -values["k"] * np.diag([0] + [1] * (n - 1)))
        assert np.allclose(compiled.jac(0.0, y, p)[n:, :n], expected, rtol=0,
                           atol=solve_tolerance(mass, expected))


def test_a_mass_matrix_that_is_not_positive_definite_gives_nan_not_numbers():
    mech, angles = slider_chain()
    compiled = mech.compile(slider_scene(angles, "scipy"))
    p = compiled.parameter_vector(VALUES)
    p[compiled.param_names.index("J")] = -5.0       # bypasses the parameter checks
    assert all(math.isnan(v) for v in compiled.rhs(0.0, STATES[0], p)[N:])


@pytest.mark.parametrize("damping, stiff", [(0.01, False), (1000.0, True)])
def test_a_large_chain_is_judged_stiff_by_its_damping_as_the_eigenvalues_say(damping, stiff):
    """40 discs (80 states: the spectrum is estimated, not computed in full). Equal discs
    J = 0.5, shafts k = 40 and dampers c between neighbours: the fastest damping rate is
    max eig(M^-1 C) = 4 c / J cos^2(pi / 80) (c = 1000: 8000 1/s), the slowest scale of
    the free chain (a rigid mode) is clamped to [1/T, 1] = 1 1/s, so the ratio is 8000 >
    2000: stiff; with c = 0.01 it is 0.08: not stiff."""
    n = 40
    mech, angles = disc_chain(n)
    for i in range(n - 1):
        mech.damper(f"damper {i}", c, stretch=angles[i + 1] - angles[i])
    mech.load("drive", 1, along=angles[0])
    scene = md.Scene("start", initial={**{a: 0 for a in angles},
                                       **{md.speed(a): 0 for a in angles}},
                     t_end=1.0, rtol=1e-6, backend="scipy")
    compiled = mech.compile(scene)
    p = compiled.parameter_vector({"J": VALUES["J"], "k": VALUES["k"], "c": damping})
    method, why = choose_method(compiled, p, [0.0] * (2 * n), 0.0, 1.0, 1e-6)
    assert (method == "Radau") == stiff, why
    if stiff:
        assert float(why.split()[2]) == pytest.approx(
            4 * damping / VALUES["J"] * math.cos(math.pi / (2 * n)) ** 2, rel=0.05)


@pytest.mark.parametrize("backend", ["scipy", "compiled"])
def test_a_constraint_among_more_than_eight_coordinates_moves_as_its_closed_form(backend):
    """Nine free discs (beyond the unrolled solve: the constrained accelerations are
    solved numerically, compile/loop_numeric.py), the first two tied by phi_0 = phi_1 and
    driven by M on the first: they turn together, phi = M t^2 / (2 (J_0 + J_1)), the rest
    stay at rest."""
    n, drive = 9, 3.0
    angles = md.coordinates(" ".join(f"b{i}" for i in range(n)))
    mech = md.Mechanism("tied discs", angles, independent=[angles[0], *angles[2:]])
    inertia = [0.5 + 0.25 * i for i in range(n)]
    for i, angle in enumerate(angles):
        mech.link(f"disc {i}", J=inertia[i], angle=angle)
    mech.constraint("tie", angles[0] - angles[1])
    mech.load("drive", drive, along=angles[0])
    scene = md.Scene("tied", initial={**{a: 0 for a in angles},
                                      **{md.speed(a): 0 for a in angles}},
                     t_end=2.0, rtol=1e-10, atol=1e-12, backend=backend)
    result = mech.simulate(scene, {})
    expected = drive * 2.0 ** 2 / (2 * (inertia[0] + inertia[1]))
    assert result.final(angles[0]) == pytest.approx(expected, rel=1e-8)
    assert result.final(angles[1]) == pytest.approx(expected, rel=1e-8)
    assert all(abs(result.final(a)) < 1e-9 for a in angles[2:])

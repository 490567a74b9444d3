"""Property tests on random mechanisms, through simulation: the energy balance holds, the
compiled equations equal sympy's exact evaluation, and closed forms equal simulation."""
import numpy as np
import pytest
import sympy as sp
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import mechdyn as md

phi, psi = md.coordinates("phi psi")
SETTINGS = settings(max_examples=6, deadline=None,
                    suppress_health_check=[HealthCheck.too_slow])
coefficient = st.floats(0.2, 2.0)


@st.composite
def one_dof_machine(draw):
    """A crank (J) driving a slider on a random smooth path, with a spring, a damper and
    a constant moment: scleronomic, so T + V changes by the work of moment and damper."""
    a, b, c = draw(coefficient), draw(coefficient), draw(coefficient)
    mech = md.Mechanism("random machine", [phi])
    mech.link("crank", J=draw(st.floats(0.05, 1.0)), angle=phi)
    mech.link("slider", m=draw(coefficient), x=a * sp.cos(phi) + b * sp.sin(2 * phi) / 4,
              y=c * sp.sin(phi) ** 2 / 2)
    mech.spring("spring", draw(st.floats(0.5, 20.0)), stretch=a * sp.sin(phi))
    mech.damper("damper", draw(st.floats(0.0, 0.5)), stretch=b * sp.cos(phi))
    mech.load("moment", draw(st.floats(-3.0, 3.0)), along=phi)
    mech.gravity(9.81)
    return mech, draw(st.floats(-5.0, 5.0))


def _work(res, labels):
    nodes, weights = np.polynomial.legendre.leggauss(8)
    total = 0.0
    for a, b in zip(res.t[:-1], res.t[1:]):
        times = (a + b) / 2 + (b - a) / 2 * nodes
        values = res.outputs_at(times)
        total += (b - a) / 2 * sum(weights @ values[label] for label in labels)
    return total


@SETTINGS
@given(one_dof_machine())
def test_energy_changes_by_the_work_of_the_non_conservative_loads(machine):
    mech, speed = machine
    labels = ["power:moment", "power:damper"]
    scene = md.Scene("run", initial={phi: 0.3, md.speed(phi): speed}, t_end=1.0,
                     outputs=labels, rtol=1e-10, atol=1e-12)
    res = mech.simulate(scene, {})
    kinetic, potential = res.energy()
    change = kinetic[-1] + potential[-1] - kinetic[0] - potential[0]
    scale = max(np.abs(kinetic).max(), np.abs(potential).max(), 1.0)
    assert change == pytest.approx(_work(res, labels), abs=1e-7 * scale)


def magnitude(expr, subs):
    """``expr`` at ``subs`` with every sum replaced by the sum of its terms' sizes."""
    if isinstance(expr, sp.Add):
        return sum(magnitude(a, subs) for a in expr.args)
    if isinstance(expr, sp.Mul):
        return sp.Mul(*(magnitude(a, subs) for a in expr.args))
    if isinstance(expr, sp.Pow) and expr.exp.is_Integer and expr.exp > 0:
        return magnitude(expr.base, subs) ** expr.exp
    return abs(expr.evalf(30, subs=subs))


@SETTINGS
@given(st.lists(coefficient, min_size=6, max_size=6),
       st.lists(st.floats(-2.0, 2.0), min_size=4, max_size=4))
def test_compiled_two_dof_equations_equal_exact_evaluation(c, state):
    mech = md.Mechanism("random pair", [phi, psi])
    mech.link("arm", m=c[0], J=c[1], x=sp.cos(phi), y=sp.sin(phi))
    mech.link("slider", m=c[2], x=sp.cos(phi) + c[3] * psi, y=psi ** 2 / 2)
    mech.spring("spring", c[4], stretch=psi - sp.sin(phi))
    mech.damper("damper", c[5], stretch=psi)
    mech.load("moment", 1.0, along=phi)
    scene = md.Scene("run", initial={phi: 0, psi: 0, md.speed(phi): 0, md.speed(psi): 0},
                     t_end=1)
    compiled = mech.compile(scene)
    eqs = mech.equations(scene)
    subs = dict(zip(list(eqs.q) + list(eqs.u), [sp.Float(v, 30) for v in state]))
    mass = eqs.mass_matrix.evalf(30, subs=subs)
    forcing = eqs.forcing.evalf(30, subs=subs)
    exact = [float(v) for v in list(mass.LUsolve(forcing))]
    got = compiled.rhs(0.0, np.array(state), compiled.parameter_vector({}))
    assert got[:2] == pytest.approx(state[2:], rel=1e-14)
    # In doubles each operation of the forcing rounds by eps of its operands' size
    # (magnitude: every sum taken of absolute values) and M a = f is solved: a is off by
    # about eps |M^-1| (|M| |a| + magnitude of f) per operation in a chain: 64 of that
    # (measured up to 2.6).
    size = max(float(magnitude(f, subs)) for f in eqs.forcing)
    numeric = np.array(mass.tolist(), dtype=float)
    bound = 64 * np.finfo(float).eps * np.linalg.norm(np.linalg.inv(numeric), np.inf) * (
        np.linalg.norm(numeric, np.inf) * np.abs(exact).max() + size)
    assert got[2:] == pytest.approx(exact, rel=0, abs=bound)


@SETTINGS
@given(st.floats(0.1, 2.0), st.floats(-2.0, 2.0), st.floats(0.0, 1.0), st.floats(-3, 3))
def test_closed_form_of_a_polynomial_drive_equals_simulation(inertia, m0, m1, omega0):
    """Case 2 with M(t) = m0 + m1 t: the closed form and the integration agree."""
    mech = md.Mechanism("flywheel", [phi])
    mech.link("flywheel", J=inertia, angle=phi)
    mech.load("drive", m0 + m1 * md.t, along=phi)
    scene = md.Scene("run", initial={phi: 0, md.speed(phi): omega0}, t_end=2.0,
                     rtol=1e-11, atol=1e-12)
    solution = md.closed_form(mech, scene, {})
    res = mech.simulate(scene, {})
    times = np.linspace(0, 2, 9)
    assert np.allclose(solution.function("phi(t)")(times), res.at(times, phi),
                       rtol=1e-8, atol=1e-10)
    # phi(t) = omega0 t + (m0 t^2/2 + m1 t^3/6) / J, at t = 2
    by_hand = omega0 * 2 + (m0 * 2 + m1 * 4 / 3) / inertia
    assert res.final(phi) == pytest.approx(by_hand, rel=1e-8, abs=1e-10)


def test_random_machine_strategy_really_varies():
    """The property tests above see different machines (guards a constant strategy)."""
    seen = set()

    @settings(max_examples=5, deadline=None)
    @given(one_dof_machine())
    def collect(machine):
        seen.add(str(machine[0].reduced_inertia()))
    collect()
    assert len(seen) > 1


def _finite_difference_jacobian(compiled, t, y, p):
    """Central differences of the compiled right-hand side, column by column."""
    y = np.asarray(y, dtype=float)
    columns = []
    for j in range(len(y)):
        h = 1e-6 * max(1.0, abs(y[j]))
        up, down = y.copy(), y.copy()
        up[j] += h
        down[j] -= h
        columns.append((np.array(compiled.rhs(t, up, p)) - np.array(compiled.rhs(t, down, p)))
                       / (2 * h))
    return np.array(columns).T


def _random_pair(c):
    mech = md.Mechanism("random pair", [phi, psi])
    mech.link("arm", m=c[0], J=c[1], x=sp.cos(phi), y=sp.sin(phi))
    mech.link("slider", m=c[2], x=sp.cos(phi) + c[3] * psi, y=psi ** 2 / 2)
    mech.spring("spring", c[4], stretch=psi - sp.sin(phi))
    mech.damper("damper", c[5], stretch=psi * sp.cos(phi))
    mech.load("moment", 1.0 + md.speed(phi) ** 2 / 4, along=phi)
    mech.friction("brake", c[0] * (1 + psi ** 2), along=psi)
    return mech


@SETTINGS
@given(one_dof_machine(), st.lists(st.floats(-2.0, 2.0), min_size=2, max_size=2))
def test_one_dof_jacobian_equals_finite_differences_of_the_right_hand_side(machine, state):
    # One coordinate: M depends on phi, so the term M_q a of da/dq is exercised.
    mech, _ = machine
    compiled = mech.compile(md.Scene("run", initial={phi: 0, md.speed(phi): 0}, t_end=1))
    p = compiled.parameter_vector({})
    expected = _finite_difference_jacobian(compiled, 0.0, state, p)
    scale = max(1.0, np.abs(expected).max())
    assert np.allclose(compiled.jac(0.0, np.array(state), p), expected, rtol=1e-6,
                       atol=1e-6 * scale)


@SETTINGS
@given(st.lists(coefficient, min_size=6, max_size=6),
       st.lists(st.floats(-2.0, 2.0), min_size=4, max_size=4), st.sampled_from([-1.0, 1.0]))
def test_two_dof_jacobian_with_friction_equals_finite_differences(c, state, sign):
    # Friction sliding either way: its magnitude depends on psi, its sign is a parameter.
    mech = _random_pair(c)
    compiled = mech.compile(md.Scene("run", initial={phi: 0, psi: 0, md.speed(phi): 0,
                                                     md.speed(psi): 0}, t_end=1))
    p = compiled.parameter_vector({}, [sign])
    expected = _finite_difference_jacobian(compiled, 0.0, state, p)
    scale = max(1.0, np.abs(expected).max())
    assert np.allclose(compiled.jac(0.0, np.array(state), p), expected, rtol=1e-6,
                       atol=1e-6 * scale)

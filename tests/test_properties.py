"""Property tests over random mechanisms (hypothesis).

Random links with random masses and inertias whose positions are random smooth
expressions (sin, cos, polynomials, random coefficients) of one or two coordinates, and
random loads, springs, dampers, friction and gravity. Two properties:

(a) the derived reduced inertia (1 DOF) / mass matrix (2 DOF) equals
    ``sum m (dx/dq_i dx/dq_j + dy/dq_i dy/dq_j) + J dangle/dq_i dangle/dq_j`` with the
    gradients taken by central finite differences of the numeric positions;
(b) along any motion, ``d/dt (T + V)`` equals the power of the non-conservative
    elements: with random q, u, t the accelerations come from the derived
    ``M a = f`` (solved numerically), ``T + V`` is written here from the positions and
    differentiated along ``(u, a)`` by central differences.
"""
import numpy as np
import pytest
import sympy as sp
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import mechdyn as md

SETTINGS = settings(max_examples=15, deadline=None,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])

COORDS = {1: (md.coordinate("phi"),), 2: md.coordinates("phi_1 phi_2")}


def bases(qs):
    """Smooth functions of the coordinates, none of them constant."""
    out = []
    for q in qs:
        out += [q, q**2 / 2, sp.sin(q), sp.cos(q), sp.sin(2 * q), q * sp.cos(q), q**3 / 6]
    if len(qs) == 2:
        a, b = qs
        out += [sp.sin(a + b), sp.cos(a - b), a * b, a * sp.sin(b), sp.cos(a) * sp.cos(b)]
    return out


coefficients = st.integers(-12, 12).filter(bool).map(lambda n: sp.Rational(n, 4))
positive = st.integers(1, 20).map(lambda n: sp.Rational(n, 4))


@st.composite
def smooth(draw, qs, allow_zero=True):
    """A random smooth expression of the coordinates (never constant unless zero)."""
    functions = bases(qs)
    if allow_zero and draw(st.booleans()) and draw(st.booleans()):
        return sp.S.Zero
    picks = draw(st.lists(st.integers(0, len(functions) - 1), min_size=1, max_size=3,
                          unique=True))
    expr = sum((draw(coefficients) * functions[i] for i in picks), sp.S.Zero)
    return expr + draw(st.sampled_from([0, 0, sp.Rational(1, 2), -1]))


@st.composite
def mechanisms(draw, dof, with_loads):
    """A random mechanism and the plain description the test reasons from."""
    qs = COORDS[dof]
    mech = md.Mechanism(f"random {dof}-DOF", list(qs))
    links = []
    # every coordinate turns a link of its own, so the mass matrix is positive definite
    for i, q in enumerate(qs):
        links.append((f"base {i}", draw(positive), draw(positive), 0, 0, q))
    for i in range(draw(st.integers(1, 3))):
        m = draw(st.one_of(st.just(0), positive))
        J = draw(st.one_of(st.just(0), positive))
        x, y, angle = draw(smooth(qs)), draw(smooth(qs)), draw(smooth(qs))
        links.append((f"link {i}", m, J, x, y, angle))
    for name, m, J, x, y, angle in links:
        mech.link(name, m=m, J=J, x=x, y=y, angle=angle)
    extra = {"loads": [], "springs": [], "dampers": [], "frictions": [], "g": None}
    if with_loads:
        for i in range(draw(st.integers(0, 2))):
            along = draw(smooth(qs, allow_zero=False))
            value = draw(smooth(qs))
            value += draw(coefficients) * md.speed(draw(st.sampled_from(qs)))
            value += draw(st.sampled_from([0, 1, -2])) * sp.sin(md.t)
            eta = draw(st.sampled_from([None, None, sp.Rational(9, 10), sp.Rational(1, 2)]))
            mech.load(f"load {i}", value, along=along, efficiency=eta)
            extra["loads"].append((f"load {i}", value, along, eta))
        for i in range(draw(st.integers(0, 2))):
            k, stretch = draw(positive), draw(smooth(qs, allow_zero=False))
            mech.spring(f"spring {i}", k, stretch=stretch)
            extra["springs"].append((k, stretch))
        for i in range(draw(st.integers(0, 2))):
            c, stretch = draw(positive), draw(smooth(qs, allow_zero=False))
            mech.damper(f"damper {i}", c, stretch=stretch)
            extra["dampers"].append((f"damper {i}", c, stretch))
        if draw(st.booleans()):
            magnitude, along = draw(positive), draw(smooth(qs, allow_zero=False))
            mech.friction("brake", magnitude, along=along)
            extra["frictions"].append(("brake", magnitude, along))
        if draw(st.booleans()):
            extra["g"] = draw(positive)
            mech.gravity(extra["g"])
    return mech, links, extra


def plain_symbols(qs):
    q = [md.plain(c) for c in qs]
    u = [md.plain(md.speed(c)) for c in qs]
    return q, u


def to_plain(expr, qs):
    """The test's own substitution of coordinates and speeds by plain symbols."""
    expr = sp.sympify(expr)
    expr = expr.xreplace({md.speed(c): md.plain(md.speed(c)) for c in qs})
    return expr.xreplace({c: md.plain(c) for c in qs})


def numeric(expr, args):
    return sp.lambdify(args, expr, modules="numpy")


def fd_gradient(function, point, h=1e-5):
    """Central-difference gradient of a scalar function of a vector."""
    point = np.asarray(point, float)
    grad = np.empty(len(point))
    for i in range(len(point)):
        step = np.zeros(len(point))
        step[i] = h
        grad[i] = (function(*(point + step)) - function(*(point - step))) / (2 * h)
    return grad


def mass_matrix_from_positions(links, qs, point):
    """sum m (grad x grad x' + grad y grad y') + J grad angle grad angle' by finite
    differences of the lambdified positions."""
    q, _ = plain_symbols(qs)
    n = len(qs)
    total = np.zeros((n, n))
    for _, m, J, x, y, angle in links:
        for weight, position in ((m, x), (m, y), (J, angle)):
            g = fd_gradient(numeric(to_plain(position, qs), q), point)
            total += float(weight) * np.outer(g, g)
    return total


configurations = st.integers(0, 2**32 - 1)


@pytest.mark.parametrize("dof", [1, 2])
@SETTINGS
@given(data=st.data())
def test_mass_matrix_equals_finite_differences_of_positions(dof, data):
    mech, links, _ = data.draw(mechanisms(dof, with_loads=False))
    qs = COORDS[dof]
    q, _ = plain_symbols(qs)
    eqs = mech.equations()
    derived = numeric(eqs.mass_matrix, q)
    rng = np.random.default_rng(data.draw(configurations))
    for point in rng.uniform(-3, 3, size=(3, dof)):
        expected = mass_matrix_from_positions(links, qs, point)
        got = np.asarray(derived(*point), float).reshape(dof, dof)
        assert np.allclose(got, expected, rtol=1e-6, atol=1e-6 * (1 + np.abs(expected).max()))
    if dof == 1:
        inertia = numeric(mech.reduced_inertia(), q)
        for point in rng.uniform(-3, 3, size=(3, 1)):
            expected = mass_matrix_from_positions(links, qs, point)[0, 0]
            assert float(inertia(*point)) == pytest.approx(expected, rel=1e-6, abs=1e-6)


def energy_and_power(links, extra, qs):
    """T + V and the power of the non-conservative elements, written from the
    declaration (not from the derivation): plain expressions of q, u and t."""
    q, u = plain_symbols(qs)

    def rate(expr):
        expr = to_plain(expr, qs)
        return sum((sp.diff(expr, qi) * ui for qi, ui in zip(q, u)), sp.S.Zero)

    kinetic = sum((m * (rate(x) ** 2 + rate(y) ** 2) / 2 + J * rate(angle) ** 2 / 2
                   for _, m, J, x, y, angle in links), sp.S.Zero)
    potential = sum((k * to_plain(s, qs) ** 2 / 2 for k, s in extra["springs"]), sp.S.Zero)
    if extra["g"] is not None:
        potential += sum((m * extra["g"] * to_plain(y, qs) for _, m, _, _, y, _ in links),
                         sp.S.Zero)
    powers = {}
    for name, value, along, eta in extra["loads"]:
        power = to_plain(value, qs) * rate(along)
        if eta is not None:   # feeding power back loses (1 - eta), drawing it costs 1/eta
            power = sp.Piecewise((power * eta, power > 0), (power / eta, True))
        powers[name] = power
    for name, c, stretch in extra["dampers"]:
        powers[name] = -c * rate(stretch) ** 2
    for name, magnitude, along in extra["frictions"]:
        powers[name] = -magnitude * sp.Abs(rate(along))
    return kinetic + potential, powers


@pytest.mark.parametrize("dof", [1, 2])
@SETTINGS
@given(data=st.data())
def test_energy_rate_equals_power_of_nonconservative_elements(dof, data):
    mech, links, extra = data.draw(mechanisms(dof, with_loads=True))
    qs = COORDS[dof]
    q, u = plain_symbols(qs)
    t = md.t
    eqs = mech.equations()
    mass = numeric(eqs.mass_matrix, q)
    forcing = numeric(eqs.forcing, q + u + [t])
    energy_expr, powers = energy_and_power(links, extra, qs)
    energy = numeric(energy_expr, q + u)
    args = q + u + [t]
    nonconservative = list(powers)
    derived_powers = {name: numeric(eqs.powers[name], args) for name in nonconservative}
    own_powers = {name: numeric(p, args) for name, p in powers.items()}
    # springs and gravity are conservative: their work is in V, not in the power
    conservative = [n for n in eqs.powers if n not in powers]
    assert all(n.startswith("spring") or n == "gravity" for n in conservative)

    rng = np.random.default_rng(data.draw(configurations))
    for _ in range(3):
        qv, uv = rng.uniform(-2, 2, dof), rng.uniform(-2, 2, dof)
        tv = rng.uniform(0, 5)
        point = [*qv, *uv, tv]
        M = np.asarray(mass(*qv), float).reshape(dof, dof)
        f = np.asarray(forcing(*point), float).reshape(dof)
        a = np.linalg.solve(M, f)
        h = 1e-6
        ahead = energy(*(qv + h * uv), *(uv + h * a))
        behind = energy(*(qv - h * uv), *(uv - h * a))
        rate_of_energy = (ahead - behind) / (2 * h)
        by_library = sum(float(derived_powers[n](*point)) for n in nonconservative)
        by_hand = sum(float(own_powers[n](*point)) for n in nonconservative)
        scale = 1 + np.abs(M @ a).sum() * np.abs(uv).sum() + abs(by_hand)
        assert by_library == pytest.approx(by_hand, rel=1e-9, abs=1e-9 * scale)
        assert rate_of_energy == pytest.approx(by_library, abs=1e-6 * scale)

"""Hypothesis strategies for random planar mechanisms of 1-3 coordinates, and an
independent route to their equations: sympy.physics.mechanics' ``LagrangesMethod``
built from the same positions (tests/test_differential.py).

A mechanism is drawn as a :class:`Spec` in plain symbols ``z0, z1, z2``: links whose x,
y and angle come from a small grammar (sums and products of sines, cosines, square
roots of positive polynomials, constants and the coordinates), masses and inertias,
springs and dampers on such expressions, constant forces and moments, gravity, and a
Kloss motor on the first coordinate. Unless ``bare``, every coordinate turns a disc of
its own, so the mass matrix is regular everywhere."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import sympy as sp
from hypothesis import strategies as st
from sympy.physics.mechanics import LagrangesMethod, Point, ReferenceFrame, dynamicsymbols

import mechdyn as md

Z = sp.symbols("z0:3", real=True)
G = 9.81
number = st.floats(-1.5, 1.5).map(lambda v: round(v, 3))
positive = st.floats(0.2, 2.0).map(lambda v: round(v, 3))


@dataclass
class Spec:
    """A mechanism in plain symbols ``Z[:n]``; parameters are symbols valued in
    ``params`` (link masses and inertias), the rest numbers."""
    n: int
    links: list = field(default_factory=list)       # (name, m, J, x, y, angle)
    springs: list = field(default_factory=list)     # (k, stretch)
    dampers: list = field(default_factory=list)     # (c, stretch)
    loads: list = field(default_factory=list)       # (value, along)
    motor: tuple | None = None                      # (M_k, s_k, omega_sync) along z0
    gravity: bool = False
    params: dict = field(default_factory=dict)


def expressions(n):
    """An expression of ``Z[:n]`` from the grammar (depth at most 2)."""
    z = st.sampled_from(Z[:n])
    leaf = st.one_of(
        number,
        st.tuples(number, z).map(lambda a: a[0] * a[1]),
        st.tuples(z, number).map(lambda a: sp.sin(a[0] + a[1])),
        z.map(sp.cos),
        st.tuples(positive, positive, z).map(lambda a: sp.sqrt(a[0] + a[1] * a[2] ** 2)),
        st.tuples(positive, st.floats(0.0, 0.9), z).map(
            lambda a: sp.sqrt(a[0] * (1 - round(a[1], 3) * sp.sin(a[2]) ** 2))))
    node = st.tuples(leaf, leaf, st.booleans()).map(
        lambda a: a[0] + a[1] if a[2] else a[0] * a[1])
    return st.one_of(leaf, node)


def moving(n):
    """An expression of the grammar plus a multiple of a coordinate: it moves."""
    return st.tuples(expressions(n), st.sampled_from(Z[:n]), positive).map(
        lambda a: a[0] + a[2] * a[1]).filter(lambda e: bool(sp.sympify(e).free_symbols))


@st.composite
def mechanisms(draw, max_dof=3, motor=True):
    n = draw(st.integers(1, max_dof))
    spec = Spec(n, gravity=draw(st.booleans()))
    expr, bare = expressions(n), draw(st.integers(0, 9)) == 9
    for i in range(n):
        if not bare:
            J = sp.Symbol(f"J_d{i}", positive=True)
            spec.params[J] = draw(st.floats(0.05, 1.0))
            spec.links.append((f"disc{i}", 0, J, 0, 0, Z[i]))
    for j in range(draw(st.integers(1, 3))):
        m, J = sp.Symbol(f"m_{j}", positive=True), sp.Symbol(f"J_{j}", positive=True)
        has_J = draw(st.booleans())
        has_m = draw(st.booleans()) or not has_J
        if has_m:
            spec.params[m] = draw(positive)
        if has_J:
            spec.params[J] = draw(st.floats(0.05, 1.0))
        spec.links.append((f"link{j}", m if has_m else 0, J if has_J else 0,
                           draw(expr), draw(expr), draw(expr)))
    along = moving(n)
    spec.springs = draw(st.lists(st.tuples(st.floats(0.5, 10.0), along), max_size=2))
    spec.dampers = draw(st.lists(st.tuples(st.floats(0.0, 1.0), along), max_size=2))
    spec.loads = draw(st.lists(st.tuples(number, along), max_size=2))
    if motor and draw(st.booleans()):
        spec.motor = (draw(st.floats(1.0, 5.0)), draw(st.floats(0.1, 0.4)),
                      draw(st.floats(5.0, 20.0)))
    return spec


def states(n):
    """Positions in [-1, 1] and speeds in [-2, 2]."""
    return st.tuples(st.lists(st.floats(-1.0, 1.0), min_size=n, max_size=n),
                     st.lists(st.floats(-2.0, 2.0), min_size=n, max_size=n))


def build(spec, name="generated"):
    """The mechdyn declaration of ``spec`` and its coordinates."""
    coords = md.coordinates(" ".join(f"q{i}" for i in range(spec.n)))
    coords = coords if isinstance(coords, (list, tuple)) else [coords]
    to_q = dict(zip(Z, coords))

    def of(expr):
        return sp.sympify(expr).xreplace(to_q)
    mech = md.Mechanism(name, coords)
    for label, m, J, x, y, angle in spec.links:
        mech.link(label, m=m, J=J, x=of(x), y=of(y), angle=of(angle))
    for k, (value, stretch) in enumerate(spec.springs):
        mech.spring(f"spring{k}", value, stretch=of(stretch))
    for k, (value, stretch) in enumerate(spec.dampers):
        mech.damper(f"damper{k}", value, stretch=of(stretch))
    for k, (value, along) in enumerate(spec.loads):
        mech.load(f"load{k}", value, along=of(along))
    if spec.motor is not None:
        mech.load("motor", md.motors.kloss(*spec.motor), along=coords[0])
    if spec.gravity:
        mech.gravity(G)
    return mech, list(coords)


def kloss(M_k, s_k, omega_sync, speed):
    """The Kloss formula, written out here: ``2 M_k / (s/s_k + s_k/s)``."""
    s = 1 - speed / omega_sync
    return 2 * M_k * s * s_k / (s ** 2 + s_k ** 2)


def lagranges(spec):
    """``(M, f)`` of ``M qddot = f`` by ``LagrangesMethod`` in the states ``Z[:n]`` and
    their speeds ``W[:n]`` (plain symbols), parameters substituted."""
    t = dynamicsymbols._t
    q = [dynamicsymbols(f"Q{i}") for i in range(spec.n)]
    qd = [qi.diff(t) for qi in q]
    to_q = dict(zip(Z, q))
    frame, origin = ReferenceFrame("N"), Point("O")
    origin.set_vel(frame, 0)

    def of(expr):
        return sp.sympify(expr).xreplace(spec.params).xreplace(to_q)

    def rate(expr):
        return sp.diff(of(expr), t)
    kinetic, potential, forces = 0, 0, []
    for _, m, J, x, y, angle in spec.links:
        m, J = sp.sympify(m).xreplace(spec.params), sp.sympify(J).xreplace(spec.params)
        kinetic += m * (rate(x) ** 2 + rate(y) ** 2) / 2 + J * rate(angle) ** 2 / 2
        potential += m * G * of(y) if spec.gravity else 0
    potential += sum(k * of(s) ** 2 / 2 for k, s in spec.springs)

    def along(expr, value):        # a point moving with expr along N.x, pushed by value
        point = Point(f"P{len(forces)}")
        point.set_pos(origin, of(expr) * frame.x)
        point.set_vel(frame, rate(expr) * frame.x)
        forces.append((point, value * frame.x))
    for c, s in spec.dampers:
        along(s, -c * rate(s))
    for value, expr in spec.loads:
        along(expr, value)
    if spec.motor is not None:
        along(Z[0], kloss(*spec.motor, qd[0]))
    method = LagrangesMethod(sp.Matrix([kinetic - potential]), q, forcelist=forces,
                             frame=frame)
    method.form_lagranges_equations()
    W = sp.symbols(f"w0:{spec.n}", real=True)
    plain = dict(zip(qd, W)) | dict(zip(q, Z))
    return (method.mass_matrix.xreplace(plain), method.forcing.xreplace(plain), W)


def reference_rhs(spec):
    """``f(t, y)`` of ``y' = [w, M^-1 f]`` from :func:`lagranges`, lambdified."""
    mass, forcing, W = lagranges(spec)
    n = spec.n
    args = list(Z[:n]) + list(W)
    M, f = sp.lambdify(args, mass, "numpy"), sp.lambdify(args, forcing, "numpy")

    def rhs(_, y):            # a singular M: NaN, the step is rejected (status -1)
        try:
            a = np.linalg.solve(np.array(M(*y), dtype=float),
                                np.array(f(*y), dtype=float).ravel())
        except np.linalg.LinAlgError:
            a = np.full(n, np.nan)
        return np.concatenate([y[n:], a])
    return rhs

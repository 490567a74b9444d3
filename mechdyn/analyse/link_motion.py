"""The motion of every link and joint of a one-DOF mechanism along a prescribed crank
motion, and the loads attributed to the links they act on: the inputs of
:mod:`mechdyn.analyse.joint_reactions`.

A load acts on the link(s) named by its ``on=``, or on the one link whose centre
``x``, ``y`` and ``angle`` its ``along`` is a constant combination of (fitted at random
configurations): a moment along a link's angle, a force along its centre's x or y.
"""
from __future__ import annotations

import numpy as np
import sympy as sp

from mechdyn.compile.codegen import list_function
from mechdyn.derive.lagrange import _efficiency_factor
from mechdyn.declare.elements import Damper, Friction, Gravity, Joint, Link, Load, Spring
from mechdyn.declare.unilateral import Stop
from mechdyn.errors import MechdynError
from mechdyn.symbols import t

__all__ = ["LinkMotion", "KinetostaticsError"]

_FIT_POINTS = 4          # random configurations the load attribution is fitted at
_FIT_TOLERANCE = 1e-9


class KinetostaticsError(MechdynError, ValueError):
    """Joints or loads that do not determine the reactions (a link without joints, a
    load whose link cannot be told, a statically indeterminate set of joints)."""


class LinkMotion:
    """The generated motion of every link and joint point, the attributed loads and
    the kinematic states of a one-DOF mechanism (open or with loops)."""

    def __init__(self, mech, params, scene=None, guess=None):
        from mechdyn.declare.parameters import ParameterSet
        values = ParameterSet(params, mechanism=mech, scene=scene)    # before deriving
        self.mech, self.params = mech, dict(params or {})
        self.eqs = eqs = mech.equations(scene)
        if eqs.rheonomic:
            raise KinetostaticsError(f"{mech.name!r}: positions depend on time; "
                                     "kinetostatics needs a motion prescribed by the crank")
        if len(eqs.independent or eqs.q) != 1:
            raise KinetostaticsError(f"{mech.name!r}: kinetostatics needs one independent "
                                     f"coordinate, it has {len(eqs.independent or eqs.q)}")
        self.linkage = None
        if eqs.constraints:
            from mechdyn.analyse.linkage import Linkage
            self.linkage = Linkage(mech, values, guess, scene)
        self.links = {n: e for n, e in mech.elements.items() if isinstance(e, Link)}
        self.values = {s: sp.Float(v) for s, v in values.by_symbol().items()}
        self.names = tuple(str(q) for q in eqs.q)
        self._compile()

    def _plain(self, expr):
        return sp.sympify(self.eqs.to_plain(sp.sympify(expr)).xreplace(self.values))

    def _compile(self):
        eqs, n = self.eqs, self.eqs.dof
        accelerations = sp.symbols(f"_a0:{n}")
        self._poses = {}
        exprs = []
        for name, link in self.links.items():
            pose = [self._plain(link.x), self._plain(link.y), self._plain(link.angle)]
            self._poses[name] = pose
            for coordinate in pose:
                exprs += [coordinate, _second_derivative(coordinate, eqs.q, eqs.u,
                                                         accelerations)]
            exprs += [self._plain(link.m), self._plain(link.J)]
        self.joints = {n: e for n, e in self.mech.elements.items() if isinstance(e, Joint)}
        for joint in self.joints.values():
            exprs += [self._plain(joint.at[0]), self._plain(joint.at[1]),
                      self._plain(joint.direction if joint.direction is not None else 0)]
        if eqs.gears:
            raise KinetostaticsError(f"lossy gear {eqs.gears[0].name!r}: its loss depends on "
                                     "the power flow, which kinetostatics does not decide; "
                                     "declare an ideal gear as a constraint instead")
        self.loads = self._loads()
        exprs += [value for _, value, _ in self.loads]
        arguments = [str(s) for s in (*eqs.q, *eqs.u, *accelerations)]
        free = set().union(*(e.free_symbols for e in exprs)) - set(eqs.q) - set(eqs.u) \
            - set(accelerations) - {t}
        if free:
            raise KinetostaticsError(f"{self.mech.name!r}: no values for "
                                     f"{sorted(map(str, free))}")
        self.motion = list_function("motion", arguments, [], exprs)

    def _loads(self):
        """``(name, value expression, {link: (cx, cy, c_angle)})`` of every load, spring,
        damper and gravity force the scene includes."""
        eqs = self.eqs
        out = []
        for name in eqs.elements:
            element = self.mech.elements[name]
            if isinstance(element, (Friction, Stop)):
                raise KinetostaticsError(f"{type(element).__name__.lower()} {name!r}: "
                                         "kinetostatics prescribes the motion, leave "
                                         "friction and stops out of the scene")
            if isinstance(element, Gravity):
                g = self._plain(element.g)
                for link_name, link in self.links.items():
                    out.append((f"{name}:{link_name}", -self._plain(link.m) * g,
                                {link_name: (0.0, 1.0, 0.0)}))
                continue
            along, value = self._load_value(element)
            out.append((name, value, self._attribute(name, along, getattr(element, "on", ()))))
        return out

    def _load_value(self, element):
        eqs = self.eqs
        if isinstance(element, Load):
            along, value = self._plain(element.along), self._plain(element.value)
            if element.efficiency is not None:
                rate = sum((sp.diff(along, q) * u for q, u in zip(eqs.q, eqs.u)), sp.S.Zero)
                value = value * _efficiency_factor(value * rate, self._plain(element.efficiency))
            return along, value
        stretch = self._plain(element.stretch)
        if isinstance(element, Spring):
            return stretch, -self._plain(element.k) * stretch
        if isinstance(element, Damper):
            rate = sum((sp.diff(stretch, q) * u for q, u in zip(eqs.q, eqs.u)), sp.S.Zero)
            return stretch, -self._plain(element.c) * rate
        raise KinetostaticsError(f"{element.name!r}: not a load")   # pragma: no cover

    def _attribute(self, name, along, on):
        """The links a load acts on and its force/moment per unit value on each: the
        constant combination ``along = sum cx x_S + cy y_S + c angle`` (fitted at random
        configurations), from the links named in ``on`` or the one link that fits."""
        candidates = [tuple(on)] if on else [(link,) for link in self.links]
        fits = [(links, fit) for links in candidates
                for fit in [_fit(along, [self._poses[k] for k in links], self.eqs.q)]
                if fit is not None]
        if len(fits) == 1:
            links, coefficients = fits[0]
            return {k: tuple(coefficients[3 * i:3 * i + 3]) for i, k in enumerate(links)}
        if on:
            raise KinetostaticsError(
                f"load {name!r}: along = {along} is not a fixed combination of the centre "
                f"x, y and angle of {', '.join(on)}; kinetostatics needs loads that act at "
                "a link's centre of mass or as a moment on it")
        which = ", ".join(links[0] for links, _ in fits) or "none"
        raise KinetostaticsError(
            f"load {name!r}: cannot tell which link it acts on (along = {along} fits "
            f"{which}); give mech.load(..., on='link') (or on=(link, other) for a load "
            "between two links)")

    def states(self, phi, omega, eps):
        """``(q, u, a)`` arrays (n x N) along the prescribed motion."""
        phi = np.atleast_1d(np.asarray(phi, dtype=float))
        omega = np.broadcast_to(np.asarray(omega, dtype=float), phi.shape)
        eps = np.broadcast_to(np.asarray(eps, dtype=float), phi.shape)
        n = self.eqs.dof
        q, u, a = (np.zeros((n, len(phi))) for _ in range(3))
        for j in range(len(phi)):
            if self.linkage is None:
                q[0, j], u[0, j], a[0, j] = phi[j], omega[j], eps[j]
            else:
                q[:, j], u[:, j], a[:, j] = self.linkage.state(phi[j], omega[j], eps[j])
        return phi, omega, eps, q, u, a


def _second_derivative(expr, q, u, a):
    """``d2 expr/dt2`` in plain symbols (accelerations ``a``)."""
    rate = sum((sp.diff(expr, qi) * ui for qi, ui in zip(q, u)), sp.S.Zero)
    return sum((sp.diff(rate, qi) * ui + sp.diff(expr, qi) * ai
                for qi, ui, ai in zip(q, u, a)), sp.S.Zero)


def _fit(along, poses, q):
    """Constants ``c`` with ``grad along = sum c_k grad pose_k`` at random
    configurations, or None when no constant combination fits."""
    rng = np.random.default_rng(2024)
    gradient = sp.lambdify([q], [sp.diff(along, qi) for qi in q], "math")
    pose_gradients = sp.lambdify([q], [[sp.diff(c, qi) for qi in q]
                                       for pose in poses for c in pose], "math")
    rows, rhs = [], []
    for _ in range(_FIT_POINTS):
        point = rng.uniform(-3.0, 3.0, len(q))
        rows.append(np.array(pose_gradients(point), dtype=float).T)
        rhs.append(np.array(gradient(point), dtype=float))
    matrix, vector = np.vstack(rows), np.concatenate(rhs)
    if not np.any(vector):
        return None
    coefficients = np.linalg.lstsq(matrix, vector, rcond=None)[0]
    scale = max(np.max(np.abs(vector)), 1e-300)
    if np.max(np.abs(matrix @ coefficients - vector)) > _FIT_TOLERANCE * scale:
        return None
    coefficients[np.abs(coefficients) < 1e-12 * np.max(np.abs(coefficients))] = 0.0
    return coefficients

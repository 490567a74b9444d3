"""Kinetostatics: the driving moment and the joint reactions a prescribed motion needs,
and the shaking force and moment on the frame.

d'Alembert's principle link by link: with the motion prescribed (crank angle, speed and
acceleration; the loops give every other coordinate), each link's inertia force
``-m a_S`` and moment ``-J alpha``, its weight and the loads on it are balanced by the
joint reactions and the driving moment:

    sum F = m a_S,   sum M_S = J alpha          (three equations per link)

A revolute joint carries a force (2 unknowns), a prismatic joint a force normal to its
slide and a moment (2), a weld a force and a moment (3); the drive adds one unknown.
The reaction of a joint is what its first link exerts on its second (the second link
gets ``+R``, the first ``-R``). Loads act on the link they name (``on=``) or on the one
link whose centre ``x``, ``y`` and ``angle`` their ``along`` is a fixed combination of
(a moment along a link's angle, a force along its centre's x).

The shaking force is the resultant of the inertia forces, ``F_s = -sum m_i a_Si``; the
shaking moment ``M_s = -sum (J_i alpha_i + (r_Si x m_i a_Si)_z)`` about the origin: what
the moving links load the frame with, beyond their weight and the loads.

>>> import sympy as sp, mechdyn as md
>>> phi = md.coordinate("phi")
>>> crank = md.Mechanism("unbalanced disc", [phi])
>>> _ = crank.link("disc", m=2, J=0.1, x=0.05 * sp.cos(phi), y=0.05 * sp.sin(phi), angle=phi)
>>> _ = crank.joint("O", ("frame", "disc"), at=(0, 0))
>>> result = md.kinetostatics(crank, {}, [0.0], omega=10)
>>> [round(float(v), 9) for v in result.shaking_force[:, 0]]   # m r omega^2 outwards
[10.0, 0.0]
>>> round(float(result.reactions["O"].x[0]), 9)                 # the frame pulls inwards
-10.0
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import sympy as sp

from .codegen import compile_source, function_source
from .derive import _efficiency_factor
from .elements import FRAME, Damper, Friction, Gravity, Joint, Link, Load, Spring
from .errors import MechdynError
from .symbols import t

__all__ = ["KinetostaticsError", "Reaction", "Kinetostatics", "kinetostatics", "shaking"]

_FIT_POINTS = 4          # random configurations the load attribution is fitted at
_FIT_TOLERANCE = 1e-9


class KinetostaticsError(MechdynError, ValueError):
    """Joints or loads that do not determine the reactions (a link without joints, a
    load whose link cannot be told, a statically indeterminate set of joints)."""


@dataclass(frozen=True)
class Reaction:
    """The reaction of a joint over the motion: the force ``x``, ``y`` its first link
    exerts on its second (arrays), and for prismatic joints and welds the ``moment``;
    for a prismatic joint also the ``normal`` force (along the slide's left normal)."""
    joint: str
    kind: str
    links: tuple
    x: np.ndarray
    y: np.ndarray
    moment: np.ndarray | None = None
    normal: np.ndarray | None = None

    @property
    def magnitude(self) -> np.ndarray:
        return np.hypot(self.x, self.y)


@dataclass(frozen=True)
class Kinetostatics:
    """Kinetostatics over a prescribed motion: crank angle ``phi``, speed ``omega``,
    acceleration ``eps`` (arrays), the ``driving`` moment (or force) of the drive,
    ``reactions`` (joint name -> :class:`Reaction`), ``shaking_force`` (2 x N),
    ``shaking_moment`` (N, about the origin), ``positions`` (all coordinates, one row
    each, ``names``) and ``residual`` (the largest unbalance of any link's equations
    after the solve, relative to the largest force or moment: 0 unless the joints are
    redundant)."""
    phi: np.ndarray
    omega: np.ndarray
    eps: np.ndarray
    driving: np.ndarray
    reactions: dict
    shaking_force: np.ndarray
    shaking_moment: np.ndarray
    positions: np.ndarray
    names: tuple
    residual: float

    def plot(self, path=None):
        """Joint forces and the driving moment over the crank angle."""
        from .linkage_plots import plot_kinetostatics
        return plot_kinetostatics(self, path)


class _Model:
    """The generated motion of every link and joint point, the attributed loads and
    the kinematic states of a one-DOF mechanism (open or with loops)."""

    def __init__(self, mech, params, scene=None, guess=None):
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
            from .linkage import Linkage
            self.linkage = Linkage(mech, params, guess, scene)
        self.links = {n: e for n, e in mech.elements.items() if isinstance(e, Link)}
        self.values = {s: sp.Float(float(v)) for s, v in
                       ((k if isinstance(k, sp.Symbol) else sp.Symbol(str(k)), v)
                        for k, v in self.params.items())}
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
        self.loads = self._loads()
        exprs += [value for _, value, _ in self.loads]
        arguments = [str(s) for s in (*eqs.q, *eqs.u, *accelerations)]
        free = set().union(*(e.free_symbols for e in exprs)) - set(eqs.q) - set(eqs.u) \
            - set(accelerations) - {t}
        if free:
            raise KinetostaticsError(f"{self.mech.name!r}: no values for "
                                     f"{sorted(map(str, free))}")
        source = function_source("motion", arguments, [], exprs,
                                 "return [" + "{}, " * len(exprs) + "]")
        self.motion = compile_source(source)["motion"]

    def _loads(self):
        """``(name, value expression, {link: (cx, cy, c_angle)})`` of every load, spring,
        damper and gravity force the scene includes."""
        eqs = self.eqs
        out = []
        for name in eqs.elements:
            element = self.mech.elements[name]
            if isinstance(element, Friction):
                raise KinetostaticsError(f"friction {name!r}: kinetostatics prescribes the "
                                         "motion, leave Coulomb friction out of the scene")
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


_UNKNOWNS = {"revolute": ("x", "y"), "prismatic": ("normal", "moment"),
             "weld": ("x", "y", "moment")}


def _unpack(model, values):
    """Link states ``{name: (x, y, ax, ay, alpha, m, J)}``, joint points
    ``{name: (x, y, direction)}`` and load values from one evaluation of the motion."""
    links, k = {}, 0
    for name in model.links:
        x, ax, y, ay, _, alpha, m, inertia = values[k:k + 8]
        links[name] = (x, y, ax, ay, alpha, m, inertia)
        k += 8
    joints = {}
    for name in model.joints:
        joints[name] = tuple(values[k:k + 3])
        k += 3
    return links, joints, values[k:]


def shaking(mech, params, phi, omega, eps=0.0, scene=None, guess=None):
    """Shaking force (2 x N) and moment (N, about the origin) of the prescribed motion:
    ``F_s = -sum m a_S``, ``M_s = -sum (J alpha + (r_S x m a_S)_z)``."""
    model = _Model(mech, params, scene, guess)
    _, _, _, q, u, a = model.states(phi, omega, eps)
    return _shaking(model, q, u, a)


def _shaking(model, q, u, a):
    force, moment = np.zeros((2, q.shape[1])), np.zeros(q.shape[1])
    for j in range(q.shape[1]):
        links, _, _ = _unpack(model, model.motion(0.0, [*q[:, j], *u[:, j], *a[:, j]], []))
        for x, y, ax, ay, alpha, m, inertia in links.values():
            force[:, j] -= (m * ax, m * ay)
            moment[j] -= inertia * alpha + m * (x * ay - y * ax)
    return force, moment


def kinetostatics(mech, params, phi, omega, eps=0.0, drive=None, scene=None,
                  guess=None) -> Kinetostatics:
    """Driving moment, joint reactions and shaking force and moment of a one-DOF
    mechanism moved through the crank angles ``phi`` at speed ``omega`` and acceleration
    ``eps`` (numbers or arrays like ``phi``).

    Parameters
    ----------
    mech : Mechanism
        With joints (:meth:`~mechdyn.Mechanism.joint`) joining every link.
    params : dict
        Parameter values.
    drive : str, optional
        Name or tag of the load whose value is unknown (the drive); default: a moment on
        the link whose angle is the independent coordinate.
    scene : Scene, optional
        Selects the loads (all when None). guess : dict, optional: the assembly branch.
    """
    model = _Model(mech, params, scene, guess)
    phi, omega, eps, q, u, a = model.states(phi, omega, eps)
    if not model.joints:
        raise KinetostaticsError(f"{mech.name!r} declares no joints; declare them with "
                                 "mech.joint(name, (link_a, link_b), at=(x, y))")
    moving = list(model.links)
    joined = {k for joint in model.joints.values() for k in joint.links}
    loose = [k for k in moving if k not in joined]
    if loose:
        raise KinetostaticsError(f"links {loose} are in no joint; join them (a flywheel "
                                 "keyed on a crank: kind='weld')")
    drive_columns = _drive(model, drive)
    columns = [(name, c) for name, joint in model.joints.items()
               for c in _UNKNOWNS[joint.kind]]
    rows, count = 3 * len(moving), len(columns) + 1
    out = np.zeros((count, len(phi)))
    directions = {name: np.zeros(len(phi)) for name in model.joints}
    worst = 0.0
    for j in range(len(phi)):
        state = [*q[:, j], *u[:, j], *a[:, j]]
        links, points, loads = _unpack(model, model.motion(0.0, state, []))
        matrix, rhs = np.zeros((rows, count)), np.zeros(rows)
        for index, name in enumerate(moving):
            x, y, ax, ay, alpha, m, inertia = links[name]
            rhs[3 * index:3 * index + 3] = (m * ax, m * ay, inertia * alpha)
        for (name, value, acting), load_value in zip(model.loads, loads):
            if name in drive_columns:
                continue
            for link, (cx, cy, c_angle) in acting.items():
                if link != FRAME:
                    i = moving.index(link)
                    rhs[3 * i:3 * i + 3] -= (load_value * cx, load_value * cy,
                                             load_value * c_angle)
        for column, (name, component) in enumerate(columns):
            joint = model.joints[name]
            px, py, direction = points[name]
            directions[name][j] = direction
            for link, sign in ((joint.links[1], 1.0), (joint.links[0], -1.0)):
                if link == FRAME:
                    continue
                i = moving.index(link)
                x, y = links[link][:2]
                force = {"x": (1.0, 0.0), "y": (0.0, 1.0),
                         "normal": (-np.sin(direction), np.cos(direction))}.get(component)
                if force is None:                                     # a couple
                    matrix[3 * i + 2, column] += sign
                else:
                    fx, fy = sign * force[0], sign * force[1]
                    matrix[3 * i:3 * i + 3, column] += (fx, fy, (px - x) * fy - (py - y) * fx)
        for link, (cx, cy, c_angle) in _drive_wrench(drive_columns).items():
            if link != FRAME:
                i = moving.index(link)
                matrix[3 * i:3 * i + 3, -1] += (cx, cy, c_angle)
        solution, _, rank, _ = np.linalg.lstsq(matrix, rhs, rcond=None)
        if rank < count:
            raise KinetostaticsError(
                f"{mech.name!r}: the joints do not determine the reactions ({rows} "
                f"equations of {len(moving)} links, {count} unknowns, rank {rank}): "
                "statically indeterminate (a redundant joint) or the drive acts on no link")
        scale = max(np.max(np.abs(rhs)), np.max(np.abs(matrix @ solution)), 1e-300)
        worst = max(worst, float(np.max(np.abs(matrix @ solution - rhs))) / scale)
        out[:, j] = solution
    if worst > 1e-8:
        raise KinetostaticsError(
            f"{mech.name!r}: the links cannot be balanced by these joints (relative "
            f"unbalance {worst:.2g}): joints missing or joining the wrong links")
    force, moment = _shaking(model, q, u, a)
    return Kinetostatics(phi, np.array(omega), np.array(eps), out[-1],
                         _reactions(model, columns, out, directions), force, moment, q,
                         model.names,
                         worst)


def _reactions(model, columns, values, directions):
    reactions = {}
    for name, joint in model.joints.items():
        parts = {c: values[k] for k, (n, c) in enumerate(columns) if n == name}
        if joint.kind == "prismatic":
            normal, angle = parts["normal"], directions[name]
            reactions[name] = Reaction(name, joint.kind, joint.links, -np.sin(angle) * normal,
                                       np.cos(angle) * normal, parts["moment"], normal)
        else:
            reactions[name] = Reaction(name, joint.kind, joint.links, parts["x"],
                                       parts["y"], parts.get("moment"))
    return reactions


def _drive(model, drive):
    """The loads whose value is the unknown drive: ``{name: {link: coefficients}}``."""
    if drive is not None:
        chosen = {name: acting for name, _, acting in model.loads
                  if name == drive or drive in getattr(model.mech.elements.get(name),
                                                       "tags", ())}
        if not chosen:
            raise KinetostaticsError(f"drive {drive!r}: no load of the scene has that name "
                                     f"or tag (loads: {[n for n, _, _ in model.loads]})")
        return chosen
    crank = model.eqs.independent[0] if model.eqs.independent else model.eqs.q[0]
    links = [k for k, pose in model._poses.items() if pose[2] == crank]
    if len(links) != 1:
        raise KinetostaticsError(
            f"{model.mech.name!r}: give drive= (the load that drives): the crank angle "
            f"{crank} turns {len(links)} links ({', '.join(links) or 'none'})")
    return {"drive": {links[0]: (0.0, 0.0, 1.0)}}


def _drive_wrench(drive_columns):
    total = {}
    for acting in drive_columns.values():
        for link, coefficients in acting.items():
            previous = total.get(link, (0.0, 0.0, 0.0))
            total[link] = tuple(p + c for p, c in zip(previous, coefficients))
    return total

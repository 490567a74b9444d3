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

from mechdyn.declare.elements import FRAME
from mechdyn.analyse.link_motion import KinetostaticsError, LinkMotion

__all__ = ["KinetostaticsError", "Reaction", "Kinetostatics", "kinetostatics", "shaking"]


@dataclass(frozen=True)
class Reaction:
    """The reaction of a joint over the motion: the force ``x``, ``y`` its first link
    exerts on its second (arrays), and for prismatic joints and welds the ``moment``;
    for a prismatic joint also the ``normal`` force (along the slide's left normal).

    Examples
    --------
    >>> import sympy as sp, mechdyn as md
    >>> phi = md.coordinate("phi")
    >>> crank = md.Mechanism("unbalanced disc", [phi])
    >>> _ = crank.link("disc", m=2, J=0.1, x=0.05 * sp.cos(phi), y=0.05 * sp.sin(phi), angle=phi)
    >>> _ = crank.joint("O", ("frame", "disc"), at=(0, 0))
    >>> pivot = md.kinetostatics(crank, {}, [0.0], omega=10).reactions["O"]
    >>> pivot.kind, pivot.links, pivot.x.round(9), pivot.y.round(9)  # the frame pulls inwards
    ('revolute', ('frame', 'disc'), array([-10.]), array([0.]))
    """
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
    redundant).

    Examples
    --------
    >>> import sympy as sp, mechdyn as md
    >>> phi = md.coordinate("phi")
    >>> crank = md.Mechanism("unbalanced disc", [phi])
    >>> _ = crank.link("disc", m=2, J=0.1, x=0.05 * sp.cos(phi), y=0.05 * sp.sin(phi), angle=phi)
    >>> _ = crank.joint("O", ("frame", "disc"), at=(0, 0))
    >>> result = md.kinetostatics(crank, {}, [0.0], omega=10)
    >>> result.shaking_force[:, 0].round(9), result.names
    (array([10.,  0.]), ('phi',))
    """
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
        from mechdyn.analyse.linkage_plots import plot_kinetostatics
        return plot_kinetostatics(self, path)


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
    ``F_s = -sum m a_S``, ``M_s = -sum (J alpha + (r_S x m a_S)_z)``.

    Examples
    --------
    >>> import sympy as sp, mechdyn as md
    >>> phi = md.coordinate("phi")
    >>> crank = md.Mechanism("unbalanced disc", [phi])
    >>> _ = crank.link("disc", m=2, J=0.1, x=0.05 * sp.cos(phi), y=0.05 * sp.sin(phi), angle=phi)
    >>> _ = crank.joint("O", ("frame", "disc"), at=(0, 0))
    >>> force, moment = md.shaking(crank, {}, [0.0, 1.5707963267948966], omega=10)
    >>> force.round(9)                                # m e omega^2 = 10 N, outwards
    array([[10.,  0.],
           [ 0., 10.]])
    """
    model = LinkMotion(mech, params, scene, guess)
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

    Returns
    -------
    Kinetostatics

    Raises
    ------
    KinetostaticsError
        Joints or loads that do not determine the reactions.

    Examples
    --------
    A disc of 2 kg whose centre is 5 cm off its pivot, turning at 10 rad/s and
    accelerating at 4 rad/s^2: the drive supplies ``(J + m e^2) eps``:

    >>> import sympy as sp, mechdyn as md
    >>> phi = md.coordinate("phi")
    >>> crank = md.Mechanism("unbalanced disc", [phi])
    >>> _ = crank.link("disc", m=2, J=0.1, x=0.05 * sp.cos(phi), y=0.05 * sp.sin(phi), angle=phi)
    >>> _ = crank.joint("O", ("frame", "disc"), at=(0, 0))
    >>> result = md.kinetostatics(crank, {}, [0.0], omega=10, eps=4)
    >>> round(float(result.driving[0]), 9)           # (0.1 + 2 * 0.05^2) * 4
    0.42
    """
    model = LinkMotion(mech, params, scene, guess)
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

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
from mechdyn.declare.elements import Joint, Link
from mechdyn.declare.contract import call, completed
from mechdyn.errors import MechdynError
from mechdyn.symbols import t

__all__ = ["LinkMotion", "KinetostaticsError"]

_FIT_POINTS = 4          # random configurations the load attribution is fitted at
_FIT_TOLERANCE = 1e-9


class KinetostaticsError(MechdynError, ValueError):
    """Joints or loads that do not determine the reactions (a link without joints, a
    load whose link cannot be told, a statically indeterminate set of joints).

    Examples
    --------
    A link without joints:

    >>> import sympy as sp, mechdyn as md
    >>> phi = md.coordinate("phi")
    >>> crank = md.Mechanism("disc", [phi])
    >>> _ = crank.link("disc", m=2, J=0.1, x=0.05 * sp.cos(phi), y=0.05 * sp.sin(phi), angle=phi)
    >>> try:
    ...     md.kinetostatics(crank, {}, [0.0], omega=10)
    ... except md.KinetostaticsError as error:
    ...     print(type(error).__name__)
    KinetostaticsError
    """


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
        """``(name, value expression, {link: (cx, cy, c_angle)})`` of every force the
        scene's elements exert (a weight: ``GRAVITY:LINK``, straight down on its link)."""
        motion = _PrescribedMotion(self)
        out = []
        for name in self.eqs.elements:
            element = self.mech.elements[name]
            work = completed(element, call(element, "work", motion), self.eqs.q, sp.diff)
            if work.sliding is not None or work.contacts:
                raise KinetostaticsError(f"{type(element).__name__.lower()} {name!r}: "
                                         "kinetostatics prescribes the motion, leave "
                                         "friction and stops out of the scene")
            for index, (value, along) in enumerate(work.forces):
                if along in motion.weighed:
                    link = motion.weighed[along]
                    out.append((f"{name}:{link}", value, {link: (0.0, 1.0, 0.0)}))
                    continue
                label = name if len(work.forces) == 1 else f"{name}:{index}"
                out.append((label, value,
                            self._attribute(label, along, getattr(element, "on", ()))))
        return out

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


class _PrescribedMotion:
    """The motion elements write their forces with (:mod:`mechdyn.declare.element_base`):
    plain symbols with the parameters' values; a link's height is a marker symbol, so a
    weight is attributed to its link even where the link's centre does not move."""

    def __init__(self, link_motion):
        self.plain, eqs = link_motion._plain, link_motion.eqs
        self.q, self.u = eqs.q, eqs.u
        self.weighed = {sp.Dummy(f"y_{name}"): name for name in link_motion.links}
        self._heights = [(name, self.plain(link_motion.links[name].m), marker)
                         for marker, name in self.weighed.items()]

    def position(self, expr, owner):
        return self.plain(expr)

    def law(self, expr, along, owner):
        return self.plain(expr)

    def rate(self, expr):
        return sum((sp.diff(expr, q) * u for q, u in zip(self.q, self.u)), sp.S.Zero)

    def heights(self):
        return self._heights


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

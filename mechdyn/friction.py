"""Friction modes: which friction elements slide, which stick, which are free.

The state machine of Modelica's friction elements (``PartialFriction``), element by
element and across coordinates:

- **sliding** forward or backward: the element pushes ``-sign * magnitude`` along its
  ``along`` expression until its sliding speed reaches zero (an event);
- **stuck**: its sliding speed is held at exactly zero by a holding force ``lambda``
  from the constrained equations ``[M -G'; G 0] [a; lambda] = [f; -bias]``; it releases
  (an event) when ``lambda`` leaves the interval it can hold, ``[-peak * magnitude,
  peak * magnitude]``, and slides the way the other loads push;
- **free**: its magnitude is not positive (a clutch not pressed): no force, never stuck;
  it engages (an event) when the magnitude becomes positive.

Stuck elements along parallel directions (two brakes on one shaft) hold together: one
constraint whose interval is the sum of theirs, the holding force shared in proportion
to their capacities. An element whose constraint cannot act at a state (``G M^-1 G'``
vanishes: friction on a slider at the crank's dead centre, where the slider stops for an
instant while the crank turns) never sticks there: it keeps sliding, the way its sliding
speed moves on. Friction only ever dissipates.

>>> import mechdyn as md
>>> model = md.load_model("models/shoe_brake.py")
>>> res = model.mechanism.simulate(model.scenes["braking"], model.params)
>>> [e.kind for e in res.events]
['stick', 'end']
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .events import Event

__all__ = ["Mode", "FrictionModes", "allowed_motions"]

_PARALLEL = 1e-12          # relative misalignment under which two gradients are parallel
_CANNOT_HOLD = 1e-12       # relative G M^-1 G' under which a constraint cannot act


@dataclass(frozen=True)
class Mode:
    """The discrete state of a segment: friction modes and locked branches.

    ``signs``: per element +1/-1 (sliding that way), 0 (stuck or free); ``groups``: the
    stuck elements as lists of ``(element, alpha)`` with ``gradient = alpha * gradient of
    the group's first element``; ``free``: elements with no positive magnitude;
    ``flags``: the side (+1/-1, 0 unlocked) of each switching function, which locks the
    branches of the equations for the segment (:class:`mechdyn.generate.Switches`)."""
    signs: tuple = ()
    groups: tuple = ()
    free: frozenset = field(default_factory=frozenset)
    flags: tuple = ()

    @property
    def stuck(self) -> list:
        return [k for group in self.groups for k, _ in group]

    @property
    def leaders(self) -> list:
        return [group[0][0] for group in self.groups]


class FrictionModes:
    """The friction elements of a compiled scene and the decisions about their modes.

    ``compiled``: the :class:`~mechdyn.compile.CompiledScene`; ``base``: the parameter
    values (``p`` without the friction signs)."""

    def __init__(self, compiled, base):
        self.c, self.base = compiled, list(base)
        self.n, self.k = compiled.dof, len(compiled.frictions)
        self.names = compiled.frictions
        self.frozen = compiled.frozen

    def p(self, mode: Mode) -> list:
        """The parameter vector of a mode: values, friction signs, branch flags."""
        return self.base + list(mode.signs or [0.0] * self.k) + \
            list(mode.flags or [0.0] * self.c.flags)

    # ------------------------------------------------------------ decisions
    def decide(self, t, y, flags=(), at_rest=(), events=None) -> Mode:
        """The mode at a state: sliding elements keep sliding the way they move;
        elements at rest (and those in ``at_rest``, whose sliding speed just reached
        zero) stick where the holding force they need fits their capacity, else slide
        the way the loads push. Releases are decided here too, at the state just past a
        release event. Decisions are appended to ``events`` as :class:`Event`."""
        flags = tuple(flags)
        if not self.k:
            return Mode(flags=flags)
        events = events if events is not None else []
        terms = self.c.terms(t, y, self.p(Mode(flags=flags)))
        rate, magnitude = terms["friction_rate"], terms["friction_magnitude"]
        scale = 1.0 + float(np.max(np.abs(y[self.n:]), initial=0.0))
        signs, free, candidates = [0.0] * self.k, set(), []
        for k in range(self.k):
            if magnitude[k] <= 0:
                free.add(k)
            elif abs(rate[k]) > 1e-12 * scale and k not in at_rest:
                signs[k] = math.copysign(1.0, rate[k])
            else:
                candidates.append(k)
        held = self._holdable(terms, candidates)
        for k in set(candidates) - set(held):     # cannot hold here: keeps sliding
            signs[k] = self._drift_sign(terms, k)
        while True:
            groups = _parallel_groups(terms["friction_gradient"], held)
            if not groups:
                break
            _, holding = self._solve(t, y, Mode(tuple(signs), tuple(groups), flags=flags))
            worst, worst_excess, slide = None, 0.0, 0.0
            for group, lam in zip(groups, holding):
                capacity = sum(abs(alpha) * magnitude[k] for k, alpha in group)
                excess = abs(lam) - capacity
                if excess > worst_excess:
                    worst, worst_excess, slide = group, excess, -math.copysign(1.0, lam)
            if worst is None:
                break
            for k, alpha in worst:
                signs[k] = slide * math.copysign(1.0, alpha)
                held.remove(k)
                events.append(Event(t, "slip", self.names[k], f"slides {_way(signs[k])}"))
        groups = _parallel_groups(terms["friction_gradient"], held)
        return Mode(tuple(signs), tuple(tuple(g) for g in groups), frozenset(free), flags)

    def _holdable(self, terms, candidates) -> list:
        """The candidates whose constraint can act: ``G M^-1 G'`` not negligible, on the
        motions the closed loops allow (mass and gradient reduced to them)."""
        mass, grads = terms["mass"], terms["friction_gradient"]
        basis = allowed_motions(terms["constraint_gradient"], self.n)
        mass = basis.T @ mass @ basis
        held = []
        for k in candidates:
            g = grads[k] @ basis
            weight = float(g @ np.linalg.solve(mass, g))
            scale = float(g @ g) / max(float(np.max(np.abs(np.diag(mass)))), 1e-300)
            if weight > _CANNOT_HOLD * scale and weight > 0:
                held.append(k)
        return held

    def _drift_sign(self, terms, k) -> float:
        """The way an element that cannot hold will slide: the sign of its sliding
        acceleration, which its own force does not change (``G M^-1 G' = 0``)."""
        bias = terms["friction_bias"][k]
        return math.copysign(1.0, bias) if bias != 0 else 1.0

    # ---------------------------------------------------------- dynamics
    def _solve(self, t, y, mode, terms=None, loops=False):
        """Accelerations and the holding force of each stuck group (and with ``loops``
        the closed loops' constraint forces, always active, first)."""
        terms = terms or self.c.terms(t, y, self.p(mode))
        mass, forcing = terms["mass"], terms["forcing"]
        loop_rows = terms["constraint_gradient"]
        if not mode.groups and not len(loop_rows):
            a = np.linalg.solve(mass, forcing)
            return (a, np.zeros(0), np.zeros(0)) if loops else (a, np.zeros(0))
        leaders = [group[0][0] for group in mode.groups]
        g = np.vstack([loop_rows, terms["friction_gradient"][leaders].reshape(-1, self.n)])
        bias = np.concatenate([terms["constraint_bias"], terms["friction_bias"][leaders]])
        m = len(g)
        system = np.zeros((self.n + m, self.n + m))
        system[:self.n, :self.n] = mass
        system[:self.n, self.n:] = -g.T
        system[self.n:, :self.n] = g
        solution = np.linalg.solve(system, np.concatenate([forcing, -bias]))
        a, lam = solution[:self.n], solution[self.n:]
        split = len(loop_rows)
        return (a, lam[split:], lam[:split]) if loops else (a, lam[split:])

    def multipliers(self, t, y, mode):
        """Closed loops: their constraint forces ``lambda`` (``M a = f + G' lambda``),
        with the stuck frictions' constraints in the same system."""
        return self._solve(t, y, mode, loops=True)[2]

    def accelerations(self, t, y, mode):
        """Accelerations and the friction force of every element (the holding force
        share of stuck ones, ``-sign * magnitude`` of sliding ones, 0 of free ones)."""
        p = self.p(mode)
        terms = self.c.terms(t, y, p)
        a, holding = self._solve(t, y, mode, terms)
        for k in mode.stuck:
            if self.frozen[k] >= 0:
                a[self.frozen[k]] = 0.0
        forces = np.array([-s * m for s, m in zip(mode.signs, terms["friction_magnitude"])])
        magnitude = terms["friction_magnitude"]
        for group, lam in zip(mode.groups, holding):
            capacity = sum(abs(alpha) * magnitude[k] for k, alpha in group)
            for k, alpha in group:
                share = abs(alpha) * magnitude[k] / capacity if capacity > 0 else 1 / len(group)
                forces[k] = lam * share * math.copysign(1.0, alpha) / abs(alpha)
        return a, forces

    def rhs(self, mode):
        """``fun(t, y)`` of a mode with stuck elements (``None`` when none is stuck: the
        generated ``rhs``, which holds closed loops itself): the constrained
        accelerations; coordinates held by a stuck element keep exactly zero speed."""
        if not mode.groups:
            return None
        n, p = self.n, self.p(mode)
        frozen = [self.frozen[k] for k in mode.stuck if self.frozen[k] >= 0]

        def constrained(t, y):
            a, _ = self._solve(t, y, mode, self.c.terms(t, y, p))
            dy = np.concatenate([y[n:], a])
            for i in frozen:
                dy[i] = dy[n + i] = 0.0
            return dy
        return constrained

    def project(self, t, y, mode):
        """Put the state on the closed loops (positions and speeds, least change), then
        make the sliding speeds of the stuck elements exactly zero by the impulse that
        changes the kinetic energy least (speeds projected with the mass matrix); with
        loops, by the least change that keeps the loops' speeds closed."""
        y = np.array(y, dtype=float)
        if self.c.constraints:
            from .assembly import project
            y = project(self.c, t, y, self.p(mode))
        if not mode.groups:
            return y
        terms = self.c.terms(t, y, self.p(mode))
        leaders = mode.leaders
        g = terms["friction_gradient"][leaders]
        if self.c.constraints:
            rows = np.vstack([terms["constraint_gradient"], g])
            residual = np.concatenate([terms["constraint_gradient"] @ y[self.n:]
                                       + terms["constraint_rate"],
                                       terms["friction_rate"][leaders]])
            y[self.n:] -= np.linalg.lstsq(rows, residual, rcond=None)[0]
        else:
            w = np.linalg.solve(terms["mass"], g.T)
            y[self.n:] -= w @ np.linalg.solve(g @ w, terms["friction_rate"][leaders])
        for k in mode.stuck:
            if self.frozen[k] >= 0:
                y[self.n + self.frozen[k]] = 0.0
        return y

    # ------------------------------------------------------------- events
    def event_values(self, t, y, mode, watched) -> list:
        """The values of friction event functions at a state, ``watched`` a list of
        ``(kind, index, direction)``: a group's release margin, a sliding speed, a
        magnitude."""
        if not watched:
            return []
        terms = self.c.terms(t, y, self.p(mode))
        holding = self._solve(t, y, mode, terms)[1] if mode.groups else ()
        magnitude = terms["friction_magnitude"]
        out = []
        for kind, index, _ in watched:
            if kind == "stick":
                out.append(terms["friction_rate"][index])
            elif kind == "release":
                group = mode.groups[index]
                capacity = sum(abs(alpha) * magnitude[k] for k, alpha in group)
                out.append(capacity - abs(holding[index]))
            else:
                out.append(magnitude[index])
        return out


def allowed_motions(loop_gradients, n):
    """A basis of the speeds the closed loops allow (the null space of their
    gradients); the identity without loops."""
    if not len(loop_gradients):
        return np.eye(n)
    _, singular, vt = np.linalg.svd(loop_gradients)
    rank = int(np.sum(singular > 1e-12 * max(singular[0], 1e-300)))
    return vt[rank:].T


def _way(sign) -> str:
    return "forward" if sign > 0 else "backward"


def _parallel_groups(grads, stuck) -> list:
    """Stuck elements grouped by parallel gradients: lists of ``(index, alpha)`` with
    ``grads[index] = alpha * grads[first of group]``."""
    groups = []
    for k in stuck:
        g = grads[k]
        for members in groups:
            reference = grads[members[0][0]]
            alpha = float(g @ reference) / float(reference @ reference)
            if np.linalg.norm(g - alpha * reference) <= _PARALLEL * np.linalg.norm(g):
                members.append((k, alpha))
                break
        else:
            groups.append([(k, 1.0)])
    return groups

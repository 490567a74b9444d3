"""Friction modes: which friction elements slide, which stick, which are free; which
one-way clutches overrun or lock, which stops are open or in contact, how lossy gears
turn.

The state machine of Modelica's friction elements (``PartialFriction``), element by
element and across coordinates:

- **sliding** forward or backward: the element pushes ``-sign * magnitude`` along its
  ``along`` expression until its sliding speed reaches zero (an event); a one-way clutch
  slides (overruns) forward only; a lossy gear's loss follows its law
  (:mod:`mechdyn.declare.gear_loss`), solved with the equations (:mod:`mechdyn.simulate.constrained`);
- **stuck**: its sliding speed is held at exactly zero by a holding force ``lambda``
  from the constrained equations ``[M -G'; G 0] [a; lambda] = [f; -bias]``; it releases
  (an event) when ``lambda`` leaves the interval it can hold: ``[-peak * magnitude,
  peak * magnitude]`` (static friction, ``peak >= 1``), unbounded backward for a locked
  one-way clutch, ``[0, inf)`` for a stop in contact, the loss law at rest for a gear;
  then it slides the way the other loads push, with its sliding ``magnitude``;
- **free**: its magnitude is not positive (a clutch not pressed): no force, never stuck;
  it engages (an event) when the magnitude becomes positive.

A stop's limit is **open** (its gap is watched) or **in contact**: a stuck member that
only pushes. Reaching a limit is an impact (:mod:`mechdyn.simulate.contacts`). Stuck elements
along parallel directions (two brakes on one shaft, a friction and a stop on one mass, a
gear and a bearing on its shaft: parallel on the motions the closed loops allow) hold
together: one constraint whose interval is the sum of theirs. An element whose
constraint cannot act at a state (``G M^-1 G'`` vanishes: friction on a slider at the
crank's dead centre, where the slider stops for an instant while the crank turns) never
sticks there: it keeps sliding, the way its sliding speed moves on. Friction only ever
dissipates.

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

from mechdyn.simulate.constrained import group_check, shares, solve
from mechdyn.simulate.events import Event
from mechdyn.declare.gear_loss import LossLaw

__all__ = ["Mode", "FrictionModes", "StateView", "allowed_motions", "largest_magnitude"]

_PARALLEL = 1e-12          # relative misalignment under which two gradients are parallel
_CANNOT_HOLD = 1e-12       # relative G M^-1 G' under which a constraint cannot act
_AT_REST = 1e-12           # sliding speeds below this (x (1 + largest speed)) are at rest


@dataclass(frozen=True)
class Mode:
    """The discrete state of a segment: friction modes and locked branches.

    ``signs``: per friction element +1/-1 (sliding that way), 0 (stuck or free);
    ``groups``: the stuck elements (frictions by index, a stop's limit in contact by
    ``number of frictions + its index``) as lists of ``(element, alpha)`` with
    ``gradient = alpha * gradient of the group's first element``; ``free``: elements
    with no positive magnitude; ``flags``: the side (+1/-1, 0 unlocked) of each
    switching function, which locks the branches of the equations for the segment
    (:class:`mechdyn.compile.generate.Switches`)."""
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


class StateView:
    """The numbers of the switching elements at one state, frictions first (``0..K-1``)
    then the stops' limits: gradients, sliding rates, biases, magnitudes, gaps."""

    def __init__(self, modes, terms):
        n, c = modes.n, modes.contacts
        self.n, self.terms, self.gears, self.kinds = n, terms, modes.gears, modes.kinds
        self.mass, self.forcing = terms["mass"], terms["forcing"]
        self.gradients, self.rates, self.biases = (
            terms[f"friction_{part}"] if not c else terms[f"contact_{part}"] if not modes.k
            else np.concatenate([terms[f"friction_{part}"], terms[f"contact_{part}"]])
            for part in ("gradient", "rate", "bias"))
        self.magnitude, self.peak = terms["friction_magnitude"], terms["friction_peak"]
        self.release, self.gaps = terms["friction_release"], terms["contact_gap"]

    def kind(self, element) -> str:
        return self.kinds[element]

    def gear_of(self, element) -> int:
        return next(i for i, (_, k, _) in enumerate(self.gears) if k == element)

    def law(self, i) -> LossLaw:
        return LossLaw(*[float(v) for v in self.terms["gear_law"][i]])

    def tau_tolerance(self, i) -> float:
        """Mesh moments this small count as zero (a self-locking gear's corner)."""
        return 1e-10 * (1.0 + float(np.abs(self.forcing).max(initial=0.0)))


class FrictionModes:
    """The friction elements, one-way clutches, stops and lossy gears of a compiled
    scene and the decisions about their modes.

    ``compiled``: the :class:`~mechdyn.compile.compiler.CompiledScene`; ``base``: the parameter
    values (``p`` without the friction signs); ``span``: the length of the run (the
    scale of a bouncing contact's remaining flights, :mod:`mechdyn.simulate.contacts`)."""

    def __init__(self, compiled, base, span=1.0):
        meta = compiled.meta
        self.c, self.base, self.span = compiled, list(base), span
        self.factor = compiled.mass_factor(self.base)    # a constant M's, else []
        self.n, self.k = compiled.dof, len(compiled.frictions)
        self.names = compiled.frictions
        self.contact_names = meta.get("contacts", [])
        self.contact_elements = meta.get("contact_elements", [])
        self.contacts = len(self.contact_names)
        self.kinds = meta.get("friction_kinds", ["friction"] * self.k) + \
            ["contact"] * self.contacts
        self.gears = [tuple(g) for g in meta.get("gears", [])]
        self.frozen = list(compiled.frozen) + list(meta.get("contact_frozen", []))
        self.lines = {}                   # the gear lines last used: tried first
        self._last_view = None            # (t, y, p) and the StateView there
        self.loop_projection = None       # a compiled assembly.project, where loaded
        self._p = {}                      # p by (signs, flags): see p

    @property
    def size(self) -> int:
        """Frictions and stop limits together."""
        return self.k + self.contacts

    def p(self, mode: Mode) -> list:
        """The parameter vector of a mode: values, friction signs, branch flags (and a
        constant mass matrix's factor)."""
        key = (mode.signs, mode.flags)
        p = self._p.get(key)                # several times per segment: kept per run
        if p is None:
            p = self._p[key] = self.base + list(mode.signs or [0.0] * self.k) + \
                list(mode.flags or [0.0] * self.c.flags) + self.factor
        return list(p)

    def view(self, t, y, mode) -> StateView:
        """The :class:`StateView` at ``(t, y)`` in ``mode``; the last one is kept (an
        event's impact, mode decision and gap offsets look at the same state)."""
        key = (float(t), np.asarray(y, dtype=float).tobytes(),      # what p depends on
               mode.signs if any(mode.signs) else (), mode.flags if any(mode.flags) else ())
        last = self._last_view
        if last is not None and last[0] == key:
            return last[1]
        view = StateView(self, self.c.terms(t, y, self.p(mode)))
        self._last_view = (key, view)
        return view

    def solve(self, view, mode):
        """The constrained equations of a mode (:func:`mechdyn.simulate.constrained.solve`)."""
        solution = solve(view, mode, self.lines)
        self.lines.update(solution.lines)
        return solution

    # ------------------------------------------------------------ decisions
    def decide(self, t, y, flags=(), at_rest=(), events=None, touching=()) -> Mode:
        """The mode at a state: sliding elements keep sliding the way they move;
        elements at rest (and those in ``at_rest``, whose sliding speed just reached
        zero) and the stops' limits in ``touching`` (:func:`mechdyn.simulate.contacts.jump`) stick
        where the holding force they need fits their capacity, else slide the way the
        loads push. Releases are decided here too, at the state just past a release
        event. Decisions are appended to ``events`` as :class:`Event`."""
        flags = tuple(flags)
        if not self.size:
            return Mode(flags=flags)
        events = events if events is not None else []
        view = self.view(t, y, Mode(flags=flags))
        rest = _AT_REST * (1.0 + largest_magnitude(y[self.n:]))
        signs, free, candidates = [0.0] * self.k, set(), []
        for k in range(self.k):
            kind, rate = self.kinds[k], view.rates[k]
            moving = abs(rate) > rest and k not in at_rest
            if kind == "friction" and view.magnitude[k] <= 0:
                free.add(k)
            elif moving and (kind != "one_way" or rate > 0):
                signs[k] = math.copysign(1.0, rate)
            else:
                candidates.append(k)
        candidates += [e for e in sorted(touching) if view.rates[e] <= rest]
        held = self._holdable(view, candidates)
        for k in set(candidates) - set(held):     # cannot hold here: keeps sliding
            if k < self.k:
                signs[k] = 1.0 if self.kinds[k] == "one_way" else self._drift_sign(view, k)
        while True:
            groups = _parallel_groups(self._reduced(view), held)
            if not groups:
                break
            trial = Mode(tuple(signs), tuple(groups), flags=flags)
            sliding = self.view(t, y, trial)           # the forcing with these signs
            solution = self.solve(sliding, trial)
            worst, worst_margin, way = None, 0.0, 0
            for group, force in zip(groups, solution.holding):
                margin, direction = group_check(sliding, group, force, solution)
                if margin < worst_margin:
                    worst, worst_margin, way = group, margin, direction
            if worst is None:
                break
            for k, alpha in worst:
                held.remove(k)
                if k >= self.k:
                    name, limit = self._limit(k)
                    events.append(Event(t, "lift", name, limit + "the loads pull it off"))
                    continue
                signs[k] = 1.0 if self.kinds[k] == "one_way" else \
                    way * math.copysign(1.0, alpha)
                events.append(Event(t, "slip", self.names[k], f"slides {_way(signs[k])}"))
        groups = _parallel_groups(self._reduced(view), held)
        for e in sorted(set(at_rest) & set(held)):
            if e >= self.k:
                name, limit = self._limit(e)
                events.append(Event(t, "contact", name, limit + "at rest on it"))
        return Mode(tuple(signs), tuple(tuple(g) for g in groups), frozenset(free), flags)

    def _limit(self, element) -> tuple:
        """A stop limit's element name and the start of a detail naming the limit."""
        label = self.contact_names[element - self.k]
        return self.contact_elements[element - self.k], f"{label.rsplit('.', 1)[1]} limit: "

    def _reduced(self, view):
        """The gradients on the motions the closed loops allow."""
        if not len(view.terms["constraint_gradient"]):
            return view.gradients                     # no loops: every motion
        return view.gradients @ allowed_motions(view.terms["constraint_gradient"], self.n)

    def _holdable(self, view, candidates) -> list:
        """The candidates whose constraint can act: ``G M^-1 G'`` not negligible, on the
        motions the closed loops allow (mass and gradient reduced to them)."""
        loops = len(view.terms["constraint_gradient"])
        basis = allowed_motions(view.terms["constraint_gradient"], self.n) if loops else None
        mass = basis.T @ view.mass @ basis if loops else view.mass
        held = []
        for k in candidates:
            g = view.gradients[k] @ basis if loops else view.gradients[k]
            weight = float(g @ np.linalg.solve(mass, g))
            scale = float(g @ g) / max(float(np.max(np.abs(np.diag(mass)))), 1e-300)
            if weight > _CANNOT_HOLD * scale and weight > 0:
                held.append(k)
        return held

    def _drift_sign(self, view, k) -> float:
        """The way an element that cannot hold will slide: the sign of its sliding
        acceleration, which its own force does not change (``G M^-1 G' = 0``)."""
        bias = view.biases[k]
        return math.copysign(1.0, bias) if bias != 0 else 1.0

    # ---------------------------------------------------------- dynamics
    def multipliers(self, t, y, mode):
        """Closed loops: their constraint forces ``lambda`` (``M a = f + G' lambda``),
        with the stuck frictions' constraints in the same system."""
        return self.solve(self.view(t, y, mode), mode).loops

    def forces(self, t, y, mode):
        """Accelerations, the force of every element along its ``along`` (frictions and
        stop limits: the holding share of stuck ones, ``-sign * magnitude`` of sliding
        ones, minus the loss moment of a sliding gear, 0 of free and open ones) and the
        :class:`~mechdyn.simulate.constrained.Solution`."""
        view = self.view(t, y, mode)
        solution = self.solve(view, mode)
        a = np.array(solution.a)
        for k in mode.stuck:
            if self.frozen[k] >= 0:
                a[self.frozen[k]] = 0.0
        forces = np.zeros(self.size)
        forces[:self.k] = [-s * max(m, 0.0) for s, m in zip(mode.signs or [0.0] * self.k,
                                                           view.magnitude)]
        for i, loss in solution.losses.items():
            forces[self.gears[i][1]] = -loss
        for group, force in zip(mode.groups, solution.holding):
            for (k, _), share in zip(group, shares(view, group, force, solution)):
                forces[k] = share
        return a, forces, solution

    def accelerations(self, t, y, mode):
        """Accelerations and the friction force of every element (see :meth:`forces`)."""
        a, forces, _ = self.forces(t, y, mode)
        return a, forces

    def rhs(self, mode):
        """``fun(t, y)`` of a mode with stuck elements or a lossy gear (``None``
        otherwise: the generated ``rhs``, which holds closed loops itself): the
        constrained accelerations; coordinates held by a stuck element keep exactly
        zero speed."""
        if not mode.groups and not self.gears:
            return None
        n, p = self.n, self.p(mode)
        frozen = [self.frozen[k] for k in mode.stuck if self.frozen[k] >= 0]

        def constrained(t, y):
            view = StateView(self, self.c.terms(t, y, p))
            dy = np.concatenate([y[n:], self.solve(view, mode).a])
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
        if self.c.constraints and self.loop_projection is not None:
            y = self.loop_projection(t, y, self.p(mode))
        elif self.c.constraints:
            from mechdyn.simulate.assembly import project
            y = project(self.c, t, y, self.p(mode))
        if not mode.groups:
            return y
        view = self.view(t, y, mode)
        leaders = mode.leaders
        g = view.gradients[leaders]
        if self.c.constraints:
            loops = view.terms["constraint_gradient"]
            held = np.vstack([loops, g])
            residual = np.concatenate([loops @ y[self.n:] + view.terms["constraint_rate"],
                                       view.rates[leaders]])
            y[self.n:] -= np.linalg.lstsq(held, residual, rcond=None)[0]
        else:
            held = g
            w = np.linalg.solve(view.mass, g.T)
            y[self.n:] -= w @ np.linalg.solve(g @ w, view.rates[leaders])
        for k in mode.stuck:
            if self.frozen[k] >= 0:
                y[self.n + self.frozen[k]] = 0.0
        if np.linalg.matrix_rank(held) == self.n:
            y[self.n:] = 0.0    # nothing can move: at rest exactly, not within rounding
        return y

    # ------------------------------------------------------------- events
    def watched(self, mode, t0=None, y0=None) -> list:
        """``(kind, element, direction, offset)`` of the events of a mode: ``stick`` (a
        sliding speed falls through zero against its sign), ``release`` (a group's
        holding margin falls through zero), ``engage`` (a free element's magnitude rises
        through zero), ``gap`` (an open stop limit's gap falls below its value at the
        segment's start ``(t0, y0)`` where that is negative by rounding, else below 0)."""
        out = [("stick", k, -sign, 0.0) for k, sign in enumerate(mode.signs) if sign != 0]
        out += [("release", i, -1, 0.0) for i in range(len(mode.groups))]
        out += [("engage", k, 1, 0.0) for k in sorted(mode.free)]
        closed = set(mode.stuck)
        open_limits = [j for j in range(self.contacts) if self.k + j not in closed]
        if open_limits:
            gaps = self.view(t0, y0, mode).gaps if y0 is not None else \
                np.zeros(self.contacts)
            out += [("gap", j, -1, min(float(gaps[j]), 0.0)) for j in open_limits]
        return out

    def event_values(self, t, y, mode, watched) -> list:
        """The values of the :meth:`watched` event functions at a state."""
        if not watched:
            return []
        view = self.view(t, y, mode)
        solution = self.solve(view, mode) if mode.groups else None
        out = []
        for kind, index, _, offset in watched:
            if kind == "stick":
                out.append(view.rates[index])
            elif kind == "release":
                out.append(group_check(view, mode.groups[index],
                                       solution.holding[index], solution)[0])
            elif kind == "engage":
                out.append(view.magnitude[index])
            else:
                out.append(view.gaps[index] - offset)
        return out


def allowed_motions(loop_gradients, n):
    """A basis of the speeds the closed loops allow (the null space of their
    gradients); the identity without loops."""
    if not len(loop_gradients):
        return np.eye(n)
    _, singular, vt = np.linalg.svd(loop_gradients)
    rank = int(np.sum(singular > 1e-12 * max(singular[0], 1e-300)))
    return vt[rank:].T


def largest_magnitude(values) -> float:
    """The largest ``|value|`` of a (finite) array, 0 for none: the scale of the
    tolerances above (a Python max: numpy's costs more on a few numbers).

    >>> largest_magnitude(np.array([1.5, -2.0])), largest_magnitude(np.zeros(0))
    (2.0, 0.0)
    """
    return float(max(map(abs, values.tolist()), default=0.0))


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

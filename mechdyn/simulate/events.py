"""Events: where a watched function of the state crosses zero, located on a step.

Each watched function ``g_i(t, y)`` has a direction (+1 rising, -1 falling, 0 either) and
a rule for a start exactly at zero:

- ``zero_is_before=True`` (friction: a release margin, a sliding speed): zero counts as
  the side *before* the crossing, so a function that starts at zero and moves across
  fires at once (a clutch with no capacity releases as soon as a load appears);
- ``zero_is_before=False`` (stop conditions, switching functions): a function at zero is
  watched from the side it moves to, so a condition met exactly at the start stops the
  run at its next crossing, not at the start.

A crossing is located on the step's polynomial by bracketing (Illinois) to a few units of
rounding in ``t``, and the event time is the *end* of the final bracket: the first time at
which the function is on the far side. The state there is the one the new mode sees (the
right limit), so a release next to a step change of the load slides the way the load
pushes after the step.

>>> import numpy as np
>>> watch = EventWatch(lambda t, y: np.array([y[0] - 0.5]), [-1], [False])
>>> watch.start(0.0, np.array([1.0]))
>>> t, y, fired = watch.check(0.0, 1.0, np.array([0.0]), np.array([[1.0], [-1.0]]))
>>> round(t, 12), fired                                     # y = 1 - t reaches 0.5
(0.5, [0])
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Event", "EventWatch", "locate"]

_EPS = np.finfo(float).eps


@dataclass(frozen=True)
class Event:
    """Something that happened at ``time``: ``kind`` ("stick", "slip", "engage", "free",
    "impact", "contact", "lift", "end"), the element or condition ``name``, and a
    ``detail`` in words. An impact carries its impulse as ``value`` and, on the first
    impact event of an instant, the kinetic energy the velocity jump took as ``energy``.

    Examples
    --------
    >>> import mechdyn as md
    >>> model = md.load_model("shoe_brake")
    >>> res = model.mechanism.simulate(model.scenes["braking"], model.params)
    >>> res.events
    [stick shoe at t = 50 s, end stopped(phi) at t = 50 s]
    >>> stick = res.events[0]
    >>> stick.kind, stick.name, round(stick.time, 9)
    ('stick', 'shoe', 50.0)
    """
    time: float
    kind: str
    name: str
    detail: str = ""
    value: float | None = None
    energy: float | None = None

    def __str__(self):
        return f"t = {self.time:.6g} s: {self.kind} {self.name} ({self.detail})"

    def __repr__(self):
        return f"{self.kind} {self.name} at t = {self.time:.6g} s"


class EventWatch:
    """The event functions of one segment: ``values(t, y) -> array``, a direction per
    function, and the zero rule per function (see the module docstring). ``interior``
    extra evaluations inside each step catch a function that crosses and re-crosses
    within one step (used where steps are long and the state barely moves)."""

    def __init__(self, values, directions, zero_is_before, interior=0):
        self.values = values
        self.directions = np.asarray(directions, dtype=float)
        self.zero_is_before = np.asarray(zero_is_before, dtype=bool)
        self.interior = interior
        self.muted = np.zeros(len(self.directions), dtype=bool)
        self.side = np.zeros(len(self.directions))
        self.start_sides = {}

    def sides(self, g):
        """+1/-1 by the sign of ``g``; at zero the side before a crossing (rule
        ``zero_is_before``) or 0 (not yet known)."""
        side = np.sign(g)
        zero = side == 0
        side[zero & self.zero_is_before] = -self.directions[zero & self.zero_is_before]
        return side

    def start(self, t, y):
        """The sides at the start; ``start_sides`` (index -> side) overrides some (a
        locked branch is watched from the side it locks)."""
        self.side = self.sides(np.asarray(self.values(t, y), dtype=float))
        for i, side in self.start_sides.items():
            self.side[i] = side

    def check(self, t_old, t_new, y_new, coefficients):
        """The earliest event within the step ``[t_old, t_new]`` (``coefficients``: the
        step's polynomial), as ``(t, y, indices)`` with every event at that instant; or
        None after updating the known sides."""
        h = t_new - t_old
        if not len(self.directions):
            return None

        def state(t):
            x = (t - t_old) / h if h else 0.0
            out = coefficients[-1]
            for c in coefficients[-2::-1]:
                out = out * x + c
            return out
        points = [t_old + h * k / (self.interior + 1) for k in range(1, self.interior + 1)]
        for t_sample in points + [t_new]:
            y_sample = y_new if t_sample == t_new else state(t_sample)
            side = self.sides(np.asarray(self.values(t_sample, y_sample), dtype=float))
            crossing = self._crossings(side)
            if crossing.any():
                return self._earliest(crossing, t_old, t_sample, state)
            known = side != 0
            self.side[known] = side[known]
        return None

    def _crossings(self, side):
        before = self.side
        crossed = (before != 0) & (side != before) & ~self.muted
        allowed = (self.directions == 0) | (side == self.directions) | \
            ((side == 0) & (before == -self.directions))
        return crossed & allowed

    def _earliest(self, crossing, t_lo, t_hi, state):
        times = {}
        for i in np.flatnonzero(crossing):
            def g(t, i=i):
                return float(self.values(t, state(t))[i])
            times[i] = locate(g, t_lo, t_hi, self.side[i], self.zero_is_before[i],
                              self.directions[i])
        first = min(times.values())
        window = 8 * _EPS * max(abs(t_lo), abs(t_hi))   # relative: any time scale
        fired = sorted(i for i, t in times.items() if t - first <= window)
        return first, state(first), [int(i) for i in fired]


def locate(g, t_lo, t_hi, side_before, zero_is_before, direction, iterations=200):
    """The first time in ``(t_lo, t_hi]`` at which ``g`` has left ``side_before``:
    bracketing by the Illinois method to a few units of rounding; returns the right end
    of the final bracket."""
    def leaves(value):
        if value == 0:
            return not (zero_is_before and direction != 0)
        return np.sign(value) != side_before

    g_lo, g_hi = g(t_lo), g(t_hi)
    scale = max(abs(t_lo), abs(t_hi))   # relative to the bracket: runs of 1e-28 s too
    if leaves(g_lo):            # left the side at the very start of the bracket
        return t_lo
    f_lo, f_hi, kept = g_lo, g_hi, 0     # f: the values the secant uses (Illinois-scaled)
    for iteration in range(iterations):
        width = t_hi - t_lo
        if width <= 4 * _EPS * scale:
            break
        secant = f_hi != f_lo and np.isfinite(f_lo - f_hi) and f_hi != 0
        if secant and iteration % 4 != 3:        # every fourth step bisects: a guarantee
            t_mid = t_hi - f_hi * width / (f_hi - f_lo)
            t_mid = min(max(t_mid, t_lo + 1e-3 * width), t_hi - 1e-3 * width)
        else:
            t_mid = t_lo + 0.5 * width
        g_mid = g(t_mid)
        if leaves(g_mid):
            t_hi, f_hi = t_mid, g_mid
            kept = kept - 1 if kept < 0 else -1
            if kept <= -2:
                f_lo *= 0.5                       # Illinois: the far end stayed twice
        else:
            t_lo, f_lo = t_mid, g_mid
            kept = kept + 1 if kept > 0 else 1
            if kept >= 2:
                f_hi *= 0.5
    return t_hi

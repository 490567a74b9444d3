"""Events of time alone: stop conditions and switching functions that depend on ``t``
(and parameters) only.

Their crossings are known without the state, so they are not looked for at the ends of
the solver's steps (a machine at rest takes 10 s steps and would skip them): each such
function is sampled once per run on a grid over the run, at most ``span / 512`` apart and
at most 1/32 of the shortest period of a sine or cosine of ``t`` in the scene's events
and loads; every sign change on the grid is located by bracketing to a few units of
rounding (:func:`mechdyn.simulate.events.locate`). A segment then ends exactly at the
next crossing in the watched direction, on both backends. Two crossings closer together
than the grid spacing (a touch of the value) can be missed; docs/hard-cases.md.

>>> import numpy as np
>>> times = TimeEvents(lambda t: np.array([np.cos(t) - 0.5]), 0.0, 10.0, [2 * np.pi])
>>> t, fired = times.next(0.0, [(0, +1, 0)])          # cos t = 1/2 rising: 5 pi / 3
>>> round(t / np.pi, 12), fired
(1.666666666667, [0])
"""
from __future__ import annotations

import numpy as np

from mechdyn.simulate.events import locate

__all__ = ["TimeEvents", "time_events", "GRID", "PER_PERIOD"]

GRID = 512                # grid points over the run at least
PER_PERIOD = 32           # ... and per shortest period of the sines and cosines of t
_MAX_POINTS = 200_000     # a run of very many periods: the grid is capped
_SAME_INSTANT = 8 * np.finfo(float).eps


def time_events(compiled, p, y0, t_start, t_end, periods):
    """The :class:`TimeEvents` of a run of ``compiled`` (its generated ``timed`` function:
    the stop conditions and switches of t alone), or None when it has none."""
    timed = compiled.meta.get("timed", [])
    if not timed:
        return None
    raw, y0 = compiled.raw["timed"], [float(v) for v in y0]

    def values(t):
        out = [0.0] * len(timed)
        raw(t, y0, p, out)
        return out
    key = (compiled.key, tuple(p), float(t_start), float(t_end), tuple(periods))
    signs, crossings = _SAMPLED.get(key, (None, {}))
    events = TimeEvents(values, t_start, t_end, periods, timed, signs=signs)
    events.crossings = crossings
    if len(_SAMPLED) >= 64:
        _SAMPLED.clear()
    _SAMPLED[key] = (events.signs, crossings)
    return events


_SAMPLED: dict = {}  # (scene, p, span, periods) -> the signs on the grid and the crossings
                     # located: every run of a scene with these values finds the same


class TimeEvents:
    """The crossings of ``values(t) -> array`` (one entry per function of time) over
    ``[t_start, t_end]``; ``periods``: the periods that set the grid spacing;
    ``indices``: the entries of the scene's ``events`` function they are."""

    def __init__(self, values, t_start, t_end, periods=(), indices=(), signs=None):
        self.values, self.indices = values, list(indices)
        span = max(t_end - t_start, 0.0)
        spacing = min([span / GRID] + [p / PER_PERIOD for p in periods if p > 0])
        points = int(min(np.ceil(span / spacing), _MAX_POINTS)) if spacing > 0 else 1
        self.grid = np.linspace(t_start, t_end, points + 1)
        self.signs = signs if signs is not None else \
            np.sign(np.array([values(t) for t in self.grid], dtype=float))
        self.crossings = {}     # the crossings located, by bracket, side and direction

    def next(self, t0, watched):
        """The earliest crossing after ``t0`` of the functions ``watched``: ``(position,
        direction, side)`` entries (position in ``values``, +1/-1/0, the side a zero
        counts as at ``t0`` or 0: the side it moves to). Returns ``(t, fired)`` with the
        indices of ``watched`` firing at ``t``, or ``(inf, [])``."""
        times = {k: self._next(t0, *entry) for k, entry in enumerate(watched)}
        first = min(times.values(), default=np.inf)
        if first == np.inf:
            return first, []
        window = _SAME_INSTANT * max(1.0, abs(first))
        return first, sorted(k for k, t in times.items() if t - first <= window)

    def segment_end(self, t0, t_end, watched):
        """Where a segment from ``t0`` ends: the next crossing of a watched event (a
        :class:`~mechdyn.simulate.segments.Watched` marked ``timed``) and the indices
        of ``watched`` firing there, or ``(t_end, [])``."""
        timed = [(k, w) for k, w in enumerate(watched) if w.timed]
        if not timed:
            return t_end, []
        t_next, fired = self.next(t0, [(self.indices.index(w.index), w.direction, w.side)
                                       for _, w in timed])
        if t_next > t_end:
            return t_end, []
        return t_next, [timed[k][0] for k in fired]

    def _next(self, t0, position, direction, side):
        def g(t):
            return float(self.values(t)[position])
        side = side or np.sign(g(t0))
        first = np.searchsorted(self.grid, t0, side="right")
        column = self.signs[first:, position]
        nonzero = np.flatnonzero(column)            # the grid points with a side
        sides = column[nonzero]
        before = np.concatenate([[side], sides[:-1]])
        crossed = (before != 0) & (sides != before) & ((direction == 0) | (sides == direction))
        if not crossed.any():
            return np.inf
        j = int(np.argmax(crossed))
        t_old = t0 if j == 0 else self.grid[first + nonzero[j - 1]]
        bracket = (position, float(t_old), int(first + nonzero[j]), float(before[j]),
                   direction)
        if bracket not in self.crossings:
            self.crossings[bracket] = float(locate(g, t_old, self.grid[first + nonzero[j]],
                                                   before[j], False, direction))
        return self.crossings[bracket]

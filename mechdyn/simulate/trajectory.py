"""The integrated motion: segments of steps, each step with its interpolating polynomial.

Every solver's dense output is stored in one form: for the step ``[t_k, t_k + h_k]`` the
coefficients ``c_0..c_d`` (one row of states each) of ``y(t) = sum_j c_j x^j`` with
``x = (t - t_k) / h_k``. Evaluating many times is then one ``searchsorted`` and one Horner
scheme over arrays, whatever the method that made the steps.

A segment is a stretch of integration with one friction mode and one method; at the
boundary between two segments the state may jump (an impulse that makes a stuck
friction's sliding speed exactly zero), and the trajectory takes the later segment's value
there (the right limit).

>>> import numpy as np
>>> seg = Segment(0.0, [1.0], mode=(), method="demo")
>>> seg.add(2.0, [5.0], [[1.0], [0.0], [4.0]])       # y = 1 + 4 x^2 on [0, 2]
>>> Trajectory([seg]).at(np.array([0.0, 1.0, 2.0]))[0].tolist()
[1.0, 2.0, 5.0]
"""
from __future__ import annotations

import numpy as np

from mechdyn.errors import MechdynError

__all__ = ["Segment", "Trajectory"]


class Segment:
    """The steps of one friction mode integrated by one method.

    ``mode`` is the friction mode (signs per friction element); ``method`` the solver's
    name. Steps are appended with :meth:`add` (one) or :meth:`extend` (arrays of many,
    kept as they come: a compiled chunk costs no Python loop).
    """

    def __init__(self, t0, y0, mode, method):
        self.mode, self.method = mode, method
        y0 = np.asarray(y0, dtype=float)
        self._chunks = [(np.array([float(t0)]), y0[None, :].copy(), np.zeros((0, 1, len(y0))))]
        self._t_end, self._y_end, self._steps = float(t0), y0, 0
        self._frozen = None

    def add(self, t, y, coefficients):
        """Append one step ending at ``(t, y)`` with its polynomial coefficients
        (``(degree + 1, states)``, in ``x = (t - t_start) / h``)."""
        if t == self._t_end:
            return
        y = np.asarray(y, dtype=float)
        self._chunks.append((np.array([float(t)]), y[None, :],
                             np.asarray(coefficients, dtype=float)[None]))
        self._t_end, self._y_end, self._steps = float(t), y, self._steps + 1
        self._frozen = None

    def extend(self, times, states, coefficients):
        """Append many steps at once: ``times (k,)``, ``states (k, m)``, coefficients
        ``(k, degree + 1, m)``."""
        if not len(times):
            return
        self._chunks.append((np.asarray(times, dtype=float), np.asarray(states, dtype=float),
                             np.asarray(coefficients, dtype=float)))
        self._t_end, self._y_end = float(times[-1]), np.asarray(states[-1], dtype=float)
        self._steps += len(times)
        self._frozen = None

    def settle(self, y):
        """Replace the last point's state by ``y``, the same state after an event's
        projection (a stuck element's speed exactly zero): the run ends there."""
        t, states, c = self._chunks[-1]
        states = np.array(states, dtype=float)
        states[-1] = y
        self._chunks[-1] = (t, states, c)
        self._y_end, self._frozen = states[-1], None

    @property
    def t_start(self):
        return float(self._chunks[0][0][0])

    @property
    def t_end(self):
        return self._t_end

    @property
    def y_end(self):
        return self._y_end

    def __len__(self):
        """The number of steps."""
        return self._steps

    def pieces(self):
        """The steps as stored, ``(t, y, c)`` per piece (a compiled chunk, or the steps
        concatenated once): no copy of the coefficients."""
        if len(self._chunks) > 1 and all(len(t) == 1 for t, _, _ in self._chunks[1:]):
            self.arrays()                     # one-step pieces (scipy): joined once
        out, start = [], self._chunks[0][0][-1:]
        for t, y, c in self._chunks:
            if len(c):
                out.append((np.concatenate([start, t]) if len(t) == len(c) else t, c))
            start = t[-1:]
        return out

    def points(self):
        """Step times ``(k + 1,)`` and states ``(k + 1, m)``, without coefficients."""
        if len(self._chunks) == 1:
            return self._chunks[0][0], self._chunks[0][1]
        return (np.concatenate([t for t, _, _ in self._chunks]),
                np.concatenate([y for _, y, _ in self._chunks]))

    def arrays(self):
        """``(t, y, c)``: step times ``(k + 1,)``, states ``(k + 1, m)`` and coefficients
        ``(k, d + 1, m)`` padded with zeros to the largest degree."""
        if self._frozen is None:
            degree = max(c.shape[1] for _, _, c in self._chunks)
            m = self._chunks[0][1].shape[1]
            coefficients = np.zeros((self._steps, degree, m))
            row = 0
            for _, _, c in self._chunks:
                coefficients[row:row + len(c), :c.shape[1]] = c
                row += len(c)
            self._frozen = (np.concatenate([t for t, _, _ in self._chunks]),
                            np.concatenate([y for _, y, _ in self._chunks]), coefficients)
            self._chunks = [self._frozen]
        return self._frozen

    def truncate(self, t_keep):
        """Drop the steps that end after ``t_keep`` (the start is always kept)."""
        t, y, c = self.arrays()
        keep = max(int(np.searchsorted(t, t_keep, side="right")), 1)
        self._frozen = (t[:keep], y[:keep], c[:keep - 1])
        self._chunks = [self._frozen]
        self._t_end, self._y_end, self._steps = float(t[keep - 1]), y[keep - 1], keep - 1


class Trajectory:
    """The segments of a run, evaluated anywhere by their step polynomials."""

    def __init__(self, segments=()):
        self.segments: list[Segment] = list(segments)
        self._stacked = None

    def add(self, segment: Segment) -> Segment:
        self.segments.append(segment)
        self._stacked = None
        return segment

    def truncate(self, t_keep):
        """Drop everything after the step point ``t_keep``."""
        self.segments = [s for s in self.segments if s.t_start <= t_keep] or self.segments[:1]
        self.segments[-1].truncate(t_keep)
        self._stacked = None

    def changed(self):
        """Forget the stacked arrays (steps were added to the last segment)."""
        self._stacked = None

    @property
    def steps(self) -> int:
        return sum(len(s) for s in self.segments)

    def points(self):
        """Times ``(K,)``, states ``(m, K)`` and segment index ``(K,)`` of every step
        point; a boundary between segments appears once, with the later segment's
        state."""
        times, states, owner = [], [], []
        for index, segment in enumerate(self.segments):
            t, y = segment.points()
            if times and len(t) and t[0] == times[-1][-1]:
                times[-1], states[-1], owner[-1] = times[-1][:-1], states[-1][:-1], owner[-1][:-1]
            times.append(t)
            states.append(y)
            owner.append(np.full(len(t), index))
        if not times:
            return np.zeros(0), np.zeros((0, 0)), np.zeros(0, dtype=int)
        return np.concatenate(times), np.concatenate(states).T, np.concatenate(owner)

    def _pieces(self):
        """``(starts, pieces)``: the start time of every piece of every segment and the
        pieces ``(segment index, t, c)``, built once per change."""
        if self._stacked is None:
            pieces = [(index, t, c) for index, segment in enumerate(self.segments)
                      for t, c in segment.pieces()]
            self._stacked = (np.array([t[0] for _, t, _ in pieces]), pieces)
        return self._stacked

    def at(self, times, with_segments=False):
        """States at ``times`` (shape ``(m, len(times))``) from the step polynomials, and
        with ``with_segments`` the index of the segment of each time. At a boundary
        between segments the later segment's value (the right limit)."""
        times = np.atleast_1d(np.asarray(times, dtype=float))
        first = self.segments[0].t_start
        last = self.segments[-1].t_end
        slack = 1e-12 * max(1.0, abs(first), abs(last))
        outside = (times < first - slack) | (times > last + slack)
        if np.any(outside):
            bad = times[outside][0]
            raise MechdynError(f"t = {bad} lies outside the simulated interval "
                               f"[{first}, {last}]")
        m = len(self.segments[-1].y_end)
        out = np.repeat(self.segments[-1].y_end[:, None], len(times), axis=1)
        owners = np.full(len(times), len(self.segments) - 1)
        starts, pieces = self._pieces()
        if pieces:
            which = np.clip(np.searchsorted(starts, times, side="right") - 1, 0,
                            len(pieces) - 1)
            at_end = times >= last
            for j in np.unique(which[~at_end]):
                chosen = np.flatnonzero((which == j) & ~at_end)
                index, t, c = pieces[j]
                out[:, chosen] = _horner(t, c, times[chosen], m)
                owners[chosen] = index
        return (out, owners) if with_segments else out


def _horner(t, c, times, m):
    """The step polynomials ``c`` over the steps ``t`` at ``times`` (all inside them)."""
    k = np.clip(np.searchsorted(t, times, side="right") - 1, 0, len(c) - 1)
    x = np.clip((times - t[k]) / (t[k + 1] - t[k]), 0.0, 1.0)[:, None]
    value = c[k, -1]
    for j in range(c.shape[1] - 2, -1, -1):
        value = value * x + c[k, j]
    return value.T

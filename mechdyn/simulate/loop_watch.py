"""Closed loops during a run: drift back onto the loops, and their singular positions.

Integrating ``G a = -bias`` keeps the loops closed only to the tolerance, so the state
drifts off them slowly. After a step where the drift of the positions ``|g|`` or of the
speeds ``|G u + dg/dt|`` exceeds rtol times the loops' size, the segment ends there and
the state is projected back (measured over 100 revolutions of a free four-bar: largest
``|g|`` 3e-11 m, ``T + V`` within 3e-9, 41 projections and no extra steps; Baumgarte
stabilisation drifts less but needs a rate chosen per problem and costs 10 % more
steps).

Where the loops lose rank (a change point: every link in line) the motion is not
determined. All ``m x m`` minors of ``G`` vanish there and one of them changes sign, so
the largest minor at a segment's start is watched as an event; where it crosses zero
and every minor is below :data:`~mechdyn.compile.loop_code.LOOP_MARGIN` times its size at the
start, the run stops with :class:`~mechdyn.compile.loop_code.LoopSingularError` naming the loop
and the independent coordinates (otherwise a new segment watches the largest minor
there). Without loops every method here does nothing.

Approaching a change point the steps the solver accepts grow inaccurate (the loop solve's
error grows like ``eps / margin^2``, with the rank margin of ``G``,
:func:`~mechdyn.compile.loop_numeric.rank_margin`, about the distance to it), so a
run stops with :class:`LoopSingularError` where the margin falls below ``sqrt(eps /
rtol)`` (the loop solve's rounding above rtol: a crank may even turn back, short of the
change point, on rounding), and :meth:`LoopWatch.trim` keeps only the points up to the
last one whose margin is at least ten times that (that error below rtol / 100); the
error says how far short of the singular position they end.
"""
from __future__ import annotations

import math

import numpy as np

from mechdyn.compile.loop_numeric import LOOP_MARGIN, LoopSingularError, rank_margin

__all__ = ["LoopWatch"]

_PREFILTER = 0.1      # the rank margin is computed where G's largest minor falls below
                      # this fraction of its size at the start (a minor is at most about
                      # sqrt(n) margin times the largest column norm squared)


class LoopWatch:
    """The closed loops of a compiled scene, watched during a run."""

    def __init__(self, compiled, rtol):
        self.c, self.rtol = compiled, rtol
        self.scale = None               # size of G's largest minor at the assembled start
        self._floor = math.sqrt(np.finfo(float).eps / rtol)

    def limits(self, y0, p) -> tuple:
        """The largest drifts of the positions and speeds a segment starting at ``y0``
        allows (``rtol`` times the loops' size). Plain Python: once per segment, on
        short lists."""
        n, m = self.c.dof, len(self.c.constraints)
        y0 = y0.tolist() if type(y0) is np.ndarray else list(y0)
        grads = self.c.closure(0.0, y0, p)[m:m + m * n]
        size = float(max(map(abs, grads)))
        speed_scale = 1.0 + float(max(map(abs, y0[n:])))
        return self.rtol * size, self.rtol * size * speed_scale

    def margin_limits(self) -> tuple:
        """The size of the largest minor below which the rank margin is computed, and
        the margin's floor (:meth:`check_margin`)."""
        return (np.inf if self.scale is None else _PREFILTER * self.scale), self._floor

    def drifted(self, y0, p):
        """``drift(t, y) -> bool`` for a segment starting at ``y0``, or None."""
        if not self.c.constraints:
            return None
        position_limit, speed_limit = self.limits(y0, p)

        def drift(t, y):
            position, speed = self.c.drift(t, y, p)
            if position > position_limit or speed > speed_limit:
                return True
            self.check_margin(t, y, p)
            return False
        return drift

    def floor(self):
        """The rank margin of ``G`` below which the loop solve's rounding (about
        ``eps / margin^2``) exceeds rtol."""
        return self._floor

    def check_margin(self, t, y, p):
        """Raise :class:`LoopSingularError` where the rank margin of ``G`` falls below
        :meth:`floor`: the accelerations there are rounding, and a crank may turn back
        short of a change point without any minor changing sign."""
        from mechdyn.simulate.assembly import _independent_text, closure_parts
        minors = np.abs(np.asarray(self.c.loop_minors(t, y, p)))
        if self.scale is not None and minors.max() > _PREFILTER * self.scale:
            return                              # every minor large: far from rank loss
        margin = rank_margin(closure_parts(self.c, t, y, p)[1])
        if margin < self.floor():
            raise LoopSingularError(self._weakest(t, y, p), t, y,
                                    f" ({_independent_text(self.c, y)}, rank margin of G "
                                    f"{margin:.2g})")

    def watched_minor(self, t, y, p):
        """``(index, direction)`` of the minor a segment starting at ``(t, y)`` watches
        (the largest, falling through zero from its side), or None without loops."""
        if not self.c.constraints:
            return None
        minors = self.c.loop_minors(t, y, p)            # a short list: plain Python
        sizes = [abs(v) for v in minors]
        k = sizes.index(max(sizes))
        if self.scale is None:
            self.scale = sizes[k]
        self.check_singular(t, y, p, minors)
        return k, -1.0 if minors[k] >= 0 else 1.0    # falling from its side (0: +)

    def check_singular(self, t, y, p, minors=None):
        """Raise :class:`LoopSingularError` where every minor of ``G`` (``minors``,
        where already evaluated at ``(t, y)``) is below ``LOOP_MARGIN`` times its size at
        the start."""
        if not self.c.constraints or self.scale is None:
            return
        sizes = [abs(v) for v in (self.c.loop_minors(t, y, p) if minors is None
                                  else minors)]
        if not all(map(math.isfinite, sizes)) or max(sizes) < LOOP_MARGIN * self.scale:
            from mechdyn.simulate.assembly import _independent_text
            raise LoopSingularError(self._weakest(t, y, p), t, y,
                                    f" ({_independent_text(self.c, y)})")

    def _weakest(self, t, y, p):
        """The loop whose constraint is most nearly dependent on the others."""
        from mechdyn.simulate.assembly import closure_parts
        _, grads, _, _ = closure_parts(self.c, t, y, p)
        scaled = grads / np.maximum(np.linalg.norm(grads, axis=1, keepdims=True), 1e-300)
        residuals = []
        for k in range(len(scaled)):
            others = np.delete(scaled, k, axis=0)
            if not len(others):
                residuals.append(np.linalg.norm(scaled[k]))
                continue
            fit = np.linalg.lstsq(others.T, scaled[k], rcond=None)[0]
            residuals.append(np.linalg.norm(scaled[k] - others.T @ fit))
        return self.c.meta["loops"][int(np.argmin(residuals))]

    def trim(self, trajectory, events, error, p):
        """Cut a run stopped by ``error`` (a :class:`LoopSingularError`) back to its
        last well-conditioned step point (rank margin at least ten times
        :meth:`floor`); the error's message and ``kept_until`` (time) say where the
        partial result ends and how far short of the singular position (extrapolated
        from the margins of the last two step points, the margin growing linearly
        with the distance from it)."""
        from mechdyn.simulate.assembly import _independent_text, closure_parts
        times, states, _ = trajectory.points()

        def margin(j):
            return rank_margin(closure_parts(self.c, times[j], states[:, j], p)[1])
        threshold = min(0.1, 10 * self.floor())
        keep, last = len(times) - 1, []
        while keep > 0 and margin(keep) < threshold:
            last.append(keep)
            keep -= 1
        singular = np.asarray(error.state, dtype=float)[list(self.c.independent)]
        if len(times) > 1:
            j = len(times) - 1
            m_last, m_before = margin(j), margin(j - 1)
            if m_before > m_last:
                x_last = states[list(self.c.independent), j]
                x_before = states[list(self.c.independent), j - 1]
                singular = x_last + m_last * (x_last - x_before) / (m_before - m_last)
        trajectory.truncate(times[keep])
        events[:] = [event for event in events if event.time <= times[keep]]
        kept = states[list(self.c.independent), keep]
        gaps = ", ".join(f"{self.c.coordinates[i]} {abs(s - k):.6g} short of {s:.9g}"
                         for i, s, k in zip(self.c.independent, singular, kept))
        error.kept_until = float(times[keep])
        error.args = (f"{error}; error.partial ends at t = {times[keep]:.9g} s "
                      f"({_independent_text(self.c, states[:, keep])}), {gaps}, the "
                      "singular position: the last step point where the loops are "
                      f"well-conditioned (rank margin of G >= {threshold:.2g})",)

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
"""
from __future__ import annotations

import numpy as np

from mechdyn.compile.loop_numeric import LOOP_MARGIN, LoopSingularError

__all__ = ["LoopWatch"]


class LoopWatch:
    """The closed loops of a compiled scene, watched during a run."""

    def __init__(self, compiled, rtol):
        self.c, self.rtol = compiled, rtol
        self.scale = None               # size of G's largest minor at the assembled start

    def limits(self, y0, p) -> tuple:
        """The largest drifts of the positions and speeds a segment starting at ``y0``
        allows (``rtol`` times the loops' size)."""
        from mechdyn.simulate.assembly import closure_parts
        _, grads, _, _ = closure_parts(self.c, 0.0, y0, p)
        size = float(np.max(np.abs(grads)))
        speed_scale = 1.0 + float(np.max(np.abs(y0[self.c.dof:])))
        return self.rtol * size, self.rtol * size * speed_scale

    def drifted(self, y0, p):
        """``drift(t, y) -> bool`` for a segment starting at ``y0``, or None."""
        if not self.c.constraints:
            return None
        position_limit, speed_limit = self.limits(y0, p)

        def drift(t, y):
            position, speed = self.c.drift(t, y, p)
            return position > position_limit or speed > speed_limit
        return drift

    def watched_minor(self, t, y, p):
        """``(index, direction)`` of the minor a segment starting at ``(t, y)`` watches
        (the largest, falling through zero from its side), or None without loops."""
        if not self.c.constraints:
            return None
        minors = np.asarray(self.c.loop_minors(t, y, p))
        k = int(np.argmax(np.abs(minors)))
        if self.scale is None:
            self.scale = abs(minors[k])
        self.check_singular(t, y, p)
        return k, -float(np.sign(minors[k]) or 1.0)

    def check_singular(self, t, y, p):
        """Raise :class:`LoopSingularError` where every minor of ``G`` is below
        ``LOOP_MARGIN`` times its size at the start."""
        if not self.c.constraints or self.scale is None:
            return
        minors = np.abs(np.asarray(self.c.loop_minors(t, y, p)))
        if not np.all(np.isfinite(minors)) or minors.max() < LOOP_MARGIN * self.scale:
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

"""Stepping with the compiled kernels: one segment, the same contract as
:class:`mechdyn.simulate.stepping.ScipySegment`.

A :class:`CompiledSegment` runs :class:`mechdyn.kernels.Integration` (DOP853 or Rodas5P
in numba) chunk by chunk, appends each chunk's steps and step polynomials to the
segment, and reports how the chunk ended as an :class:`~mechdyn.simulate.stepping.Outcome`. The
events it watches are entries of the scene's generated ``events`` function; their
rules at a start exactly at zero (see :mod:`mechdyn.simulate.events`) are set through the
kernel's sign memory: the side a function counts as being on while it is zero.
"""
from __future__ import annotations

import math

import numpy as np

from mechdyn.kernels import (CHUNK_FULL, DOP853, EVENT, FINISHED, IGNORED, NONSTIFF, RODAS5P,
                      STIFF, Integration)
from mechdyn.errors import ParameterError
from mechdyn.kernels.layout import EVENTS_VALID, HEAD
from mechdyn.simulate.stepping import Outcome

__all__ = ["CompiledSegment", "KERNEL_METHODS"]

KERNEL_METHODS = {"DOP853": DOP853, "Rodas5P": RODAS5P}


class CompiledSegment:
    """One segment integrated by a compiled kernel.

    ``functions``: the scene's :func:`~mechdyn.compile.numba_model.numba_functions`; ``p`` the
    parameter vector; ``watched``: ``(index in events, direction, side while zero)``
    per watched event, in the order the driver numbers them (a side of +2/-2: that side
    whatever the value at the start, :mod:`mechdyn.kernels.layout`); the last ``drift`` of them
    end the segment with status ``"drift"`` (the state left its constraints) when they
    fire alone; ``switch``: whether the kernel may report that the method no longer
    fits (stiff / not stiff); ``midpoint``: whether events are also sampled at each
    step's midpoint (on the interpolant, which may leave the loops' constraints further
    than the steps do); ``scratch``: the work arrays of the kernel's chunks, kept for the
    next segment (:class:`mechdyn.kernels.Integration`).
    """

    def __init__(self, method, functions, p, t0, y0, t_bound, rtol, atol, segment,
                 watched=(), n_events=0, first_step=None, max_step=np.inf, switch=False,
                 autonomous=False, drift=0, midpoint=True, scratch=None):
        self.method, self.segment, self.t_bound = method, segment, t_bound
        self.events = len(watched) - drift       # the driver's watched events
        directions = [IGNORED] * n_events
        for index, direction, _ in watched:
            directions[index] = direction
        self.order = [index for index, _, _ in watched]
        y0 = np.array(y0, dtype=float)
        if not all(map(math.isfinite, y0.tolist())):
            raise ParameterError(f"the state at the segment's start must be finite, got "
                                 f"{y0.tolist()}")
        n = y0.size
        atol = np.full(n, float(atol)) if np.ndim(atol) == 0 \
            else np.ascontiguousarray(atol, dtype=float)
        self.run = Integration.prepared(                # the driver built the inputs
            functions, np.array(p, dtype=float), float(t0), y0, KERNEL_METHODS[method],
            float(rtol), atol, np.array(directions, dtype=np.int64),
            h0=float(first_step or 0.0), max_step=float(max_step),
            autonomous=bool(autonomous), detect_switch=bool(switch),
            midpoint_events=bool(midpoint), scratch=scratch)
        if n_events:                   # the side each event counts as while it is zero
            carry = self.run.carry
            carry[EVENTS_VALID] = 1.0
            for index, _, side in watched:
                carry[HEAD + 2 * n + index] = side
        self.steps = 0
        self._h = 0.0

    def hold_switching(self):
        """Keep the method whatever the stiffness tests say; returns the function that
        lets them act again."""
        detect = self.run.detect_switch
        self.run.detect_switch = False

        def release():
            self.run.detect_switch = detect
        return release

    @property
    def h(self) -> float:
        return self._h

    @property
    def counts(self) -> dict:
        stats = self.run.stats
        return {"steps": self.steps, "nfev": stats["nfev"], "njev": stats["njev"],
                "nlu": stats["nlu"]}

    def advance(self, max_steps) -> Outcome:
        """Take up to ``max_steps`` steps; see :class:`~mechdyn.simulate.stepping.Outcome`."""
        chunk = self.run.advance(self.t_bound, max_steps)
        steps = len(chunk.coefs)
        if steps:
            self.segment.extend(chunk.ts[1:], chunk.ys[1:], chunk.coefs)
            self._h = float(chunk.ts[-1] - chunk.ts[-2])
        self.steps += steps
        t, y = self.run.t, self.run.y
        status = chunk.status
        if status == FINISHED:
            return Outcome("finished", t, y)
        if status == CHUNK_FULL:
            return Outcome("chunk", t, y)
        if status == EVENT:
            signs = chunk.fired.tolist()
            fired = [k for k, index in enumerate(self.order) if signs[index] != 0]
            if fired and fired[0] >= self.events:
                return Outcome("drift", t, y)
            return Outcome("event", t, y, [k for k in fired if k < self.events])
        if status in (STIFF, NONSTIFF):
            return Outcome("stiff", t, y)
        return Outcome("failed", t, y, message=f"the compiled {self.method} stopped: "
                       f"{chunk.status_name}")

"""Python side of the kernels: a run advanced in chunks, and dense-output evaluation.

:class:`Integration` allocates the kernel's arrays, checks the inputs (naming the
culprit) and calls :func:`mechdyn.kernels.loop.integrate` once per :meth:`advance`;
:func:`dense_values` evaluates stored steps at many times at once.

>>> import numpy as np
>>> from numba import njit
>>> from mechdyn.kernels import RHS_SIGNATURE, Integration, model_functions
>>> @njit(RHS_SIGNATURE)
... def decay(t, y, p, out):
...     out[0] = -p[0] * y[0]
>>> run = Integration(model_functions(decay), p=[2.0], t0=0.0, y0=[1.0], rtol=1e-10,
...                   atol=1e-12)
>>> chunk = run.advance(t_bound=1.0, max_steps=1000)
>>> chunk.status_name, bool(abs(run.y[0] - np.exp(-2.0)) < 1e-9)
('finished', True)
>>> bool(abs(dense_values(chunk.ts, chunk.coefs, [0.5])[0, 0] - np.exp(-1.0)) < 1e-9)
True

A driver that switches methods on the kernel's stiffness statuses (a composite method,
as LSODA or DifferentialEquations.jl's AutoTsit5(Rosenbrock23()) do):

>>> from mechdyn.kernels import CHUNK_FULL, DOP853, NONSTIFF, RODAS5P, STIFF
>>> @njit(RHS_SIGNATURE)
... def van_der_pol(t, y, p, out):
...     out[0] = y[1]
...     out[1] = p[0] * (1.0 - y[0] ** 2) * y[1] - y[0]
>>> run = Integration(model_functions(van_der_pol), [1000.0], 0.0, [2.0, 0.0], rtol=1e-6,
...                   atol=1e-8, method=DOP853, autonomous=True)
>>> while (chunk := run.advance(3000.0, 10_000)).status in (STIFF, NONSTIFF, CHUNK_FULL):
...     if chunk.status != CHUNK_FULL:
...         run.switch(RODAS5P if chunk.status == STIFF else DOP853)
>>> chunk.status_name, run.t, round(float(run.y[0]), 3)
('finished', 3000.0, -1.511)
"""
import math
from typing import NamedTuple

import numpy as np

from ..errors import MechdynError, ParameterError
from .functions import ModelFunctions
from .layout import (COUNT_NAMES, DEGREE, DOP853, EVENTS_VALID, H, HEAD, IGNORED,
                     INVALID_INPUT, METHOD, METHOD_NAMES, N_COUNTS, RODAS5P, STATUS_NAMES,
                     T, carry_size)
from .loop import integrate

__all__ = ["Chunk", "Integration", "dense_values", "new_carry"]


class Chunk(NamedTuple):
    """What one call of the kernel produced (arrays are views of fresh buffers)."""
    status: int            #: a status of :mod:`mechdyn.kernels.layout`
    method: int            #: the method that took these steps
    ts: np.ndarray         #: (steps + 1,) step boundaries; ts[0] = start of the call
    ys: np.ndarray         #: (steps + 1, n) states at the boundaries
    coefs: np.ndarray      #: (steps, degree + 1, n) monomial dense-output coefficients
    fired: np.ndarray      #: (n_events,) +1/-1 for events firing at ts[-1] (rising/falling)

    @property
    def status_name(self):
        return STATUS_NAMES[self.status]


def new_carry(t0, y0, n_events=0, h0=0.0):
    """The kernel's state vector for a run starting at (t0, y0); ``h0`` <= 0 lets the
    kernel choose the first step (layout in :mod:`mechdyn.kernels.layout`)."""
    y0 = np.asarray(y0, dtype=np.float64)
    carry = np.zeros(carry_size(y0.size, n_events))
    carry[T], carry[H], carry[METHOD] = t0, h0, -1.0
    carry[HEAD:HEAD + y0.size] = y0
    return carry


class Integration:
    """One run of the compiled kernel from (t0, y0), advanced chunk by chunk.

    ``functions`` from :func:`mechdyn.kernels.model_functions`; ``p`` the parameter
    vector passed to them; ``atol`` a scalar or one value per state; ``directions`` one
    entry per event function (+1 rising, -1 falling, 0 either, 2 ignored). Options as in
    :func:`mechdyn.kernels.loop.integrate`: ``autonomous`` skips df/dt in RODAS5P,
    ``midpoint_events`` also samples events at each step's midpoint, ``detect_switch``
    lets the kernel return STIFF / NONSTIFF, ``dense`` stores dense output.
    ``scratch``: a dict the chunks' work arrays are kept in and reused from (a driver
    running many short segments passes the same one to each: no fresh megabytes per
    call); the chunks returned are then copies of the part used.
    """

    def __init__(self, functions, p, t0, y0, *, method=DOP853, rtol=1e-6, atol=1e-9,
                 directions=(), h0=0.0, max_step=np.inf, autonomous=False,
                 midpoint_events=True, detect_switch=True, dense=True, scratch=None):
        self.scratch = scratch
        if not isinstance(functions, ModelFunctions):
            raise ParameterError("functions must come from mechdyn.kernels.model_functions"
                                 f", got {type(functions).__name__}")
        self.functions = functions
        self.p = _vector("p", p, allow_empty=True)
        y0 = _vector("y0", y0)
        self.n = y0.size
        self.rtol = float(rtol)
        if not self.rtol >= 0.0:
            raise ParameterError(f"rtol must be >= 0, got {rtol}")
        self.atol = (np.full(self.n, float(atol)) if np.ndim(atol) == 0
                     else _vector("atol", atol))
        if self.atol.size != self.n or not all(a > 0.0 for a in self.atol.tolist()):
            raise ParameterError(f"atol must be one value > 0, or one per state ({self.n}),"
                                 f" got {atol}")
        if not float(max_step) > 0.0:
            raise ParameterError(f"max_step must be > 0, got {max_step}")
        self.max_step = float(max_step)
        self.directions = self._directions(directions)
        if not np.isfinite(float(t0)):
            raise ParameterError(f"t0 must be finite, got {t0}")
        self.method = self._method(method)
        self.autonomous, self.midpoint_events = bool(autonomous), bool(midpoint_events)
        self.detect_switch, self.dense = bool(detect_switch), bool(dense)
        self.carry = new_carry(float(t0), y0, self.directions.size, float(h0))
        self.counts = np.zeros(N_COUNTS, dtype=np.int64)

    @classmethod
    def prepared(cls, functions, p, t0, y0, method, rtol, atol, directions, *, h0=0.0,
                 max_step=np.inf, autonomous=False, midpoint_events=True,
                 detect_switch=True, dense=True, scratch=None):
        """An Integration from inputs a caller has already built and checked (the
        simulation driver, once per segment): ``p``, ``y0``, ``atol`` (one per state)
        and ``directions`` float64 / int64 vectors, ``method`` a kernel method; none
        of the checks of the constructor are repeated."""
        run = cls.__new__(cls)
        run.scratch, run.functions, run.p = scratch, functions, p
        run.n, run.rtol, run.atol, run.max_step = y0.size, rtol, atol, max_step
        run.directions, run.method = directions, method
        run.autonomous, run.midpoint_events = autonomous, midpoint_events
        run.detect_switch, run.dense = detect_switch, dense
        run.carry = new_carry(t0, y0, directions.size, h0)
        run.counts = np.zeros(N_COUNTS, dtype=np.int64)
        return run

    @property
    def t(self):
        return float(self.carry[T])

    @property
    def y(self):
        return self.carry[HEAD:HEAD + self.n].copy()

    @property
    def stats(self):
        """Counts so far: nfev, njev, nlu, naccept, nreject, ngev."""
        return dict(zip(COUNT_NAMES, self.counts.tolist()))

    def advance(self, t_bound, max_steps=1000):
        """Integrate towards ``t_bound`` for at most ``max_steps`` accepted steps."""
        t_bound = float(t_bound)
        if not t_bound >= self.t:
            raise ParameterError(f"t_bound {t_bound} lies before the current time {self.t}"
                                 " (the kernels integrate forward only)")
        max_steps = int(max_steps)
        if max_steps < 0:
            raise ParameterError(f"max_steps must be >= 0, got {max_steps}")
        n, degree = self.n, DEGREE[self.method]
        ts, ys, coefs = self._work_arrays(max_steps, n, degree)
        fired = np.zeros(self.directions.size, dtype=np.int64)
        status, steps = integrate(
            self.method, self.functions.addresses, self.p, t_bound, self.rtol, self.atol,
            self.max_step, self.autonomous, self.midpoint_events, self.detect_switch,
            self.directions, max_steps, self.carry, self.counts, ts, ys, coefs, 0, fired)
        if status == INVALID_INPUT:   # the checks above should make this unreachable
            raise MechdynError("the integration kernel rejected its inputs")
        ts, ys, coefs = ts[:steps + 1], ys[:steps + 1], coefs[:steps] if self.dense else coefs
        if self.scratch is not None:                 # the work arrays are used again
            ts, ys, coefs = ts.copy(), ys.copy(), coefs.copy()
        return Chunk(status, self.method, ts, ys, coefs, fired)

    def _work_arrays(self, max_steps, n, degree):
        """``ts``, ``ys`` and ``coefs`` for a chunk of ``max_steps`` steps: fresh, or
        from ``scratch`` (allocated there once per shape)."""
        shape = (max_steps, n, degree if self.dense else -1)
        if self.scratch is not None and shape in self.scratch:
            return self.scratch[shape]
        arrays = (np.empty(max_steps + 1), np.empty((max_steps + 1, n)),
                  np.empty((max_steps if self.dense else 0, degree + 1, n)))
        if self.scratch is not None:
            self.scratch[shape] = arrays
        return arrays

    def switch(self, method):
        """Continue with another method (the kernel resets the step-size controller)."""
        self.method = self._method(method)

    def change_model(self, functions=None, p=None, directions=None):
        """Continue from the current (t, y) with other functions, parameters or event
        directions; event signs are then taken afresh (zero at the start never fires)."""
        if functions is not None:
            self.functions = functions
        if p is not None:
            self.p = _vector("p", p, allow_empty=True)
        directions = self._directions(self.directions if directions is None else directions)
        if directions.size != self.directions.size:
            carry = new_carry(self.t, self.y, directions.size)
            carry[:HEAD + 2 * self.n] = self.carry[:HEAD + 2 * self.n]
            self.carry = carry
        self.directions = directions
        self.carry[EVENTS_VALID] = 0.0

    def _directions(self, directions):
        directions = np.asarray(directions, dtype=np.int64).reshape(-1)
        if directions.size and not self.functions.has_events:
            raise ParameterError(f"{directions.size} event directions given but the model"
                                 " has no events function")
        bad = [d for d in directions.tolist() if d not in (-1, 0, 1, IGNORED)]
        if bad:
            raise ParameterError(f"event directions must be +1, -1, 0 or {IGNORED} "
                                 f"(ignored), got {bad}")
        return directions

    @staticmethod
    def _method(method):
        if method not in (DOP853, RODAS5P):
            raise ParameterError(f"unknown kernel method {method!r}; use DOP853 "
                                 f"({DOP853}) or RODAS5P ({RODAS5P}): {METHOD_NAMES}")
        return int(method)


def dense_values(ts, coefs, times):
    """States at ``times`` from stored steps: ``ts`` (steps + 1,) boundaries, ``coefs``
    (steps, degree + 1, n) monomial coefficients in x = (t - ts[k]) / (ts[k+1] - ts[k]).
    Vectorised: one searchsorted and one Horner pass over all times."""
    ts, coefs = np.asarray(ts), np.asarray(coefs)
    times = np.atleast_1d(np.asarray(times, dtype=np.float64))
    step = np.clip(np.searchsorted(ts, times, side="right") - 1, 0, len(coefs) - 1)
    x = ((times - ts[step]) / (ts[step + 1] - ts[step]))[:, None]
    values = coefs[step, -1, :].copy()
    for k in range(coefs.shape[1] - 2, -1, -1):
        values = values * x + coefs[step, k, :]
    return values


def _vector(name, values, allow_empty=False):
    array = np.ascontiguousarray(values, dtype=np.float64).reshape(-1)
    if array.size == 0 and not allow_empty:
        raise ParameterError(f"{name} is empty")
    if not all(map(math.isfinite, array.tolist())):
        raise ParameterError(f"{name} must be finite, got {array.tolist()}")
    return array

"""Compiled ODE integration kernels (numba): DOP853 and Rodas5P with dense output,
event location and stiffness-switch tests, driven in chunks from Python.

Import cost: numba, its one-time initialisation and the cached kernel (measured by
``benchmarks/process.py``), with the garbage collector paused (:mod:`.startup`); nothing
in mechdyn imports this package until a run uses the compiled backend. The first import after installing or editing a kernel module compiles
the kernel, kept in mechdyn's cache folder (:mod:`mechdyn.numba_cache`; with
``MECHDYN_CACHE=off`` compiled in memory by every process).

Model functions (see :mod:`.functions`) are numba functions with the signatures
``RHS_SIGNATURE`` / ``JAC_SIGNATURE`` / ``EVENTS_SIGNATURE``; :func:`model_functions`
collects their addresses. The kernel is compiled once, for every model.

The kernel (:func:`integrate`, in :mod:`.loop`)::

    status, steps = integrate(
        method,            # int64: DOP853 (0) or RODAS5P (1)
        functions,         # int64[6]: ModelFunctions.addresses (rhs, jac, events)
        p,                 # float64[::1]: parameters passed to the model functions
        t_bound,           # float64: stop there (>= current t; may be inf)
        rtol, atol,        # float64, float64[n] (> 0)
        max_step,          # float64 (inf: none)
        autonomous,        # bool: f does not depend on t (RODAS5P skips df/dt)
        midpoint_events,   # bool: also sample events at each step's dense midpoint
        detect_switch,     # bool: may return STIFF (DOP853) / NONSTIFF (RODAS5P)
        directions,        # int64[m]: per event +1 rising, -1 falling, 0 either, 2 ignored
        max_steps,         # int64: at most this many accepted steps in this call
        carry,             # float64[carry_size(n, m)]: t, y and the state between calls
        counts,            # int64[6]: nfev, njev, nlu, naccept, nreject, ngev (added to)
        ts, ys,            # float64[N+1], float64[N+1, n]: step boundaries (N = 0: none)
        coefs,             # float64[N, >= degree+1, n]: dense output per step (N = 0: none)
        first,             # int64: where this call starts writing (append to buffers)
        fired)             # int64[m]: +1/-1 for each event firing at the stop, else 0

Returns the status and the number of steps written. It writes ``ts[first] = t`` and
``ys[first] = y`` (the start), then per accepted step k = 0, 1, ... the end time
``ts[first+k+1]``, state ``ys[first+k+1]`` and the step's polynomial
``coefs[first+k, j, i]``: y_i(t) = sum_j coefs[first+k, j, i] x^j with
x = (t - ts[first+k]) / (ts[first+k+1] - ts[first+k]) in [0, 1]. An event truncates its
step at the event time (the polynomial rescaled to the shorter step), and ``carry``
then holds the state there.

Statuses (:mod:`.layout`): FINISHED, EVENT, CHUNK_FULL, STIFF, NONSTIFF (carry at the
last accepted step; switch method and call again), STEP_TOO_SMALL, NOT_FINITE,
INVALID_INPUT (nothing written: array sizes that do not fit, non-positive atol, ...).
Calling again with the returned carry continues exactly where the last
call stopped: one long call and many short ones give identical results (f(t, y) is
re-evaluated at the start of each call, one RHS evaluation per call). After changing
the model functions, parameters or event functions, set ``carry[EVENTS_VALID] = 0``
so that event signs are taken afresh; after changing ``method`` the kernel resets the
step-size controller itself.

:class:`Integration` wraps all this for Python callers; :func:`dense_values` evaluates
stored steps at many times at once.
"""
from .startup import collector_paused

with collector_paused():          # numba's start-up and the cached kernel (see .startup)
    from .api import Chunk, Integration, dense_values, new_carry
    from .functions import (EVENTS_SIGNATURE, JAC_SIGNATURE, RHS_SIGNATURE,
                            ModelFunctions, model_functions)
    from .loop import integrate
from .layout import (CHUNK_FULL, DOP853, EITHER, EVENT, FALLING, FINISHED, IGNORED,
                     INVALID_INPUT, NONSTIFF, NOT_FINITE, RISING, RODAS5P, STEP_TOO_SMALL,
                     STIFF, carry_size)

__all__ = ["integrate", "Integration", "Chunk", "dense_values", "new_carry", "carry_size",
           "model_functions", "ModelFunctions", "RHS_SIGNATURE", "JAC_SIGNATURE",
           "EVENTS_SIGNATURE", "DOP853", "RODAS5P", "FINISHED", "EVENT", "CHUNK_FULL",
           "STIFF", "NONSTIFF", "STEP_TOO_SMALL", "NOT_FINITE", "INVALID_INPUT", "RISING",
           "FALLING", "EITHER", "IGNORED"]

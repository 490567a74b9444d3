"""The compiled integration loop: :func:`integrate`, one entry point for both methods.

Compiled once, with an explicit signature, releasing the GIL (threads can run kernels
in parallel), and cached on disk in mechdyn's cache folder (:mod:`mechdyn.numba_cache`;
in memory with ``MECHDYN_CACHE=off``). numba keys its
cache on this file only, so the loop is built in a closure over a fingerprint of the
sources it is compiled from (``COMPILED_MODULES``): editing any of them recompiles it
instead of loading stale machine code. The one compilation (about 15 s, after installing
or editing a kernel module) is announced on stderr with the seconds elapsed.
"""
import hashlib
import math
from pathlib import Path

import numpy as np
from numba import njit, types

from ..numba_cache import CACHED
from ..progress import announce
from . import dop853, iteration, rodas
from .events import locate
from .functions import as_jac, as_rhs
from .layout import (CHUNK_FULL, DEGREE, DOP853, ERR_ACCEPTED, EVENT, EVENTS_VALID,
                     FINISHED, H, H_ACCEPTED, H_RHO, HEAD, IGNORED, INVALID_INPUT, METHOD,
                     N_COUNTS, NACCEPT, NFEV, NGEV, NJEV, NLU, NONSTIFF, NONSTIFF_LIMIT,
                     NONSTIFF_STEPS, NOT_FINITE, NREJECT, QUIET_STEPS, QUIET_TO_FORGET,
                     REJECTED, RODAS5P, STEP_TOO_SMALL, STIFF, STIFF_HITS,
                     STIFF_HITS_TO_REPORT, STIFF_LIMIT, T)

_vector = types.Array(types.float64, 1, "C")
_int_vector = types.Array(types.int64, 1, "C")
SIGNATURE = types.UniTuple(types.int64, 2)(
    types.int64, _int_vector, _vector, types.float64, types.float64, _vector,
    types.float64, types.boolean, types.boolean, types.boolean, _int_vector, types.int64,
    _vector, _int_vector, _vector, types.Array(types.float64, 2, "C"),
    types.Array(types.float64, 3, "C"), types.int64, _int_vector)
ERROR_EXPONENT = (1.0 / 8.0, 1.0 / 5.0)   # 1 / (order of the error estimate + 1)


@njit(inline="always")
def _scaled_rms(v, w, y, atol, rtol):
    """RMS of (v - w) / (atol + rtol |y|), its squares taken relative to the largest term:
    no overflow where accelerations are 1e150 (an inertia of 1e-150 kg m^2)."""
    n = y.shape[0]
    largest = 0.0
    for i in range(n):
        largest = max(largest, abs((v[i] - w[i]) / (atol[i] + abs(y[i]) * rtol)))
    if largest == 0.0 or not math.isfinite(largest):
        return largest
    total = 0.0
    for i in range(n):
        total += ((v[i] - w[i]) / (atol[i] + abs(y[i]) * rtol) / largest) ** 2
    return largest * math.sqrt(total / n)


@njit
def initial_step(rhs, t, y, f0, p, rtol, atol, t_bound, max_step, exponent, y1, f1):
    """Hairer's / scipy's starting step (one RHS evaluation)."""
    y1[:] = 0.0
    d0 = _scaled_rms(y, y1, y, atol, rtol)
    d1 = _scaled_rms(f0, y1, y, atol, rtol)
    h0 = 1e-6 if (d0 < 1e-5 or d1 < 1e-5) else 0.01 * d0 / d1
    h0 = min(h0, t_bound - t)
    if not h0 > 0.0:
        return min(t_bound - t, max_step)
    for i in range(y.shape[0]):
        y1[i] = y[i] + h0 * f0[i]
    rhs(t + h0, y1, p, f1)
    d2 = _scaled_rms(f1, f0, y, atol, rtol) / h0
    if not math.isfinite(d2) or (d1 <= 1e-15 and d2 <= 1e-15):
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** exponent
    return min(100.0 * h0, h1, t_bound - t, max_step)


@njit(inline="always")
def _copy(source, target):
    for i in range(source.shape[0]):
        target[i] = source[i]


@njit
def _valid(method, functions, t_bound, rtol, atol, max_step, directions, max_steps,
           carry, counts, ts, ys, coefs, first, fired):
    n = atol.shape[0]
    m = directions.shape[0]
    if method != DOP853 and method != RODAS5P:
        return False
    if functions.shape[0] != 6 or (functions[0] == 0 and functions[1] == 0):
        return False
    if m > 0 and functions[4] == 0 and functions[5] == 0:
        return False
    if (carry.shape[0] != HEAD + 2 * n + m or counts.shape[0] < N_COUNTS
            or fired.shape[0] != m or n == 0 or first < 0 or max_steps < 0):
        return False
    if ts.shape[0] != ys.shape[0] or (ts.shape[0] > 0 and (ys.shape[1] != n
                                                          or ts.shape[0] < first + 1)):
        return False
    if coefs.shape[0] > 0 and (coefs.shape[2] != n or coefs.shape[1] < DEGREE[method] + 1
                               or coefs.shape[0] < first):
        return False
    if not (rtol >= 0.0 and max_step > 0.0 and t_bound >= carry[T]
            and math.isfinite(carry[T])):
        return False
    for i in range(n):
        if not (atol[i] > 0.0 and math.isfinite(carry[HEAD + i])):
            return False
    return True


def _compile(fingerprint):
    @njit(SIGNATURE, cache=CACHED, nogil=True)
    def integrate(method, functions, p, t_bound, rtol, atol, max_step, autonomous,
                  midpoint_events, detect_switch, directions, max_steps, carry, counts,
                  ts, ys, coefs, first, fired):
        fingerprint  # noqa: B018 (keys numba's cache on every kernel source)
        if not _valid(method, functions, t_bound, rtol, atol, max_step, directions,
                      max_steps, carry, counts, ts, ys, coefs, first, fired):
            return INVALID_INPUT, 0
        n = atol.shape[0]
        m = directions.shape[0]
        rhs = as_rhs(functions[0], functions[1])
        jac = as_jac(functions[2], functions[3])
        events = as_rhs(functions[4], functions[5])
        has_jac = functions[2] != 0 or functions[3] != 0
        y = carry[HEAD:HEAD + n]
        power_vector = carry[HEAD + n:HEAD + 2 * n]

        K = np.zeros((16, n))
        f0, f_new, y_stage, y_new, y_work, w1, w2, dfdt = (
            np.zeros(n), np.zeros(n), np.zeros(n), np.zeros(n), np.zeros(n),
            np.zeros(n), np.zeros(n), np.zeros(n))
        poly = np.zeros((8, n))
        J = np.zeros((n, n))
        W = np.zeros((n, n))
        pivots = np.zeros(n, np.int64)
        order, position, degree = (np.zeros(n, np.int64), np.zeros(n, np.int64),
                                   np.zeros(n, np.int64))
        plan = np.full(iteration.plan_size(n), -1, np.int64)   # how W is factored
        core = np.zeros((n // 2, n // 2))     # the reduced matrix (second-order models)
        ordered = False
        g_old, g_new, g_mid, g_work = np.zeros(m), np.zeros(m), np.zeros(m), np.zeros(m)
        memory = np.zeros(m, np.int64)

        if carry[METHOD] != method:   # a switch: forget the other method's controller
            for slot in (H_ACCEPTED, ERR_ACCEPTED, REJECTED, STIFF_HITS, QUIET_STEPS):
                carry[slot] = 0.0
            carry[METHOD] = method
        t = carry[T]
        for i in range(m):
            fired[i] = 0
        store = ts.shape[0] > 0
        store_dense = coefs.shape[0] > 0
        limit = max_steps
        if store:
            limit = min(limit, ts.shape[0] - 1 - first)
            ts[first] = t
            _copy(y, ys[first])
        if store_dense:
            limit = min(limit, coefs.shape[0] - first)
        rhs(t, y, p, f0)
        counts[NFEV] += 1
        for i in range(n):
            if not math.isfinite(f0[i]):
                return NOT_FINITE, 0
        watching = False
        if m > 0:
            events(t, y, p, g_old)
            counts[NGEV] += 1
            for i in range(m):
                sign = 1 if g_old[i] > 0.0 else (-1 if g_old[i] < 0.0 else 0)
                if carry[EVENTS_VALID] == 1.0:
                    kept = carry[HEAD + 2 * n + i]
                    if kept == 2.0 or kept == -2.0:    # this side, whatever the value
                        sign = int(kept) // 2
                    elif sign == 0:
                        sign = int(kept)
                memory[i] = sign
                watching = watching or directions[i] != IGNORED
            carry[EVENTS_VALID] = 1.0

        h = carry[H]
        if h <= 0.0 and t < t_bound:
            h = initial_step(rhs, t, y, f0, p, rtol, atol, t_bound, max_step,
                             ERROR_EXPONENT[method], y_work, f_new)
            counts[NFEV] += 1
        rejected = carry[REJECTED] != 0.0
        h_accepted = carry[H_ACCEPTED]
        err_accepted = carry[ERR_ACCEPTED]
        stiff_hits = int(carry[STIFF_HITS])
        quiet = int(carry[QUIET_STEPS])
        rho = 0.0
        need_jacobian = True
        steps = 0
        status = FINISHED if t >= t_bound else CHUNK_FULL
        while status == CHUNK_FULL and steps < limit:
            h_min = 10.0 * (np.nextafter(t, np.inf) - t)
            h = max(min(h, max_step), h_min)
            last = t + 1.01 * h >= t_bound
            if last:
                h = t_bound - t
                t_new = t_bound
            else:
                t_new = t + h
            if method == DOP853:
                _copy(f0, K[0])
                err = dop853.attempt(rhs, t, y, h, t_new, p, atol, rtol, K, y_stage, y_new)
                counts[NFEV] += 12
                _copy(K[12], f_new)
            else:
                if need_jacobian:
                    counts[NFEV] += rodas.jacobian(rhs, jac, has_jac, t, y, f0, p, J,
                                                   y_work, w1)
                    counts[NJEV] += 1
                    if not autonomous:
                        rodas.time_derivative(rhs, t, y, f0, p, dfdt)
                        counts[NFEV] += 1
                    ordered = iteration.plan(J, plan, order, position, degree, core, W,
                                             ordered)
                    rho = rodas.spectral_radius(J, power_vector, w1, w2, plan, order,
                                                position)
                    need_jacobian = False
                err = rodas.attempt(rhs, t, y, f0, h, t_new, p, atol, rtol, J, dfdt,
                                    autonomous, W, pivots, K, y_stage, w1, y_new, f_new,
                                    plan, order, position, core, w2)
                counts[NLU] += 1
                if not math.isnan(err):
                    counts[NFEV] += 8
            if not err <= 1.0:   # rejected (also NaN: singular, inf: not finite)
                counts[NREJECT] += 1
                if method == DOP853:
                    h *= dop853.step_factor(err, rejected)
                else:
                    h *= rodas.step_factor(err, h, rejected, h_accepted, err_accepted)
                rejected = True
                if h < h_min:
                    status = NOT_FINITE if math.isinf(err) else STEP_TOO_SMALL
                continue

            counts[NACCEPT] += 1
            if method == DOP853:
                cap, err_accepted = dop853.blind_guard(err, err_accepted)
                h_next = h * min(cap, dop853.step_factor(err, rejected))
                h_rho = dop853.stiffness_estimate(h, K, y_stage, y_new)
                if h_rho > STIFF_LIMIT:
                    stiff_hits += 1
                    quiet = 0
                else:
                    quiet += 1
                    if quiet >= QUIET_TO_FORGET:
                        stiff_hits = 0
                switch = detect_switch and stiff_hits >= STIFF_HITS_TO_REPORT
                if store_dense or watching:
                    dop853.dense_output(rhs, t, y, h, p, K, y_stage, y_new, poly)
                    counts[NFEV] += 3
            else:
                h_next = h * rodas.step_factor(err, h, rejected, h_accepted, err_accepted)
                h_accepted = h
                err_accepted = max(1e-2, err)
                h_rho = h * rho
                if h_rho >= NONSTIFF_LIMIT:
                    quiet = 0
                elif h_next < 2.0 * h:   # steps that are still growing fast prove nothing
                    quiet += 1
                switch = detect_switch and quiet >= NONSTIFF_STEPS
                if store_dense or watching:
                    rodas.dense_output(y, y_new, K, poly)
            rejected = False
            carry[H_RHO] = h_rho

            t_stop = t_new
            if watching:
                t_event = locate(events, p, t, t_new, y_new, poly, directions, memory,
                                 g_old, g_new, g_mid, midpoint_events, y_work, g_work,
                                 fired, counts)
                if math.isnan(t_event):
                    _copy(g_new, g_old)
                else:
                    status = EVENT
                    t_stop = t_event
                    _copy(y_work, y_new)
                    shrink = (t_event - t) / h
                    for k in range(1, 8):
                        for i in range(n):
                            poly[k, i] *= shrink ** k
            if t_stop > t:
                if store_dense:
                    for k in range(coefs.shape[1]):
                        for i in range(n):
                            coefs[first + steps, k, i] = poly[k, i] if k < 8 else 0.0
                if store:
                    ts[first + steps + 1] = t_stop
                    _copy(y_new, ys[first + steps + 1])
                steps += 1
            t = t_stop
            _copy(y_new, y)
            _copy(f_new, f0)
            need_jacobian = True
            h = h_next
            if status == CHUNK_FULL:
                if last:
                    status = FINISHED
                elif switch:   # report, and count afresh if the caller carries on
                    status = STIFF if method == DOP853 else NONSTIFF
                    stiff_hits = 0
                    quiet = 0

        carry[T] = t
        carry[H] = h
        carry[REJECTED] = 1.0 if rejected else 0.0
        carry[H_ACCEPTED] = h_accepted
        carry[ERR_ACCEPTED] = err_accepted
        carry[STIFF_HITS] = stiff_hits
        carry[QUIET_STEPS] = quiet
        for i in range(m):
            carry[HEAD + 2 * n + i] = memory[i]
        return status, steps

    return integrate


COMPILED_MODULES = ("band", "dop853", "dop853_tableau", "events", "functions",
                    "iteration", "layout", "linalg", "loop", "rodas", "sparse")


def _fingerprint():
    digest = hashlib.sha256()
    for name in COMPILED_MODULES:
        digest.update(Path(__file__).with_name(name + ".py").read_bytes())
    return digest.hexdigest()


with announce("compiling the integration kernels", 15):
    integrate = _compile(_fingerprint())      # loaded from numba's disk cache when there

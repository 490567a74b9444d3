"""Event location on one accepted step's dense output.

Each event function g_i keeps a sign memory: the sign of its last non-zero sample
(0 while it has been exactly zero since the start of the run). After a step the kernel
samples g at the step's end (and at its dense-output midpoint if asked); a sample whose
sign differs from the memory is a crossing between it and the previous sample. A
watched crossing (``directions[i]``: +1 rising, -1 falling, 0 either, 2 ignored) is
located by the Illinois variant of regula falsi on the dense output until the bracket
is narrower than 4 eps |t|; the reported time is the bracket's end on the new side, so
g there already has its new sign (or is 0). Zeros never count as a sign: a g that is
exactly 0 at the start of a run takes its sign from its first non-zero sample and
fires only on a later crossing; one whose caller set its side while zero (an event
whose zero counts as before the crossing) fires at the first point beyond that zero,
never at it. The earliest root wins; every event whose root lies
within 16 eps max(|t|) of it fires with it.

Limitation: a g that crosses and re-crosses zero between two samples (within one step,
or half a step with the midpoint sample) is not seen. Where an event function can
oscillate faster than the solution is stepped, bound the step with ``max_step``.
"""
import math

import numpy as np
from numba import njit

from .layout import IGNORED, NGEV

EPS = np.finfo(np.float64).eps
MAX_ITERATIONS = 200


@njit
def dense_value(poly, x, out):
    """out = sum_k poly[k] x^k (Horner)."""
    degree = poly.shape[0] - 1
    for i in range(out.shape[0]):
        total = poly[degree, i]
        for k in range(degree - 1, -1, -1):
            total = total * x + poly[k, i]
        out[i] = total


@njit
def _sign(value):
    return 1 if value > 0.0 else (-1 if value < 0.0 else 0)


@njit
def _g_at(events, p, i, t, t_old, h, poly, y_work, g_work):
    dense_value(poly, (t - t_old) / h, y_work)
    events(t, y_work, p, g_work)
    return g_work[i]


@njit
def _root(events, p, i, t_old, h, poly, ta, ga, tb, gb, y_work, g_work, counts):
    """A root of g_i in [ta, tb] with g(ta) of the old sign (or 0), g(tb) of the new:
    the first point on the new side once the bracket is below 4 eps |t|."""
    side = 0
    checked_width = tb - ta
    for iteration in range(MAX_ITERATIONS):
        if ga == 0.0 and ta > t_old:
            return ta
        # a zero at the step's start counts as the old side (an event whose zero is
        # "before", e.g. a clutch's normal force ramping up from 0): bisect towards it
        # for the first point on the new side
        width = tb - ta
        if width <= 4.0 * EPS * max(abs(ta), abs(tb)):
            break
        t = ta - ga * width / (gb - ga)
        if iteration % 4 == 3:      # guarantee progress: bisect if not halved lately
            if width > 0.5 * checked_width:
                t = ta + 0.5 * width
            checked_width = width
        if not (ta < t < tb):
            t = ta + 0.5 * width
            if not (ta < t < tb):
                break
        g = _g_at(events, p, i, t, t_old, h, poly, y_work, g_work)
        counts[NGEV] += 1
        if g == 0.0:
            return t
        if (g > 0.0) == (gb > 0.0):
            tb, gb = t, g
            if side == -1:
                ga *= 0.5
            side = -1
        else:
            ta, ga = t, g
            if side == 1:
                gb *= 0.5
            side = 1
    return tb


@njit
def locate(events, p, t_old, t_new, y_new, poly, directions, memory, g_old, g_new, g_mid,
           midpoint, y_work, g_work, fired, counts):
    """Check the step [t_old, t_new] (g_old at t_old given); fills g_new and updates
    ``memory``. Returns the earliest event time, or NaN if nothing fired; then
    ``fired[i]`` is +1/-1 (rising/falling) for each event firing at that time, ``y_work``
    the state there and ``memory`` valid at that time. ``counts[NGEV]`` counts evaluations.
    """
    m = directions.shape[0]
    h = t_new - t_old
    events(t_new, y_new, p, g_new)
    counts[NGEV] += 1
    t_mid = t_old + 0.5 * h
    if midpoint:
        dense_value(poly, 0.5, y_work)
        events(t_mid, y_work, p, g_mid)
        counts[NGEV] += 1
    roots = np.empty(m)
    new_sign = np.zeros(m, np.int64)
    old_memory = np.empty(m, np.int64)
    for i in range(m):
        roots[i] = np.inf
        old_memory[i] = memory[i]
    for i in range(m):
        if directions[i] == IGNORED:
            continue
        t_prev = t_old
        g_prev = g_old[i]
        for sample in range(2):
            if sample == 0:
                if not midpoint:
                    continue
                t_s, g_s = t_mid, g_mid[i]
            else:
                t_s, g_s = t_new, g_new[i]
            s = _sign(g_s)
            if s != 0:
                if memory[i] != 0 and s != memory[i] and (directions[i] == 0
                                                          or directions[i] == s):
                    roots[i] = _root(events, p, i, t_old, h, poly, t_prev, g_prev,
                                     t_s, g_s, y_work, g_work, counts)
                    new_sign[i] = s
                    break
                memory[i] = s
            t_prev, g_prev = t_s, g_s
    t_event = np.inf
    for i in range(m):
        t_event = min(t_event, roots[i])
    if t_event == np.inf:
        return math.nan
    window = 16.0 * EPS * max(abs(t_old), abs(t_new))
    for i in range(m):
        fired[i] = new_sign[i] if roots[i] <= t_event + window else 0
    # the state at the event, and the memory valid there
    dense_value(poly, (t_event - t_old) / h, y_work)
    events(t_event, y_work, p, g_work)
    counts[NGEV] += 1
    for i in range(m):
        if fired[i] != 0:
            memory[i] = fired[i]
        else:
            s = _sign(g_work[i])
            memory[i] = s if s != 0 else old_memory[i]
    return t_event

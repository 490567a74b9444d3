"""One DOP853 step: stages, error norm, step-size factor, dense output, stiffness test.

Dormand & Prince's explicit Runge-Kutta 8(5,3) as in Hairer's dop853.f and scipy's
``DOP853``: the error norm combines the 5th- and 3rd-order estimates as both do
(RMS of err / (atol_i + rtol max(|y_old_i|, |y_new_i|))), floored at ``ERROR_FLOOR``
times the 5th-order estimate (the blend falls far below it where the 3rd-order
estimate is large, and accepted steps 10 times over the tolerance on the slider-crank,
docs/hard-cases.md), step-size control follows
dop853.f (safety 0.9, new/old step within [0.333, 6], no growth right after a
rejection), and the continuous extension is the 7th-order one of dop853.f, returned as
monomial coefficients in x = (t - t_old) / h on [0, 1].

The functions are compiled into the kernel of :mod:`mechdyn.kernels.loop`; ``K`` is a
(16, n) work array whose row 0 holds f(t, y) on entry.
"""
import math

from numba import njit

from .dop853_tableau import A, B, C, D, E3, E5
from .linalg import stage_sum

SAFETY = 0.9
MIN_FACTOR = 0.333   # dop853.f FAC1: the new step is at least 0.333 the old one
MAX_FACTOR = 6.0     # dop853.f FAC2: ... and at most 6 times
EXPONENT = 1.0 / 8.0
ERROR_FLOOR = 0.1    # the norm is at least this part of the 5th-order estimate's
BLIND_DROP = 1e-2    # an estimate this far below the last trusted one is taken as blind
TRUST_DECAY = 0.1    # ... and the trusted value decays so a real fall of the error shows


@njit
def attempt(rhs, t, y, h, t_new, p, atol, rtol, K, y_stage, y_new):
    """Try a step of size ``h`` from (t, y) to ``t_new``: fills K[1:13], y_new, and the
    12th stage's argument in ``y_stage``. Returns the error norm (inf if anything in
    the step is not finite)."""
    n = y.shape[0]
    for s in range(1, 12):
        _stage_argument(y, h, K, y_stage, s)
        rhs(t + C[s] * h, y_stage, p, K[s])
    for i in range(n):
        y_new[i] = y[i] + h * stage_sum(B, K, i, 12)
    rhs(t_new, y_new, p, K[12])
    err5 = 0.0
    err3 = 0.0
    for i in range(n):
        if not (math.isfinite(y_new[i]) and math.isfinite(K[12, i])):
            return math.inf
        e5 = 0.0
        e3 = 0.0
        for j in range(12):
            e5 += E5[j] * K[j, i]
            e3 += E3[j] * K[j, i]
        scale = atol[i] + rtol * max(abs(y[i]), abs(y_new[i]))
        err5 += (e5 / scale) ** 2
        err3 += (e3 / scale) ** 2
    denominator = math.sqrt((err5 + 0.01 * err3) * n)
    if denominator == 0.0:        # no error, or one so small that 0.01 err3 underflows
        return 0.0
    norm = abs(h) * err5 / denominator
    norm = max(norm, ERROR_FLOOR * abs(h) * math.sqrt(err5 / n))
    return norm if math.isfinite(norm) else math.inf


@njit(inline="always")
def _stage_argument(y, h, K, y_stage, s):
    """The argument of stage ``s`` into ``y_stage`` (its slope, ``rhs`` there, is the
    caller's: a model function passed into an inlined function slows the step by a
    third)."""
    weights = A[s]
    for i in range(y.shape[0]):
        y_stage[i] = y[i] + h * stage_sum(weights, K, i, s)


@njit(inline="always")
def step_factor(err, rejected_before):
    """New step / old step after an error norm ``err`` (dop853.f's rule)."""
    if not math.isfinite(err):
        return MIN_FACTOR
    factor = min(MAX_FACTOR, max(MIN_FACTOR, SAFETY / err ** EXPONENT)) if err > 0.0 \
        else MAX_FACTOR
    if err <= 1.0 and rejected_before:
        factor = min(factor, 1.0)
    return factor


@njit(inline="always")
def blind_guard(err, trusted):
    """The step factor's cap and the new trusted error after an accepted step.

    The embedded estimate vanishes where the estimated local error changes sign; when one
    state carries the error (a one-DOF machine, whose angle grows without bound) this
    happens once per revolution, and the controller would grow the step up to 6-fold
    into a step whose true error is 6**9 times the tolerance. An estimate more than
    ``1/BLIND_DROP`` below the last trusted one does not grow the step; the trusted value
    decays by ``TRUST_DECAY`` per such step, so a genuine fall of the error (a motion
    settling) lets the step grow again after a few steps.
    """
    if trusted > 0.0 and err < BLIND_DROP * trusted:
        return 1.0, TRUST_DECAY * trusted
    return MAX_FACTOR, err


@njit(inline="always")
def stiffness_estimate(h, K, y_stage, y_new):
    """h times Hairer's estimate of the dominant eigenvalue's modulus:
    |f(y_new) - f(y_stage12)| / |y_new - y_stage12| (both at t + h)."""
    numerator = 0.0
    denominator = 0.0
    for i in range(y_new.shape[0]):
        numerator += (K[12, i] - K[11, i]) ** 2
        denominator += (y_new[i] - y_stage[i]) ** 2
    if denominator > 0.0:
        return abs(h) * math.sqrt(numerator / denominator)
    return 0.0


@njit
def dense_output(rhs, t, y, h, p, K, y_stage, y_new, poly):
    """The 7th-order continuous extension as ``poly[k, i]`` (k = 0..7) with
    y_i(t + x h) = sum_k poly[k, i] x^k; evaluates the three extra stages K[13:16]."""
    n = y.shape[0]
    for s in range(13, 16):
        _stage_argument(y, h, K, y_stage, s)
        rhs(t + C[s] * h, y_stage, p, K[s])
    # dop853.f's form: y + x(F0 + (1-x)(F1 + x(F2 + (1-x)(F3 + x(F4 + (1-x)(F5 + x F6))))))
    D3, D4, D5, D6 = D[0], D[1], D[2], D[3]
    for i in range(n):
        d3 = stage_sum(D3, K, i, 16)
        d4 = stage_sum(D4, K, i, 16)
        d5 = stage_sum(D5, K, i, 16)
        d6 = stage_sum(D6, K, i, 16)
        delta = y_new[i] - y[i]
        f_terms = (delta, h * K[0, i] - delta, 2.0 * delta - h * (K[12, i] + K[0, i]),
                   h * d3, h * d4, h * d5, h * d6)
        for k in range(8):
            poly[k, i] = 0.0
        poly[0, i] = f_terms[6]
        degree = 0
        for level in range(5, -1, -1):
            # multiply by x on even levels from the top, by (1 - x) on odd ones
            if (5 - level) % 2 == 0:
                for k in range(degree + 1, 0, -1):
                    poly[k, i] = poly[k - 1, i]
                poly[0, i] = 0.0
            else:
                for k in range(degree + 1, 0, -1):
                    poly[k, i] = poly[k, i] - poly[k - 1, i]
            degree += 1
            poly[0, i] += f_terms[level]
        for k in range(degree + 1, 0, -1):   # the final factor x, then + y
            poly[k, i] = poly[k - 1, i]
        poly[0, i] = y[i]


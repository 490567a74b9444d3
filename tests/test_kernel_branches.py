"""Each step-size control, error estimate and event-location branch of the compiled
kernels (mechdyn/kernels/dop853.py, rodas.py, events.py), called directly, against an
independent reference: a closed form, dop853.f's / rodas.f's formulas written out here,
or scipy's DOP853 error norm on the same stages.
"""
import math

import numpy as np
import pytest
from numba import njit
from scipy.integrate import DOP853 as ScipyDOP853
from scipy.integrate._ivp.dop853_coefficients import E3, E5

import mechdyn.kernels as mk
from mechdyn.kernels import dop853, rodas



@njit(mk.RHS_SIGNATURE, cache=True)
def linear(t, y, p, out):
    out[0] = p[0] * y[0]


@njit(mk.RHS_SIGNATURE, cache=True)
def not_finite(t, y, p, out):
    out[0] = math.inf if t > 0.0 else 1.0


def dop853_step(rhs, lam, h, y0=1.0):
    K, stage, y_new = np.zeros((16, 1)), np.zeros(1), np.zeros(1)
    y, p = np.array([y0]), np.array([lam])
    rhs(0.0, y, p, K[0])
    err = dop853.attempt(rhs, 0.0, y, h, h, p, np.full(1, 1e-12), 1e-10, K, stage, y_new)
    return err, K, y_new


# ------------------------------------------------------------------------- DOP853
@pytest.mark.parametrize("lam, h", [(3.0, 0.1), (3.0, 0.3), (-10.0, 0.1),   # the floor
                                    (-50.0, 0.3), (20.0, 1.0), (-10.0, 0.3)])  # the blend
def test_dop853_error_norm_is_scipys_blend_floored_at_a_tenth_of_the_fifth_order_one(lam, h):
    err, K, y_new = dop853_step(linear, lam, h)
    scale = 1e-12 + 1e-10 * np.maximum(1.0, np.abs(y_new))
    blend = ScipyDOP853(lambda t, y: lam * y, 0, [1.0], 1.0)._estimate_error_norm(
        K[:13], h, scale)
    fifth = abs(h) * np.linalg.norm(K[:13].T @ E5 / scale)
    # e5, e3 are sums of 12 terms that nearly cancel (by up to 1e8 here): the kernel's
    # loop and numpy's dot may each be off by 12 eps sum|terms|, and the norm
    # (e5^2 / sqrt(e5^2 + 0.01 e3^2)) triples a relative error in e5 or e3.
    rel = max(2 * 12 * np.finfo(float).eps * np.abs(K[:13, 0] * e).sum()
              / abs(K[:13, 0] @ e) for e in (E5, E3))
    assert err == pytest.approx(max(blend, 0.1 * fifth), rel=3 * rel + 1e-14)


def test_dop853_step_is_of_eighth_order_against_the_exponential():
    # local error C h^9: halving h divides it by 2^9 = 512
    errors = [abs(dop853_step(linear, 1.0, h)[2][0] - math.exp(h)) for h in (0.8, 0.4)]
    assert 512 / 1.5 < errors[0] / errors[1] < 512 * 1.5


def test_dop853_error_norm_is_zero_for_a_constant_and_inf_where_not_finite():
    assert dop853_step(linear, 0.0, 0.5)[0] == 0.0            # y' = 0: both estimates 0
    assert dop853_step(not_finite, 0.0, 0.5)[0] == math.inf


@pytest.mark.parametrize("err, rejected, expected", [
    (0.0, False, 6.0),                     # no error: the largest growth
    (1e-12, False, 6.0),                   # 0.9 err^(-1/8) = 28: capped at 6
    (1.0, False, 0.9),                     # the safety factor
    (0.9 ** 8, False, 1.0),                # 0.9 / 0.9 = 1
    (1e6, False, 0.333),                   # 0.9 / 1e6^(1/8) = 0.16: floored at 0.333
    (0.01, True, 1.0),                     # no growth right after a rejection
    (math.nan, False, 0.333), (math.inf, False, 0.333)])
def test_dop853_step_factor_follows_dop853f(err, rejected, expected):
    assert dop853.step_factor(err, rejected) == pytest.approx(expected, rel=1e-12)


def test_dop853_blind_guard_keeps_the_step_only_after_a_sudden_fall():
    assert dop853.blind_guard(0.5, 0.0) == (6.0, 0.5)          # nothing trusted yet
    assert dop853.blind_guard(0.02, 1.0) == (6.0, 0.02)        # a fall of 50: trusted
    cap, trusted = dop853.blind_guard(1e-4, 0.5)               # a fall of 5000: blind
    assert (cap, trusted) == (1.0, pytest.approx(0.05, rel=1e-15))


def test_dop853_stiffness_estimate_is_h_lambda_on_a_linear_equation():
    _, K, y_new = dop853_step(linear, -7.0, 0.2)
    stage = np.array([0.3])                         # any 12th-stage argument: K[11] = f
    K[11, 0], K[12, 0] = -7.0 * stage[0], -7.0 * y_new[0]
    assert dop853.stiffness_estimate(0.2, K, stage, y_new) == pytest.approx(1.4, rel=1e-12)
    assert dop853.stiffness_estimate(0.2, K, y_new.copy(), y_new) == 0.0   # no distance


# ------------------------------------------------------------------------- Rodas5P
SAFETY, MIN_FACTOR, MAX_FACTOR, EXPONENT = 0.9, 0.2, 6.0, 1 / 5   # rodas.f


def rodas_f(err, h, rejected, h_accepted, err_accepted):
    """rodas.f's controller written out: the classical factor, and Gustafsson's
    prediction once a step was accepted."""
    clip = lambda d: max(1 / MAX_FACTOR, min(1 / MIN_FACTOR, d))   # noqa: E731
    divisor = clip(err ** EXPONENT / SAFETY)
    if err <= 1 and h_accepted > 0:
        divisor = max(divisor, clip(h_accepted / h * (err * err / err_accepted) ** EXPONENT
                                    / SAFETY))
    factor = 1 / divisor
    return min(factor, 1.0) if err <= 1 and rejected else factor


@pytest.mark.parametrize("err, h, rejected, h_accepted, err_accepted", [
    (0.5, 0.1, False, 0.0, 0.0),           # first step: classical
    (1e-9, 0.1, False, 0.0, 0.0),          # capped growth (6)
    (0.5, 0.1, False, 0.1, 0.01),          # predictive: error grew since the last step
    (0.5, 0.1, True, 0.1, 0.9),            # after a rejection: no growth
    (30.0, 0.1, False, 0.1, 0.5),          # rejected: shrink
    (1e12, 0.1, False, 0.0, 0.0)])         # shrink floored (0.2)
def test_rodas_step_factor_follows_rodasf(err, h, rejected, h_accepted, err_accepted):
    assert rodas.step_factor(err, h, rejected, h_accepted, err_accepted) == \
        pytest.approx(rodas_f(err, h, rejected, h_accepted, err_accepted), rel=1e-12)


def test_rodas_step_factor_on_a_singular_or_non_finite_step():
    assert rodas.step_factor(math.nan, 0.1, False, 0.0, 0.0) == 0.5
    assert rodas.step_factor(math.inf, 0.1, False, 0.0, 0.0) == pytest.approx(MIN_FACTOR)


def test_rodas_spectral_radius_of_an_oscillator_and_of_a_zero_matrix():
    # J = [[0, 1], [-w^2, 0]]: J J = -w^2 I, so the estimate is w exactly
    w = 40.0
    v, work1, work2 = np.zeros(2), np.zeros(2), np.zeros(2)
    order, dense = np.arange(2), np.array([0, -1, -1])
    assert rodas.spectral_radius(np.array([[0.0, 1.0], [-w * w, 0.0]]), v, work1,
                                 work2, dense, order, order) == pytest.approx(w, rel=1e-14)
    assert rodas.spectral_radius(np.zeros((2, 2)), v, work1, work2, dense, order,
                                 order) == 0.0
    assert not v.any()                        # and the start vector is taken afresh


@pytest.mark.parametrize("coupled", [False, True])
def test_rodas_spectral_radius_with_the_structure_found_equals_the_dense_products(coupled):
    """Twenty oscillators w_i = 10 + i (coupled: also by springs to their neighbours),
    numbered [q..., u...]: the structure found (second order, reduced to a band) gives
    the estimate of the dense products."""
    from mechdyn.kernels import iteration
    n = 20
    J = np.zeros((2 * n, 2 * n))
    for i in range(n):
        J[i, n + i], J[n + i, i] = 1.0, -(10.0 + i) ** 2
        if coupled and i + 1 < n:
            J[n + i, i + 1] = J[n + i + 1, i] = 3.0
    plan, order, position = (np.zeros(iteration.plan_size(2 * n), np.int64),
                             np.zeros(2 * n, np.int64), np.zeros(2 * n, np.int64))
    iteration.plan(J, plan, order, position, np.zeros(2 * n, np.int64), np.zeros((n, n)),
                   np.zeros((2 * n, 2 * n)), False)
    assert plan[:3].tolist() == [1, int(coupled), int(coupled)]
    estimates = []
    for plan_ in (np.array([0, -1, -1]), plan):
        v = np.ones(2 * n)
        estimates.append(rodas.spectral_radius(J, v, np.zeros(2 * n), np.zeros(2 * n),
                                               plan_, order, position))
    assert estimates[1] == pytest.approx(estimates[0], rel=1e-14)
    assert 10.0 < estimates[0] <= 40.0


# ------------------------------------------------------------------------- events
@njit(mk.RHS_SIGNATURE, cache=True)
def clock(t, y, p, out):
    out[0] = 1.0


@njit(mk.RHS_SIGNATURE, cache=True)
def window(t, y, p, out):
    out[0] = (y[0] - 0.4) * (y[0] - 0.5)      # negative on (0.4, 0.5) only
    out[1] = y[0] - 0.45                       # rises through zero at 0.45 exactly


def clock_run(max_step, midpoint, directions):
    run = mk.Integration(mk.model_functions(clock, events=window), [], 0.0, [0.0],
                         rtol=1e-10, atol=1e-12, directions=directions, max_step=max_step,
                         h0=max_step,
                         midpoint_events=midpoint, detect_switch=False)
    return run, run.advance(1.0, 1000)


def test_a_crossing_and_back_within_a_step_is_found_by_the_midpoint_sample():
    # y = t exactly (the error estimate is 0: steps of max_step from the first). The
    # step [0, 0.9] ends where the first function is positive again: only its midpoint
    # sample (t = 0.45, inside the dip) sees it. The dip's first crossing is at t = 0.4.
    # The root's bracket closes to 4 eps t and y = t is exact to an ulp or two: 1e-14 is
    # ten times that (measured 8e-16).
    run, chunk = clock_run(0.9, True, [-1, 2])        # steps of 0.9: midpoint 0.45
    assert chunk.status == mk.EVENT and run.t == pytest.approx(0.4, abs=1e-14)
    run, chunk = clock_run(0.9, False, [-1, 2])       # end samples only: missed
    assert chunk.status == mk.FINISHED


def test_an_ignored_crossing_does_not_stop_and_the_watched_one_is_exact():
    run, chunk = clock_run(0.9, True, [2, +1])         # rising through 0.45
    assert chunk.status == mk.EVENT and run.t == pytest.approx(0.45, abs=1e-14)
    assert chunk.fired.tolist() == [0, 1]
    run, chunk = clock_run(0.9, True, [2, -1])         # it never falls
    assert chunk.status == mk.FINISHED and run.t == 1.0


@njit(mk.RHS_SIGNATURE, cache=True)
def _decay(t, y, p, out):
    out[0] = -p[0] * y[0]


@njit(mk.JAC_SIGNATURE, cache=True)
def _decay_jacobian(t, y, p, out):
    out[0, 0] = -p[0]


def test_rodas_counts_one_jacobian_an_accepted_step_and_eight_evaluations_an_attempt():
    """Counts of an autonomous run with an analytic Jacobian, from the kernel's own
    rule: f at the start and one for the first step's size, then per attempt one LU and
    eight evaluations (seven stages and the new point); the Jacobian is evaluated before
    each accepted step's first attempt (a rejected attempt reuses it)."""
    run = mk.Integration(mk.model_functions(_decay, _decay_jacobian), [50.0], 0.0, [1.0],
                         method=mk.RODAS5P, rtol=1e-8, atol=1e-10, autonomous=True,
                         detect_switch=False)
    assert run.advance(1.0, 10_000).status == mk.FINISHED
    stats = run.stats
    attempts = stats["naccept"] + stats["nreject"]
    assert stats["nreject"] > 0 or stats["naccept"] > 10
    assert stats["nlu"] == attempts
    assert stats["njev"] == stats["naccept"]
    assert stats["nfev"] == 2 + 8 * attempts
    assert run.y[0] == pytest.approx(math.exp(-50.0), abs=1e-9)

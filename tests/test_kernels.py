"""The compiled integration kernels (mechdyn.kernels) against closed forms and scipy.

Expected values come from closed forms (exponential decay, harmonic oscillator, the
rigid limit and the matrix exponential of the linear two-inertia drive, energy balance,
blow-up time of y' = y^2), never from the kernels themselves.
"""
import math

import numpy as np
import pytest
from numba import njit
from scipy.integrate import solve_ivp
from scipy.linalg import expm

import mechdyn as md
from mechdyn import kernels as mk
from mechdyn.simulate.error_control import guarded

METHODS = [mk.DOP853, mk.RODAS5P]
TIGHT = dict(rtol=1e-10, atol=1e-12)


@njit(mk.RHS_SIGNATURE, cache=True)
def decay(t, y, p, out):
    out[0] = -p[0] * y[0]


@njit(mk.RHS_SIGNATURE, cache=True)
def oscillator(t, y, p, out):
    out[0] = y[1]
    out[1] = -y[0]


@njit(mk.RHS_SIGNATURE, cache=True)
def oscillator_events(t, y, p, out):
    out[0] = y[0]          # cos t: falls through 0 at pi/2, rises at 3 pi/2
    out[1] = -y[0]         # the mirror image: fires at the same instants, other way
    out[2] = y[1]          # -sin t: exactly 0 at the start
    out[3] = y[0] - 0.5    # cos t = 1/2 at pi/3


@njit(mk.RHS_SIGNATURE, cache=True)
def drive(t, y, p, out):
    """Two inertias J1, J2, spring k, damper c, moment M on J1: y = phi1, phi2, w1, w2."""
    torque = p[2] * (y[0] - y[1]) + p[3] * (y[2] - y[3])
    out[0] = y[2]
    out[1] = y[3]
    out[2] = (p[4] - torque) / p[0]
    out[3] = torque / p[1]


@njit(mk.JAC_SIGNATURE, cache=True)
def drive_jacobian(t, y, p, out):
    out[:, :] = 0.0
    out[0, 2] = out[1, 3] = 1.0
    for row, inertia, sign in ((2, p[0], -1.0), (3, p[1], 1.0)):
        out[row, 0] = sign * p[2] / inertia
        out[row, 1] = -sign * p[2] / inertia
        out[row, 2] = sign * p[3] / inertia
        out[row, 3] = -sign * p[3] / inertia


@njit(mk.RHS_SIGNATURE, cache=True)
def crank(t, y, p, out):
    """I(phi) phi'' + 1/2 I'(phi) phi'^2 = M with I = J + m l^2 sin^2 phi."""
    s, c = math.sin(y[0]), math.cos(y[0])
    out[0] = y[1]
    out[1] = (p[2] - p[1] * s * c * y[1] ** 2) / (p[0] + p[1] * s * s)


@njit(mk.RHS_SIGNATURE, cache=True)
def forced_stiff(t, y, p, out):
    out[0] = -p[0] * (y[0] - math.cos(t))


@njit(mk.RHS_SIGNATURE, cache=True)
def van_der_pol(t, y, p, out):
    out[0] = y[1]
    out[1] = p[0] * (1.0 - y[0] ** 2) * y[1] - y[0]


@njit(mk.RHS_SIGNATURE, cache=True)
def robertson(t, y, p, out):
    out[0] = -0.04 * y[0] + 1e4 * y[1] * y[2]
    out[1] = 0.04 * y[0] - 1e4 * y[1] * y[2] - 3e7 * y[1] ** 2
    out[2] = 3e7 * y[1] ** 2


@njit(mk.RHS_SIGNATURE, cache=True)
def blow_up(t, y, p, out):
    out[0] = y[0] * y[0]


@njit(mk.RHS_SIGNATURE, cache=True)
def poisoned_after_half(t, y, p, out):
    out[0] = math.nan if t > 0.5 else 1.0


def solve(rhs, p, y0, t_end, method, jac=None, events=None, **options):
    options = {**TIGHT, "detect_switch": False, **options}
    run = mk.Integration(mk.model_functions(rhs, jac, events), p, 0.0, y0, method=method,
                         **options)
    return run, run.advance(t_end, max_steps=10 ** 6)


J1, J2, K, M = 1.0, 1e-4, 1e6, 10.0
C_DAMPED = 2 * 0.1 * math.sqrt(K * J1 * J2 / (J1 + J2))


def drive_exact(times, c):
    """The linear drive y' = A y + b by the matrix exponential of [[A, b], [0, 0]]."""
    a = np.zeros((5, 5))
    a[0, 2] = a[1, 3] = 1.0
    a[2, :4] = np.array([-K, K, -c, c]) / J1
    a[3, :4] = np.array([K, -K, c, -c]) / J2
    a[2, 4] = M / J1
    return np.array([(expm(a * t) @ [0, 0, 0, 0, 1.0])[:4] for t in np.atleast_1d(times)])


# ------------------------------------------------------------------------ closed forms
@pytest.mark.parametrize("method", METHODS)
def test_exponential_decay_matches_closed_form_at_steps_and_in_between(method):
    run, chunk = solve(decay, [2.0], [1.0], 1.0, method, autonomous=True)
    assert chunk.status == mk.FINISHED and run.t == 1.0
    assert np.max(np.abs(chunk.ys[:, 0] - np.exp(-2 * chunk.ts))) < 1e-9
    times = np.linspace(0.0, 1.0, 1001)
    dense = mk.dense_values(chunk.ts, chunk.coefs, times)[:, 0]
    assert np.max(np.abs(dense - np.exp(-2 * times))) < 1e-9


@pytest.mark.parametrize("method", METHODS)
def test_harmonic_oscillator_keeps_phase_and_energy_over_ten_periods(method):
    t_end = 20 * math.pi
    run, chunk = solve(oscillator, [], [1.0, 0.0], t_end, method)
    assert np.allclose(run.y, [1.0, 0.0], atol=1e-7)
    times = np.linspace(0.0, t_end, 5001)
    dense = mk.dense_values(chunk.ts, chunk.coefs, times)
    assert np.max(np.abs(dense[:, 0] - np.cos(times))) < 1e-7
    energy = 0.5 * (dense[:, 0] ** 2 + dense[:, 1] ** 2)
    assert np.max(np.abs(energy - 0.5)) < 1e-7


def test_rodas5p_uses_the_time_derivative_of_a_forced_stiff_problem():
    # y' = -lam (y - cos t): y = (lam^2 cos t + lam sin t) / (lam^2 + 1) + C e^(-lam t)
    lam = 1e4
    run, chunk = solve(forced_stiff, [lam], [0.0], 2.0, mk.RODAS5P)
    times = np.linspace(0.01, 2.0, 500)
    exact = (lam ** 2 * np.cos(times) + lam * np.sin(times)) / (lam ** 2 + 1)
    dense = mk.dense_values(chunk.ts, chunk.coefs, times)[:, 0]
    assert np.max(np.abs(dense - exact)) < 1e-9


@pytest.mark.parametrize("method,jacobian", [(mk.DOP853, None), (mk.RODAS5P, None),
                                             (mk.RODAS5P, drive_jacobian)])
def test_stiff_damped_drive_matches_matrix_exponential_and_rigid_limit(method, jacobian):
    run, chunk = solve(drive, [J1, J2, K, C_DAMPED, M], np.zeros(4), 1.0, method,
                       jac=jacobian, autonomous=True)
    assert chunk.status == mk.FINISHED
    rigid = M / (2 * (J1 + J2))            # phi = M t^2 / (2 (J1 + J2)) at t = 1
    assert abs(run.y[0] - rigid) < 1e-6 and abs(run.y[1] - rigid) < 1e-6
    times = np.linspace(0.0, 1.0, 41)
    exact = drive_exact(times, C_DAMPED)
    dense = mk.dense_values(chunk.ts, chunk.coefs, times)
    assert np.max(np.abs(dense[:, :2] - exact[:, :2])) < 1e-8
    assert np.max(np.abs(dense[:, 2:] - exact[:, 2:])) < 1e-6


@pytest.mark.parametrize("method,t_end", [(mk.DOP853, 1.0), (mk.RODAS5P, 0.2)])
def test_undamped_stiff_drive_keeps_energy_equal_to_the_work_of_the_moment(method, t_end):
    run, chunk = solve(drive, [J1, J2, K, 0.0, M], np.zeros(4), t_end, method,
                       jac=drive_jacobian, autonomous=True)
    phi1, phi2, w1, w2 = chunk.ys.T
    energy = 0.5 * J1 * w1 ** 2 + 0.5 * J2 * w2 ** 2 + 0.5 * K * (phi1 - phi2) ** 2
    work = M * phi1
    assert chunk.status == mk.FINISHED
    assert np.max(np.abs(energy - work)[1:] / work[1:]) < 1e-6


# ------------------------------------------------------------------------------ events
def oscillator_run(method, directions):
    return solve(oscillator, [], [1.0, 0.0], 10.0, method, events=oscillator_events,
                 directions=directions)


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("direction,expected_time,expected_sign", [
    (mk.FALLING, math.pi / 2, -1), (mk.RISING, 3 * math.pi / 2, 1),
    (mk.EITHER, math.pi / 2, -1)])
def test_event_direction_selects_the_crossing(method, direction, expected_time,
                                              expected_sign):
    run, chunk = oscillator_run(method, [direction, mk.IGNORED, mk.IGNORED, mk.IGNORED])
    assert chunk.status == mk.EVENT
    assert abs(run.t - expected_time) < 1e-9 and chunk.ts[-1] == run.t
    assert chunk.fired.tolist() == [expected_sign, 0, 0, 0]
    assert np.allclose(run.y, [math.cos(run.t), -math.sin(run.t)], atol=1e-9)


@pytest.mark.parametrize("method", METHODS)
def test_event_function_zero_at_the_start_fires_only_on_its_next_crossing(method):
    # -sin t is 0 at t = 0 and negative just after: falling fires at 2 pi, not at 0
    run, chunk = oscillator_run(method, [mk.IGNORED, mk.IGNORED, mk.FALLING, mk.IGNORED])
    assert chunk.status == mk.EVENT and abs(run.t - 2 * math.pi) < 1e-9
    run, chunk = oscillator_run(method, [mk.IGNORED, mk.IGNORED, mk.EITHER, mk.IGNORED])
    assert abs(run.t - math.pi) < 1e-9 and chunk.fired[2] == 1


@pytest.mark.parametrize("method", METHODS)
def test_simultaneous_events_fire_together_and_the_run_continues_past_them(method):
    run, chunk = oscillator_run(method, [mk.EITHER, mk.EITHER, mk.IGNORED, mk.IGNORED])
    assert abs(run.t - math.pi / 2) < 1e-9 and chunk.fired.tolist() == [-1, 1, 0, 0]
    chunk = run.advance(10.0)            # the same events do not fire again at once
    assert chunk.status == mk.EVENT and abs(run.t - 3 * math.pi / 2) < 1e-9
    assert chunk.fired.tolist() == [1, -1, 0, 0]


def test_watched_event_before_an_ignored_one_and_the_earliest_of_several_wins():
    run, chunk = oscillator_run(mk.DOP853, [mk.EITHER, mk.IGNORED, mk.IGNORED, mk.FALLING])
    assert abs(run.t - math.pi / 3) < 1e-9 and chunk.fired.tolist() == [0, 0, 0, -1]


def test_changing_the_watched_events_at_a_stop_takes_their_signs_afresh():
    ignored = mk.IGNORED
    run, chunk = oscillator_run(mk.RODAS5P, [mk.FALLING, ignored, ignored, ignored])
    assert abs(run.t - math.pi / 2) < 1e-9
    run.change_model(directions=[mk.IGNORED, mk.EITHER, mk.IGNORED, mk.RISING])
    chunk = run.advance(10.0)                  # -cos t rises through 0 at pi/2 itself: no
    assert abs(run.t - 3 * math.pi / 2) < 1e-9 and chunk.fired.tolist() == [0, -1, 0, 0]
    chunk = run.advance(10.0)                  # cos t = 1/2 rising at 5 pi / 3
    assert abs(run.t - 5 * math.pi / 3) < 1e-9 and chunk.fired.tolist() == [0, 0, 0, 1]


# -------------------------------------------------------------------- chunks, statuses
@pytest.mark.parametrize("method", METHODS)
def test_many_short_chunks_give_exactly_the_result_of_one_long_call(method):
    def run(chunk_steps):
        integration = mk.Integration(mk.model_functions(crank), [0.5, 2.0, 3.0], 0.0,
                                     [0.0, 0.0], method=method, rtol=1e-8, atol=1e-10,
                                     detect_switch=False)
        chunks = [integration.advance(5.0, chunk_steps)]
        while chunks[-1].status == mk.CHUNK_FULL:
            chunks.append(integration.advance(5.0, chunk_steps))
        ts = np.concatenate([chunks[0].ts[:1]] + [c.ts[1:] for c in chunks])
        coefs = np.concatenate([c.coefs for c in chunks])
        return ts, coefs, integration.y, chunks[-1].status

    whole, pieces = run(10 ** 6), run(7)
    assert whole[3] == pieces[3] == mk.FINISHED
    for a, b in zip(whole[:3], pieces[:3]):
        assert np.array_equal(a, b)


def test_raw_kernel_appends_chunks_into_the_callers_buffers():
    functions, p = mk.model_functions(crank), np.array([0.5, 2.0, 3.0])
    capacity, no_events = 1000, np.zeros(0, np.int64)
    ts, ys = np.zeros(capacity + 1), np.zeros((capacity + 1, 2))
    coefs = np.zeros((capacity, 8, 2))
    carry, counts = mk.new_carry(0.0, [0.0, 0.0]), np.zeros(6, np.int64)

    def call(first, max_steps):
        return mk.integrate(mk.DOP853, functions.addresses, p, 5.0, 1e-8, np.full(2, 1e-10),
                            np.inf, False, False, False, no_events, max_steps, carry,
                            counts, ts, ys, coefs, first, no_events)
    first, status = 0, mk.CHUNK_FULL
    while status == mk.CHUNK_FULL:
        status, steps = call(first, 5)
        first += steps
    run, chunk = solve(crank, p, [0.0, 0.0], 5.0, mk.DOP853, rtol=1e-8, atol=1e-10)
    assert status == mk.FINISHED and counts[mk.layout.NACCEPT] == first
    assert np.array_equal(ts[:first + 1], chunk.ts)
    assert np.array_equal(coefs[:first], chunk.coefs)
    assert call(capacity + 1, 5) == (mk.INVALID_INPUT, 0)     # beyond the buffers: refused


def test_dop853_reports_stiffness_and_rodas5p_finishes_from_there():
    run, chunk = solve(van_der_pol, [1000.0], [2.0, 0.0], 3000.0, mk.DOP853, rtol=1e-6,
                       atol=1e-8, detect_switch=True)
    assert chunk.status == mk.STIFF and run.t < 1.0
    run.switch(mk.RODAS5P)
    run.detect_switch = False
    chunk = run.advance(3000.0, 10 ** 6)
    assert chunk.status == mk.FINISHED and run.t == 3000.0


def test_no_stiffness_reported_on_a_harmonic_oscillator_and_rodas5p_says_nonstiff():
    run, chunk = solve(oscillator, [], [1.0, 0.0], 200 * math.pi, mk.DOP853, rtol=1e-6,
                       atol=1e-9, detect_switch=True)
    assert chunk.status == mk.FINISHED
    run, chunk = solve(oscillator, [], [1.0, 0.0], 200 * math.pi, mk.RODAS5P, rtol=1e-6,
                       atol=1e-9, detect_switch=True)
    assert chunk.status == mk.NONSTIFF and run.t < 200 * math.pi


@pytest.mark.parametrize("method", METHODS)
def test_blow_up_ends_with_step_too_small_just_before_the_singularity(method):
    run, chunk = solve(blow_up, [], [1.0], 2.0, method)    # y = 1 / (1 - t)
    assert chunk.status == mk.STEP_TOO_SMALL and abs(run.t - 1.0) < 1e-6


@pytest.mark.parametrize("method", METHODS)
def test_non_finite_derivative_is_reported_where_it_starts(method):
    run, chunk = solve(poisoned_after_half, [], [0.0], 1.0, method)
    assert chunk.status == mk.NOT_FINITE and 0.5 - 1e-6 < run.t <= 0.5
    assert abs(run.y[0] - run.t) < 1e-9
    run, chunk = solve(poisoned_after_half, [], [0.0], 1.0, method)
    run.carry[mk.layout.T] = 0.75             # restarting inside the poisoned region
    chunk = run.advance(1.0)
    assert chunk.status == mk.NOT_FINITE and chunk.ts.tolist() == [0.75] and run.t == 0.75


def test_max_step_bounds_every_step():
    run, chunk = solve(decay, [1.0], [1.0], 1.0, mk.DOP853, max_step=0.01)
    assert np.max(np.diff(chunk.ts)) <= 0.01 * (1 + 1e-12) and chunk.status == mk.FINISHED


# ------------------------------------------------------------ scipy, compilation, input
def scipy_function(rhs, p):
    def f(t, y):
        out = np.empty(len(y))
        rhs(t, np.ascontiguousarray(y), np.asarray(p, dtype=float), out)
        return out
    return f


def test_dop853_agrees_with_scipy_dop853_on_a_nonlinear_crank():
    # The same method at the same tolerance: about the same steps and the same global
    # error against a tight reference. (Comparing the two runs with each other would
    # test the last step of the controllers: one step more or less on another machine
    # or scipy release moves them 1e-8 apart, while both are 1e-7 off the motion.)
    p = [0.5, 2.0, 3.0]
    run, chunk = solve(crank, p, [0.0, 0.0], 5.0, mk.DOP853)
    f = scipy_function(crank, p)
    scipy_run = solve_ivp(f, (0.0, 5.0), [0.0, 0.0], method="DOP853", rtol=1e-10,
                          atol=1e-12, dense_output=True)
    tight = solve_ivp(f, (0.0, 5.0), [0.0, 0.0], method="DOP853", rtol=3e-14, atol=1e-16,
                      dense_output=True)
    times = np.linspace(0.0, 5.0, 101)
    mine = np.max(np.abs(mk.dense_values(chunk.ts, chunk.coefs, times) - tight.sol(times).T))
    theirs = np.max(np.abs(scipy_run.sol(times).T - tight.sol(times).T))
    assert mine < 1e-6 and mine <= 1.25 * theirs
    # the step count against scipy's DOP853 under the kernel's error control (its
    # estimate floored at a tenth of the 5th-order one, the blind guard): more steps than
    # scipy's own where Hairer's blend flatters the step (docs/hard-cases.md)
    same_control = solve_ivp(f, (0.0, 5.0), [0.0, 0.0], method=guarded("DOP853"),
                             rtol=1e-10, atol=1e-12)
    assert abs(len(chunk.ts) - len(same_control.t)) <= 0.05 * len(same_control.t)


def test_rodas5p_agrees_with_scipy_radau_on_robertson_kinetics():
    run, chunk = solve(robertson, [], [1.0, 0.0, 0.0], 1e5, mk.RODAS5P, rtol=1e-8,
                       atol=1e-12, autonomous=True)
    reference = solve_ivp(scipy_function(robertson, []), (0.0, 1e5), [1.0, 0.0, 0.0],
                          method="Radau", rtol=1e-8, atol=1e-12, dense_output=True)
    times = np.logspace(-5, 5, 41)
    mine = mk.dense_values(chunk.ts, chunk.coefs, times)
    theirs = reference.sol(times).T
    assert np.all(np.abs(mine - theirs) <= 1e-6 * np.abs(theirs) + 1e-11)
    assert np.max(np.abs(mine.sum(axis=1) - 1.0)) < 1e-10   # mass is conserved


def test_kernel_is_compiled_once_for_all_models():
    signatures = list(mk.integrate.signatures)
    solve(decay, [1.0], [1.0], 1.0, mk.DOP853)
    solve(oscillator, [], [1.0, 0.0], 1.0, mk.RODAS5P)
    assert len(signatures) == 1 and list(mk.integrate.signatures) == signatures


def test_every_compiled_kernel_module_keys_the_cache():
    from pathlib import Path
    from mechdyn.kernels import loop
    python_side = {"__init__", "api", "startup"}
    modules = {path.stem for path in Path(loop.__file__).parent.glob("*.py")}
    assert modules - python_side == set(loop.COMPILED_MODULES)


def test_a_lazily_compiled_numba_function_is_compiled_for_the_kernel():
    @njit
    def lazy(t, y, p, out):
        out[0] = -y[0]
    run = mk.Integration(mk.model_functions(lazy), [], 0.0, [1.0], **TIGHT)
    assert run.advance(1.0).status == mk.FINISHED and abs(run.y[0] - math.exp(-1)) < 1e-9


def test_bad_inputs_name_the_culprit():
    @njit("void(float64, float64[:], float64[:], float64[:])")
    def strided(t, y, p, out):
        out[0] = 0.0
    with pytest.raises(md.MechdynError, match="strided"):
        mk.model_functions(strided)
    functions = mk.model_functions(decay)
    with pytest.raises(md.ParameterError, match="atol"):
        mk.Integration(functions, [1.0], 0.0, [1.0], atol=-1.0)
    with pytest.raises(md.ParameterError, match="event directions"):
        mk.Integration(functions, [1.0], 0.0, [1.0], directions=[0])
    with pytest.raises(md.ParameterError, match="y0"):
        mk.Integration(functions, [1.0], 0.0, [math.nan])


def test_the_kernels_start_up_pauses_the_collector_and_respects_a_disabled_one():
    import gc
    import weakref
    from mechdyn.kernels.startup import collector_paused

    class Node:
        pass
    assert gc.isenabled()
    with collector_paused():
        assert not gc.isenabled()
        garbage = Node()
        garbage.itself = garbage               # a cycle made during the start-up ...
        dead = weakref.ref(garbage)
        del garbage
        kept = Node()
    assert gc.isenabled() and dead() is None  # ... freed at its end, not frozen
    assert not any(o is kept for o in gc.get_objects())   # what lives is frozen
    gc.disable()
    try:
        frozen = gc.get_freeze_count()
        with collector_paused():
            assert not gc.isenabled()
        assert not gc.isenabled() and gc.get_freeze_count() == frozen
    finally:
        gc.enable()


def test_a_cfunc_model_function_integrates_like_an_njit_one():
    from numba import cfunc

    @cfunc(mk.RHS_SIGNATURE)
    def c_decay(t, y, p, out):
        out[0] = -p[0] * y[0]
    run = mk.Integration(mk.model_functions(c_decay), [2.0], 0.0, [1.0], **TIGHT)
    assert run.advance(1.0).status == mk.FINISHED
    assert abs(run.y[0] - math.exp(-2.0)) < 1e-9
    with pytest.raises(md.MechdynError, match="must be a numba function"):
        mk.model_functions(lambda t, y, p, out: None)


def test_integrating_backwards_is_refused_naming_both_times():
    run = mk.Integration(mk.model_functions(decay), [2.0], 0.0, [1.0], **TIGHT)
    run.advance(1.0)
    with pytest.raises(md.ParameterError, match="t_bound 0.5 lies before the current time 1.0"):
        run.advance(0.5)
    assert run.t == 1.0 and abs(run.y[0] - math.exp(-2.0)) < 1e-9     # left as it was


@njit(mk.RHS_SIGNATURE, cache=True)
def starts_at_one(t, y, p, out):
    out[0] = 1.0 if t > 1.0 else 0.0          # y = max(t - 1, 0): exactly 0 until t = 1


@njit(mk.EVENTS_SIGNATURE, cache=True)
def position_event(t, y, p, out):
    out[0] = y[0]


@pytest.mark.parametrize("method", METHODS)
def test_a_side_set_for_a_zero_event_function_holds_across_short_calls(method):
    # g = y is exactly 0 until t = 1; its caller set it on the side before a rising
    # crossing (carry's sign memory), so it fires at the first point where y > 0, near
    # t = 1: in one long call, and in calls of one step each, which continue exactly
    # (the module doc).
    from mechdyn.kernels.layout import EVENTS_VALID, HEAD
    for max_steps in (10 ** 6, 1):
        run = mk.Integration(mk.model_functions(starts_at_one, events=position_event), [],
                             0.0, [0.0], method=method, directions=[mk.RISING],
                             detect_switch=False, **TIGHT)
        run.carry[EVENTS_VALID], run.carry[HEAD + 2] = 1.0, -1.0
        chunk = run.advance(3.0, max_steps=max_steps)
        while chunk.status == mk.CHUNK_FULL:
            chunk = run.advance(3.0, max_steps=max_steps)
        assert chunk.status == mk.EVENT and chunk.fired.tolist() == [1]
        assert abs(run.t - 1.0) < 1e-6 and run.y[0] > 0.0   # a step straddles t = 1


@njit(mk.RHS_SIGNATURE, cache=True)
def slow_drift_noting_times(t, y, p, out):
    out[0] = 1.0
    p[0] = max(p[0], t)                  # the latest time the model was evaluated at


@pytest.mark.parametrize("method", METHODS)
def test_the_model_is_never_evaluated_beyond_t_bound(method):
    # y = 1000 + t: Hairer's first guess 0.01 |y| / |f| = 10 s is far beyond the 0.1 s
    # left from t0 = 0.4; the starting step's probe, and every stage, stays within it.
    run = mk.Integration(mk.model_functions(slow_drift_noting_times), [0.0], 0.4,
                         [1000.0], method=method, **TIGHT)
    assert run.advance(0.5).status == mk.FINISHED
    assert run.y[0] == pytest.approx(1000.1, rel=1e-12)
    assert run.p[0] <= 0.5

"""Stop conditions: ``md.reaches(expr, value, direction=...)`` stops at the crossing in its
direction, from either side, and a condition met exactly at the start is watched from
there (issue 20 item 1).

Expected times are the crossings of cos t and sin t, solved by hand:
cos t = 1/2 at t = pi/3 (falling) and 5 pi/3 (rising); -cos t = 1/2 at 2 pi/3 (rising) and
4 pi/3 (falling); sin t = 0 at pi (falling) and 2 pi (rising).
"""
import math

import pytest
import sympy as sp
from scipy.special import ellipk

import mechdyn as md

q = md.coordinate("q")


def oscillator():
    """J = 1 on a spring k = 1: q'' = -q, so q = q0 cos t + u0 sin t exactly."""
    mech = md.Mechanism("unit oscillator", [q])
    mech.link("mass", J=1, angle=q)
    mech.spring("spring", 1, stretch=q)
    return mech


def stop_time(condition, q0, u0, backend=None):
    scene = md.Scene("run", initial={q: q0, md.speed(q): u0}, until=condition, t_end=10)
    res = oscillator().simulate(scene, {}, backend=backend)
    assert res.reason == repr(condition)
    return res.t_end


cos_t, minus_cos_t = sp.cos(md.t), -sp.cos(md.t)

# (expression, initial state giving q = that expression, direction, expected stop time)
FROM_ABOVE = [(+1, 5 * math.pi / 3), (-1, math.pi / 3), (0, math.pi / 3)]
FROM_BELOW = [(+1, 2 * math.pi / 3), (-1, 4 * math.pi / 3), (0, 2 * math.pi / 3)]


@pytest.mark.parametrize("direction, expected", [
    pytest.param(d, e, id=f"direction {d:+d}") for d, e in FROM_ABOVE])
def test_coordinate_starting_above_the_value_stops_at_the_crossing_in_its_direction(
        direction, expected):
    # q = cos t starts at 1 > 1/2.
    assert stop_time(md.reaches(q, 0.5, direction=direction), 1, 0) == \
        pytest.approx(expected, rel=1e-8)


@pytest.mark.parametrize("direction, expected", [
    pytest.param(d, e, id=f"direction {d:+d}") for d, e in FROM_BELOW])
def test_coordinate_starting_below_the_value_stops_at_the_crossing_in_its_direction(
        direction, expected):
    # q = -cos t starts at -1 < 1/2.
    assert stop_time(md.reaches(q, 0.5, direction=direction), -1, 0) == \
        pytest.approx(expected, rel=1e-8)


def _time_only_cases():
    # A system at rest: the solver's steps grow to the whole run (nothing bounds them);
    # the crossings of a condition of t alone are solved without the steps.
    for name, expression, crossings in (("cos t", cos_t, FROM_ABOVE),
                                        ("-cos t", minus_cos_t, FROM_BELOW)):
        for direction, expected in crossings:
            yield pytest.param(expression, direction, expected,
                               id=f"{name} direction {direction:+d}")


BACKENDS = ["scipy", "compiled"]


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("expression, direction, expected", list(_time_only_cases()))
def test_expression_of_time_stops_at_the_crossing_in_its_direction(
        expression, direction, expected, backend):
    # The condition need not involve the state: an expression of md.t alone, integrated
    # alongside a system at rest.
    assert stop_time(md.reaches(expression, 0.5, direction=direction), 0, 0, backend) == \
        pytest.approx(expected, rel=1e-8)


# ------------------------------------------------------------ met exactly at the start
@pytest.mark.parametrize("direction, expected", [(+1, 2 * math.pi), (-1, math.pi),
                                                 (0, math.pi)])
def test_condition_met_at_the_start_stops_at_its_next_crossing(direction, expected):
    # q = sin t: q = 0 at the start, rising. Leaving the value is not a crossing; the next
    # falling crossing is at pi, the next rising one at 2 pi.
    assert stop_time(md.reaches(q, 0, direction=direction), 0, 1) == \
        pytest.approx(expected, rel=1e-8)


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("direction, expected", [(+1, 2 * math.pi), (-1, math.pi)])
def test_expression_of_time_met_at_the_start_stops_at_its_next_crossing(direction, expected,
                                                                        backend):
    assert stop_time(md.reaches(sp.sin(md.t), 0, direction=direction), 0, 0, backend) == \
        pytest.approx(expected, rel=1e-8)


@pytest.mark.parametrize("direction, expected", [(+1, 2 * math.pi / 3),
                                                 (-1, 4 * math.pi / 3)])
def test_expression_of_time_stops_at_its_crossing_while_the_state_moves(direction, expected):
    # The same -cos t = 1/2 crossings (2 pi/3 rising, 4 pi/3 falling) with the oscillator
    # swinging (q = sin t): the motion keeps the steps short, and the crossings are found.
    assert stop_time(md.reaches(minus_cos_t, 0.5, direction=direction), 0, 1) == \
        pytest.approx(expected, rel=1e-8)


def pendulum():
    mech = md.Mechanism("pendulum", [q])
    mech.link("bob", m=1, x=sp.sin(q), y=-sp.cos(q))    # length 1
    mech.gravity(9.81)
    return mech


@pytest.mark.parametrize("amplitude", [0.5, 2.0])
def test_pendulum_released_from_rest_runs_to_its_next_turning_point(amplitude):
    # stopped(q) is met at the release (speed 0). The run ends at the next turning point,
    # half a period later: T/2 = 2 sqrt(l/g) K(k), k = sin(amplitude/2) (complete elliptic
    # integral of the first kind, scipy's ellipk takes m = k^2), where q = -amplitude by
    # energy conservation.
    scene = md.Scene("swing", initial={q: amplitude, md.speed(q): 0}, until=md.stopped(q),
                     t_end=10)
    res = pendulum().simulate(scene, {})
    half_period = 2 * math.sqrt(1 / 9.81) * ellipk(math.sin(amplitude / 2) ** 2)
    assert res.reason == "stopped(q)"
    assert res.t_end == pytest.approx(half_period, rel=1e-8)
    assert res.final(q) == pytest.approx(-amplitude, rel=1e-8)


def test_small_swing_half_period_is_the_textbook_value():
    # The reference used above, checked against the small-amplitude formula
    # T/2 = pi sqrt(l/g) (1 + a^2/16): the test's own arithmetic, not mechdyn's.
    a = 0.01
    exact = 2 * math.sqrt(1 / 9.81) * ellipk(math.sin(a / 2) ** 2)
    assert exact == pytest.approx(math.pi * math.sqrt(1 / 9.81) * (1 + a * a / 16), rel=1e-9)


def test_pendulum_released_from_rest_stops_at_the_turning_point_of_a_nonzero_start():
    # Released with a small push (speed not zero): the next zero of the speed is the first
    # turning point; today's semantics and the rewrite agree here. With q0 = 0 and speed
    # u0 the swing reaches amplitude a with u0^2 = 2 g (1 - cos a), after a quarter
    # period T/4 = sqrt(l/g) K(sin^2(a/2)).
    a = 1.0
    u0 = math.sqrt(2 * 9.81 * (1 - math.cos(a)))
    scene = md.Scene("swing", initial={q: 0, md.speed(q): u0}, until=md.stopped(q), t_end=10)
    res = pendulum().simulate(scene, {})
    assert res.t_end == pytest.approx(math.sqrt(1 / 9.81) * ellipk(math.sin(a / 2) ** 2),
                                      rel=1e-8)
    assert res.final(q) == pytest.approx(a, rel=1e-8)

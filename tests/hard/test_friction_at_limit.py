"""Coulomb friction exactly at its limit, with zero capacity, at a step of the load, and
against a load that exceeds the capacity briefly between solver steps (issue 20 item 2,
the defects of issue 14). A shaft of inertia J = 1 unless said otherwise; expected
values are the impulse balance J omega' = load - friction integrated by hand."""
import math

import numpy as np
import pytest
import sympy as sp

import mechdyn as md

phi = md.coordinate("phi")
t = md.t


def shaft(load, capacity, inertia=1):
    mech = md.Mechanism("braked shaft", [phi])
    mech.link("shaft", J=inertia, angle=phi)
    mech.load("load", load, along=phi)
    mech.friction("brake", capacity, along=phi)
    return mech


def run(mech, t_end, **scene):
    return mech.simulate(md.Scene("run", initial={phi: 0, md.speed(phi): 0}, t_end=t_end,
                                  **scene), {})


def slips(res):
    return [e for e in res.events if e.kind == "slip"]


@pytest.mark.parametrize("sign", [+1, -1])
def test_load_exactly_at_the_brake_capacity_is_held_with_no_slip(sign):
    # Load 25 against a brake of 25: the holding moment needed equals the capacity, which
    # holds (stick while |holding| <= capacity). Nothing moves, ever.
    res = run(shaft(sign * 25, 25), 3, outputs=["brake"])
    assert slips(res) == []
    assert np.all(res[phi] == 0.0) and np.all(res[md.speed(phi)] == 0.0)
    assert res.final(phi) == 0.0 and res.final(md.speed(phi)) == 0.0
    assert res.at(2.0, md.speed(phi)) == 0.0
    assert res["brake"] == pytest.approx(np.full(len(res.t), -sign * 25.0), rel=1e-12)


@pytest.mark.parametrize("sign", [+1, -1])
def test_brake_held_at_its_limit_releases_as_soon_as_the_load_grows(sign):
    # Load 25 + 10 max(0, t - 1) against 25: held exactly at the limit until t = 1, then
    # J omega' = 10 (t - 1) sliding forward: omega(3) = 5 * 2^2 = 20, phi(3) = 10/6 * 2^3.
    res = run(shaft(sign * (25 + 10 * sp.Max(0, t - 1)), 25), 3)
    assert [e.time for e in slips(res)] == [pytest.approx(1.0, abs=1e-8)]
    assert np.all(res[phi][res.t < 1.0] == 0.0)
    assert res.final(md.speed(phi)) == pytest.approx(sign * 20.0, rel=1e-9)
    assert res.final(phi) == pytest.approx(sign * 40.0 / 3.0, rel=1e-9)


def test_held_shaft_never_moves_while_the_load_stays_just_below_the_capacity():
    # Load 25 (1 - exp(-t)) approaches 25 from below and never exceeds it.
    res = run(shaft(25 * (1 - sp.exp(-t)), 25), 20)
    assert slips(res) == [] and np.all(res[phi] == 0.0)


def test_friction_with_zero_capacity_at_rest_releases_when_a_load_appears():
    # A clutch not yet pressed (capacity 10 max(0, t - 5): zero over the whole run) on a
    # shaft at rest. The load 10 max(0, t - 1) meets no resistance: from t = 1,
    # omega' = 10 (t - 1), omega(3) = 20, phi(3) = 40/3.
    res = run(shaft(10 * sp.Max(0, t - 1), 10 * sp.Max(0, t - 5)), 3)
    assert res.final(md.speed(phi)) == pytest.approx(20.0, rel=1e-9)
    assert res.final(phi) == pytest.approx(40.0 / 3.0, rel=1e-9)
    assert all(e.time == pytest.approx(1.0, abs=1e-8) for e in slips(res))


def test_friction_with_zero_capacity_releases_at_a_step_of_the_load():
    # Same clutch, load stepping from 0 to 20 at t = 1: omega(3) = 20 * 2 = 40.
    res = run(shaft(sp.Piecewise((0, t < 1), (20, True)), 10 * sp.Max(0, t - 5)), 3)
    assert res.final(md.speed(phi)) == pytest.approx(40.0, rel=1e-9)
    assert res.final(phi) == pytest.approx(40.0, rel=1e-9)


@pytest.mark.parametrize("sign", [+1, -1])
def test_release_at_a_step_of_the_load_slides_the_way_the_load_pushes_after_the_step(sign):
    # Brake 5, load stepping from 0 to 20 at t = 1. The holding moment jumps from 0 to 20
    # there; the brake releases at the step and slides the way the load pushes:
    # J omega' = 20 - 5 from t = 1, omega(3) = 30, phi(3) = 15 * 2^2 / 2 = 30. Sliding the
    # other way first would add a spurious slip event and a stick (the old driver located
    # the release just before the step, where the holding moment is 0, and slid backward
    # for good: omega(3) = 50).
    res = run(shaft(sign * sp.Piecewise((0, t < 1), (20, True)), 5), 3)
    assert [e.time for e in slips(res)] == [pytest.approx(1.0, abs=1e-8)]
    assert [e.kind for e in res.events] == ["slip"]
    assert ("forward" if sign > 0 else "backward") in slips(res)[0].detail
    assert res.final(md.speed(phi)) == pytest.approx(sign * 30.0, rel=1e-9)
    assert res.final(phi) == pytest.approx(sign * 30.0, rel=1e-9)


# A stuck mass under F = 5 + 15 sin(pi t / 2) against a capacity of 15: F0 = 5 < 15 <
# F0 + A = 20. The first release is where F reaches 15: sin(pi t / 2) = 2/3.
T_RELEASE = 2 / math.pi * math.asin(2 / 3)


def sine_driven():
    return shaft(5 + 15 * sp.sin(sp.pi * t / 2), 15)


def speed_after_release(time):
    # omega(t) = int_{t1}^{t} (F - 15) ds = -10 (t - t1) - 30/pi (cos(pi t/2) - cos(pi t1/2))
    return -10 * (time - T_RELEASE) - 30 / math.pi * (math.cos(math.pi * time / 2)
                                                      - math.cos(math.pi * T_RELEASE / 2))


def test_release_time_reference_is_where_the_force_reaches_the_capacity():
    # The test's own reference: F(t1) = 15 and F rises through it; the speed it predicts
    # is positive right after (so the mass does slide forward there).
    assert 5 + 15 * math.sin(math.pi * T_RELEASE / 2) == pytest.approx(15.0, rel=1e-14)
    assert speed_after_release(T_RELEASE + 0.2) > 0


@pytest.mark.parametrize("t_end", [0.6, 50.0, pytest.param(1000.0, marks=pytest.mark.slow)])
def test_stuck_mass_releases_when_the_force_first_exceeds_the_capacity_whatever_t_end(t_end):
    # While stuck the solver may take long steps; the release must still be found at the
    # first crossing, the same for every t_end.
    res = run(sine_driven(), t_end)
    assert slips(res)[0].time == pytest.approx(T_RELEASE, abs=1e-8)
    assert "forward" in slips(res)[0].detail
    assert np.all(res[phi][res.t < T_RELEASE] == 0.0)
    assert res.at(T_RELEASE + 0.05, md.speed(phi)) == pytest.approx(
        speed_after_release(T_RELEASE + 0.05), rel=1e-7)


def test_stuck_mass_before_the_release_time_does_not_move():
    res = run(sine_driven(), 0.4)
    assert slips(res) == [] and np.all(res[phi] == 0.0) and res.final(md.speed(phi)) == 0.0

"""Coulomb friction with true stick and slip: brakes that stop and hold, slip, release."""
import numpy as np
import pytest
import sympy as sp

import mechdyn as md

phi = md.coordinate("phi")
J, m, r, g, M_b = sp.symbols("J m r g M_b", positive=True)


def braked_drum():
    """A drum (J) with a hanging load (m on radius r) and a shoe brake M_b.

    phi grows as the load goes down: gravity drives +phi with m g r."""
    drum = md.Mechanism("braked drum", [phi])
    drum.link("drum", J=J, angle=phi)
    drum.link("load", m=m, y=-r * phi)
    drum.gravity(g)
    drum.friction("brake", M_b, along=phi)
    return drum


PARAMS = {J: 2.0, m: 10.0, r: 0.5, g: 9.81}      # load moment m g r = 49.05 N m
INERTIA = 2.0 + 10.0 * 0.5**2                    # J + m r^2


def test_brake_stops_the_drum_and_holds_it_exactly_at_rest():
    # Load lifted at 4 rad/s against brake 80 N m > 49.05: decelerates by (80 + 49.05)/I.
    scene = md.Scene("hold", initial={phi: 0, md.speed(phi): -4}, t_end=10,
                     outputs=["brake"])
    res = braked_drum().simulate(scene, PARAMS | {M_b: 80.0})
    deceleration = (80 + 49.05) / INERTIA
    t_stop = 4 / deceleration
    stick = [e for e in res.events if e.kind == "stick"]
    assert len(stick) == 1 and stick[0].time == pytest.approx(t_stop, rel=1e-10)
    phi_stop = -4 * t_stop + deceleration * t_stop**2 / 2
    after = res.t > t_stop * (1 + 1e-9)         # past the event point itself
    assert after.sum() >= 1 and res.t_end == 10
    assert np.all(res[md.speed(phi)][after] == 0.0)
    assert np.all(res[phi][after] == res[phi][after][0])
    assert res[phi][after][0] == pytest.approx(phi_stop, rel=1e-10)
    assert res.at(7.5, md.speed(phi)) == 0.0
    # While held, the brake carries exactly the load moment.
    assert res["brake"][after] == pytest.approx(-49.05, rel=1e-12)


def test_brake_weaker_than_the_load_slips_and_accelerates_by_the_net_moment():
    scene = md.Scene("slip", initial={phi: 0, md.speed(phi): 0}, t_end=3)
    res = braked_drum().simulate(scene, PARAMS | {M_b: 30.0})
    a = (49.05 - 30.0) / INERTIA
    assert res.final(md.speed(phi)) == pytest.approx(a * 3, rel=1e-10)
    assert res.final(phi) == pytest.approx(a * 9 / 2, rel=1e-10)
    assert [e.kind for e in res.events] == ["slip"]
    assert np.all(res[md.speed(phi)][1:] > 0)


def test_weak_brake_on_a_rising_load_reverses_and_never_stays_stopped():
    scene = md.Scene("reverse", initial={phi: 0, md.speed(phi): -2}, t_end=4)
    res = braked_drum().simulate(scene, PARAMS | {M_b: 30.0})
    up, down = (49.05 + 30) / INERTIA, (49.05 - 30) / INERTIA
    t_turn = 2 / up
    assert not [e for e in res.events if e.kind == "stick"]
    assert res.final(md.speed(phi)) == pytest.approx(down * (4 - t_turn), rel=1e-9)


def test_load_growing_with_time_releases_the_brake_when_it_exceeds_it():
    # Load moment 10 t N m against a 25 N m brake, from rest: held until t = 2.5 s.
    shaft = md.Mechanism("shaft", [phi])
    shaft.link("shaft", J=1, angle=phi)
    shaft.load("ramp", 10 * md.t, along=phi)
    shaft.friction("brake", 25, along=phi)
    res = shaft.simulate(md.Scene("ramp", initial={phi: 0, md.speed(phi): 0}, t_end=4), {})
    slip = [e for e in res.events if e.kind == "slip"]
    assert [e.time for e in slip] == [pytest.approx(2.5, rel=1e-9)]
    held = res.t < 2.5
    assert np.all(res[phi][held] == 0.0)
    # After release: omega' = 10 t - 25, so omega(4) = 5 (16 - 6.25) - 25 * 1.5 = 11.25.
    assert res.final(md.speed(phi)) == pytest.approx(11.25, rel=1e-9)


def test_two_brakes_on_one_shaft_add_up():
    shaft = md.Mechanism("shaft", [phi])
    shaft.link("shaft", J=0.5, angle=phi)
    shaft.friction("front", 1.0, along=phi)
    shaft.friction("rear", 1.5, along=phi)
    scene = md.Scene("stop", initial={phi: 0, md.speed(phi): 10}, until=md.stopped(phi))
    res = shaft.simulate(scene, {})
    assert res.t_end == pytest.approx(0.5 * 10 / 2.5, rel=1e-10)
    assert res.final(phi) == pytest.approx(0.5 * 100 / (2 * 2.5), rel=1e-10)


def test_friction_on_one_coordinate_of_a_two_mass_drive():
    # Motor (J1) -- shaft (k) -- load (J2) braked by M_b. The load stops and sticks while
    # the spring moment stays below M_b; the motor oscillates about the static twist.
    phi1, phi2 = md.coordinates("phi_1 phi_2")
    drive = md.Mechanism("two masses", [phi1, phi2])
    drive.link("motor", J=1.0, angle=phi1)
    drive.link("load", J=2.0, angle=phi2)
    drive.spring("shaft", 100.0, stretch=phi1 - phi2)
    drive.load("motor moment", 5.0, along=phi1)
    drive.friction("brake", 20.0, along=phi2)
    scene = md.Scene("held", initial={phi1: 0, phi2: 0, md.speed(phi1): 0,
                                      md.speed(phi2): 0}, t_end=2, outputs=["shaft"])
    res = drive.simulate(scene, {})
    # Spring moment peaks at 2 x 5 = 10 < 20: the load never moves.
    assert np.all(res[phi2] == 0.0) and np.all(res[md.speed(phi2)] == 0.0)
    omega = np.sqrt(100.0 / 1.0)
    expected = 5.0 / 100.0 * (1 - np.cos(omega * res.t))
    assert np.allclose(res[phi1], expected, atol=1e-7)
    dense = res.outputs_at(np.linspace(0, 2, 4001))["shaft"]
    assert dense.max() == pytest.approx(10.0, rel=1e-6)


def test_friction_output_is_the_sliding_friction_moment():
    model = md.load_model("models/shoe_brake.py")
    res = model.mechanism.simulate(
        md.Scene("b", effects=["shoe"], initial={model.mechanism.coordinates[0]: 0,
                 md.speed(model.mechanism.coordinates[0]): 100}, t_end=60, outputs=["shoe"]),
        model.params)
    stick = next(e.time for e in res.events if e.kind == "stick")
    assert stick == pytest.approx(50.0, rel=1e-12)
    sliding = res.t < stick                       # before the stick event (held there)
    assert np.allclose(res["shoe"][sliding], -0.8, rtol=1e-14)
    held = res.t > 50 * (1 + 1e-9)                          # past the stop event itself
    assert np.all(res["shoe"][held] == 0.0)                 # held with no load: no force
    assert res.at(55.0, model.mechanism.coordinates[0]) == pytest.approx(2500.0, rel=1e-9)

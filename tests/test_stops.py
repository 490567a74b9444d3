"""Hard stops and ideal backlash: impacts against Newton's law of restitution and
momentum, bounce sequences that end (the energy balance closes), resting contacts that
hold while they push and let go when the load pulls."""
import dataclasses
import math

import numpy as np
import pytest
import sympy as sp

import mechdyn as md

x = md.coordinate("x")
phi_1, phi_2 = md.coordinates("phi_1 phi_2")
J, M, THETA, E = 0.02, 4.0, 0.5, 0.6           # the lever of models/hard_stop.py


def lever():
    return md.load_model("models/hard_stop.py")


def test_lever_bounces_by_the_law_of_restitution_and_rests_when_the_series_ends():
    model = lever()
    res = model.mechanism.simulate(model.scenes["bounce"], model.params)
    impacts = [e for e in res.events if e.kind == "impact"]
    t_1 = math.sqrt(2 * J * THETA / M)               # M theta_0 = J omega^2 / 2
    omega_1 = M * t_1 / J
    assert impacts[0].time == pytest.approx(t_1, rel=1e-10)
    assert impacts[0].value == pytest.approx((1 + E) * J * omega_1, rel=1e-10)
    # each impulse e times the one before; each flight 2 e^k omega_1 J / M
    for k, (a, b) in enumerate(zip(impacts[:5], impacts[1:6])):
        assert b.value / a.value == pytest.approx(E, rel=1e-8)
        assert b.time - a.time == pytest.approx(2 * E ** (k + 1) * omega_1 * J / M, rel=1e-8)
    rest = res.events[-1]
    assert rest.kind == "contact" and rest.name == "end stop"
    # The series is cut once a bounce would rise less than 1e-12 (1 + 0.5) (contacts.py):
    # omega < 2.4e-5, whose remaining bounces last 2 J omega / (M (1 - E)) < 6.1e-7.
    assert rest.time == pytest.approx(t_1 + 2 * E * omega_1 * J / ((1 - E) * M), abs=1e-6)
    # at rest on the upper limit: the stop pushes back the whole drive
    assert res.final("end stop") == pytest.approx(-M, rel=1e-12)
    assert res.final("end stop.mode") == -1.0
    assert res.final(md.coordinate("theta")) == pytest.approx(THETA, abs=1e-12)
    # all the drive's work M theta_0 went into the impacts
    assert sum(e.energy for e in impacts) == pytest.approx(M * THETA, rel=1e-10)


def test_a_plastic_stop_takes_all_the_kinetic_energy_in_one_impact():
    model = lever()
    params = model.params | {model.param_symbol("e"): 0}
    res = model.mechanism.simulate(model.scenes["bounce"], params)
    kinds = [e.kind for e in res.events]
    assert kinds == ["impact", "contact"]
    assert res.events[0].energy == pytest.approx(M * THETA, rel=1e-12)
    after = res.t > res.events[0].time
    assert np.all(res["end stop"][after] == pytest.approx(-M, rel=1e-12))


def resting_lever(drive):
    mech = md.Mechanism("lever", [x])
    mech.link("lever", J=2, angle=x)
    mech.load("drive", drive, along=x)
    mech.stop("stop", along=x, lower=0)
    return mech


def test_a_resting_contact_lets_go_when_the_load_pulls_away():
    # Resting on the lower limit under -3 cos(t): pushed into the stop until pi/2, then
    # pulled away: 2 x'' = -3 cos t from t = pi/2.
    res = resting_lever(-3 * sp.cos(md.t)).simulate(
        md.Scene("s", initial={x: 0, md.speed(x): 0}, t_end=3, outputs=["stop"]), {})
    lift = [e for e in res.events if e.kind == "lift"]
    assert [e.time for e in lift] == [pytest.approx(math.pi / 2, rel=1e-9)]
    assert res.outputs_at([1.0])["stop"][0] == pytest.approx(3 * math.cos(1.0), rel=1e-12)
    assert res.final(md.speed(x)) == pytest.approx(-1.5 * (math.sin(3) - 1), rel=1e-9)


def test_a_run_may_not_start_beyond_a_limit_and_one_touching_and_moving_in_hits_at_once():
    mech = resting_lever(0)
    with pytest.raises(md.SceneError, match="stop 'stop'.*beyond its lower limit"):
        mech.simulate(md.Scene("s", initial={x: -0.1, md.speed(x): 0}, t_end=1), {})
    res = mech.simulate(md.Scene("s", initial={x: 0, md.speed(x): -2}, t_end=1), {})
    assert [(e.kind, e.time) for e in res.events] == [("impact", 0.0), ("contact", 0.0)]
    assert res.final(x) == 0.0 and res.final(md.speed(x)) == 0.0


def test_ideal_backlash_between_two_shafts_keeps_momentum_and_restitutes_the_approach():
    # Shaft 1 (J = 1) at 3 rad/s, shaft 2 (J = 2) at rest, play 0.2 rad centred: contact
    # after 0.1 / 3 s; then relative speed -e times 3, momentum 3 kept.
    drive = md.Mechanism("backlash", [phi_1, phi_2])
    drive.link("one", J=1, angle=phi_1)
    drive.link("two", J=2, angle=phi_2)
    drive.backlash("play", phi_2 - phi_1, gap=0.2, restitution=0.5)
    res = drive.simulate(md.Scene("s", initial={phi_1: 0, phi_2: 0, md.speed(phi_1): 3,
                                                md.speed(phi_2): 0}, t_end=0.2), {})
    impacts = [e for e in res.events if e.kind == "impact"]
    assert impacts[0].time == pytest.approx(0.1 / 3, rel=1e-10)
    w1, w2 = res.at(0.1, md.speed(phi_1)), res.at(0.1, md.speed(phi_2))
    assert w1 + 2 * w2 == pytest.approx(3.0, rel=1e-12)
    assert w2 - w1 == pytest.approx(0.5 * 3, rel=1e-12)
    # the energy lost: (1 - e^2) mu v^2 / 2 with the reduced inertia mu = 2/3
    assert impacts[0].energy == pytest.approx(0.75 * (2 / 3) * 9 / 2, rel=1e-12)
    # the next contact (other side) only after the play is crossed: 0.2 / 1.5 s later
    assert impacts[1].time - impacts[0].time == pytest.approx(0.2 / 1.5, rel=1e-9)


def test_a_stop_on_a_closed_loop_moves_both_coordinates_by_one_impulse():
    # Two masses tied by the constraint y = 2 x; a stop on x. Kinetic energy with
    # m_x = 1, m_y = 1: (1 + 4) x'^2 / 2, so the bounce reverses x' by e and y' with it.
    y = md.coordinate("y")
    mech = md.Mechanism("tied", [x, y])
    mech.link("a", m=1, x=x)
    mech.link("b", m=1, y=y)
    mech.constraint("tie", y - 2 * x)
    mech.stop("stop", along=x, upper=0.1, restitution=0.8)
    res = mech.simulate(md.Scene("s", initial={x: 0, y: 0, md.speed(x): 1}, t_end=0.15), {})
    impact = [e for e in res.events if e.kind == "impact"][0]
    assert impact.time == pytest.approx(0.1, rel=1e-9)
    assert impact.value == pytest.approx(1.8 * 5, rel=1e-9)        # (1 + e) * 5 * 1
    assert res.final(md.speed(x)) == pytest.approx(-0.8, rel=1e-9)
    assert res.final(md.speed(y)) == pytest.approx(-1.6, rel=1e-9)


def test_a_block_on_a_stop_with_friction_stays_until_the_pull_beats_the_static_limit():
    # Pulled away from the stop by 2 t against friction 6 (peak 1.5): held by the
    # friction, then the stop, until 2 t = 9; then 1 kg slides with (2 t - 6).
    mech = md.Mechanism("block", [x], units={x: "m"})
    mech.link("block", m=1, x=x)
    mech.load("pull", 2 * md.t, along=x)
    mech.friction("floor", 6, along=x, peak=1.5)
    mech.stop("wall", along=x, lower=0)
    res = mech.simulate(md.Scene("s", initial={x: 0, md.speed(x): 0}, t_end=5), {})
    slip = [e for e in res.events if e.kind == "slip"]
    assert [e.time for e in slip] == [pytest.approx(4.5, rel=1e-10)]
    assert res.final(md.speed(x)) == pytest.approx(25 - 4.5**2 - 6 * 0.5, rel=1e-9)


def test_stop_outputs_and_latex():
    mech = resting_lever(-1)
    scene = md.Scene("s", initial={x: 0.5, md.speed(x): 0}, t_end=2,
                     outputs=["stop", "stop.mode"])
    res = mech.simulate(scene, {})
    assert res.units["stop"] == "N*m"            # along an angle: a moment
    assert res.outputs_at([0.1])["stop.mode"][0] == 0.0
    assert res.final("stop.mode") == 1.0
    latex = mech.latex()
    assert "g_{\\text{stop.lower}} &= x \\geq 0" in latex


@pytest.mark.parametrize("kwargs, match", [
    (dict(along=x), "give lower=, upper= or both"),
    (dict(along=x, lower=1, upper=0), "must lie below"),
    (dict(along=x, lower=0, restitution=1.5), r"restitution = 1.5 must lie in \[0, 1\]"),
    (dict(along=0, lower=0), "does not depend on the coordinates"),
])
def test_bad_stops_are_refused_naming_the_stop(kwargs, match):
    mech = md.Mechanism("m", [x])
    with pytest.raises(md.DeclarationError, match=match):
        mech.stop("end", **kwargs)


def test_the_ball_of_the_docstring_loses_its_energy_in_the_bounces():
    ball = md.Mechanism("ball", [x], units={x: "m"})
    ball.link("ball", m=1, y=x)
    ball.gravity(10)
    ball.stop("floor", along=x, lower=0, restitution=0.5)
    scene = md.Scene("drop", initial={x: 5, md.speed(x): 0}, t_end=4, outputs=["floor"])
    res = ball.simulate(scene, {})
    lost = sum(e.energy for e in res.events if e.kind == "impact")
    assert lost == pytest.approx(50.0, rel=1e-10)                   # m g h
    assert res.final("floor") == pytest.approx(10.0, rel=1e-12)    # carries m g
    scene = dataclasses.replace(scene, t_end=1.5)
    assert ball.simulate(scene, {}).final(md.speed(x)) == pytest.approx(0.0, abs=1e-9)


def test_an_impact_passes_through_a_freewheel_that_would_be_driven_backward():
    # Hub (J = 1) and wheel (J = 3) turning together at 2 rad/s; the wheel hits a
    # plastic stop. The hub would run on ahead of it, which the freewheel forbids: both
    # stop, the stop taking the impulse (1 + 3) * 2 and the energy 4 * 2^2 / 2. Had the
    # hub hit the stop, the wheel would overrun on at 2 rad/s.
    def run(stopped):
        mech = md.Mechanism("hub", [phi_1, phi_2])
        mech.link("hub", J=1, angle=phi_1)
        mech.link("wheel", J=3, angle=phi_2)
        mech.freewheel("freewheel", along=phi_2 - phi_1)
        mech.stop("stop", along=stopped, upper=0.5)
        scene = md.Scene("s", initial={phi_1: 0, phi_2: 0, md.speed(phi_1): 2,
                                       md.speed(phi_2): 2}, t_end=0.5)
        return mech.simulate(scene, {})
    res = run(phi_2)
    impact = [e for e in res.events if e.kind == "impact"][0]
    assert impact.time == pytest.approx(0.25, rel=1e-10)
    assert impact.value == pytest.approx(8.0, rel=1e-10)
    assert impact.energy == pytest.approx(8.0, rel=1e-10)
    assert res.final(md.speed(phi_1)) == pytest.approx(0.0, abs=1e-12)
    res = run(phi_1)
    assert res.final(md.speed(phi_2)) == pytest.approx(2.0, rel=1e-12)
    assert res.final(md.speed(phi_1)) == pytest.approx(0.0, abs=1e-12)


def test_an_impact_passes_through_two_freewheels_in_a_row():
    # Hub (J = 1), wheel (J = 3) and rim (J = 5) turning together at 2 rad/s, each
    # freewheel forbidding the inner one to run ahead of the outer; the rim hits a
    # plastic stop: all three stop, the stop taking the impulse (1 + 3 + 5) * 2 and the
    # energy 9 * 2^2 / 2 (one impact, two locking freewheels).
    phi_3 = md.coordinate("phi_3")
    mech = md.Mechanism("hub, wheel and rim", [phi_1, phi_2, phi_3])
    for name, inertia, angle in (("hub", 1, phi_1), ("wheel", 3, phi_2), ("rim", 5, phi_3)):
        mech.link(name, J=inertia, angle=angle)
    mech.freewheel("inner", along=phi_2 - phi_1)
    mech.freewheel("outer", along=phi_3 - phi_2)
    mech.stop("stop", along=phi_3, upper=0.5)
    scene = md.Scene("s", initial={phi_1: 0, phi_2: 0, phi_3: 0, md.speed(phi_1): 2,
                                   md.speed(phi_2): 2, md.speed(phi_3): 2}, t_end=0.5)
    res = mech.simulate(scene, {})
    impact = [e for e in res.events if e.kind == "impact"][0]
    assert impact.time == pytest.approx(0.25, rel=1e-10)
    assert impact.value == pytest.approx(18.0, rel=1e-10)
    assert impact.energy == pytest.approx(18.0, rel=1e-10)
    for angle in (phi_1, phi_2, phi_3):
        assert res.final(md.speed(angle)) == pytest.approx(0.0, abs=1e-12)


def test_a_lever_touching_its_stop_at_a_speed_of_rounding_size_rests_on_it():
    # Speeds below 1e-12 (x (1 + the largest speed)) are rest: a start on the limit
    # moving into it at 1e-13 rad/s is no impact; pushed in until pi/2, then pulled away
    # as from rest: 2 x'' = -3 cos t from t = pi/2.
    res = resting_lever(-3 * sp.cos(md.t)).simulate(
        md.Scene("s", initial={x: 0, md.speed(x): -1e-13}, t_end=3), {})
    assert not [e for e in res.events if e.kind == "impact"]
    assert [e.time for e in res.events if e.kind == "lift"] == \
        [pytest.approx(math.pi / 2, rel=1e-9)]
    assert res.final(md.speed(x)) == pytest.approx(-1.5 * (math.sin(3) - 1), rel=1e-9)


def test_the_printed_derivation_states_the_gap_and_the_impact_law():
    """A stop prints its gap (0.1 - x >= 0 for an upper limit at 0.1) and Newton's impact
    law g'+ = -e g'- with e = 0.8: the speed reverses, reduced by e."""
    x = md.coordinate("x")
    mech = md.Mechanism("ball", [x])
    mech.link("ball", m=1, x=x)
    mech.load("push", 1, along=x)
    mech.stop("stop", along=x, upper=0.1, restitution=0.8)
    lines = [line for line in mech.latex().splitlines() if "stop" in line]
    assert lines == ["g_{\\text{stop.upper}} &= 0.1 - x \\geq 0 \\\\",
                     "\\dot{g}^{+}_{\\text{stop.upper}} &= - 0.8 \\dot{g} \\\\"]

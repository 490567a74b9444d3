"""Static peak friction, clutches, brakes, one-way clutches and freewheels, tables:
worked examples against closed forms (momentum and energy balances, kinematics of
constant moments)."""
import dataclasses
import math

import numpy as np
import pytest
import sympy as sp

import mechdyn as md

x = md.coordinate("x")
phi_1, phi_2 = md.coordinates("phi_1 phi_2")


def block(peak):
    """A 2 kg block pushed by F = 10 t N over a floor: sliding friction 6 N."""
    mech = md.Mechanism("block", [x], units={x: "m"})
    mech.link("block", m=2, x=x)
    mech.load("push", 10 * md.t, along=x)
    mech.friction("floor", 6, along=x, peak=peak)
    return mech


def test_static_peak_delays_the_breakaway_and_the_block_then_slides_with_6_N():
    # Held while 10 t <= 1.5 * 6: breakaway at t_0 = 0.9 s (not 0.6 s); then
    # 2 v' = 10 t - 6, so v(t) = (5 (t^2 - t_0^2) - 6 (t - t_0)) / 2.
    scene = md.Scene("push", initial={x: 0, md.speed(x): 0}, t_end=2, outputs=["floor"])
    res = block(1.5).simulate(scene, {})
    slip = [e for e in res.events if e.kind == "slip"]
    assert [e.time for e in slip] == [pytest.approx(0.9, rel=1e-10)]
    assert np.all(res[x][res.t < 0.9] == 0.0)
    v = (5 * (2.0**2 - 0.81) - 6 * (2.0 - 0.9)) / 2
    assert res.final(md.speed(x)) == pytest.approx(v, rel=1e-9)
    # Held, the floor carries the push exactly; sliding, it pushes back 6 N (not 9 N).
    held = res.outputs_at([0.5])["floor"][0]
    assert held == pytest.approx(-5.0, rel=1e-12)
    assert res.outputs_at([1.5])["floor"][0] == pytest.approx(-6.0, rel=1e-12)


def test_the_printed_derivation_states_a_static_limit_above_the_sliding_friction():
    """peak 1.5 on 6 N: the floor holds up to 9 N, and the derivation says so; without a
    peak the limit is the sliding friction and no line is printed for it."""
    limit = [line for line in block(1.5).latex().splitlines()
             if line.startswith("\\lambda^{\\max}_{\\text{floor}}")]
    assert len(limit) == 1 and "&= 9.0" in limit[0]
    assert "\\lambda^{\\max}" not in block(1).latex()


def test_without_a_peak_the_block_breaks_away_at_the_sliding_friction():
    scene = md.Scene("push", initial={x: 0, md.speed(x): 0}, t_end=1)
    res = block(1).simulate(scene, {})
    assert [e.time for e in res.events if e.kind == "slip"] == [pytest.approx(0.6, rel=1e-10)]


def test_a_sliding_block_sticks_where_the_load_stays_below_the_static_limit():
    # Sliding at 3 m/s against 6 N with a constant push of 8 N: decelerates? No: 8 > 6
    # accelerates. Pushed back with -4 N: decelerates at (6 + 4) / 2 = 5 m/s^2, stops
    # at 0.6 s and stays: 4 N < 1.5 * 6 N.
    mech = md.Mechanism("block", [x])
    mech.link("block", m=2, x=x)
    mech.load("push", -4, along=x)
    mech.friction("floor", 6, along=x, peak=1.5)
    res = mech.simulate(md.Scene("s", initial={x: 0, md.speed(x): 3}, t_end=2), {})
    assert [(e.kind, round(e.time, 12)) for e in res.events] == [("stick", 0.6)]
    assert res.final(x) == pytest.approx(0.9, rel=1e-10)


@pytest.mark.parametrize("backend", ["scipy", "compiled"])
def test_clutch_engagement_locks_by_momentum_and_turns_the_slip_into_heat(backend):
    # (compiled: the normal force ramps up from exactly 0 at the start; the kernel's
    # event location took that zero for the engagement, 201 times over, until issue 27)
    model = md.load_model("models/clutch_engagement.py")
    phi1, phi2 = model.mechanism.coordinates
    scene = model.scenes["engage"]
    labels = ["power:clutch"]
    scene = dataclasses.replace(scene, outputs=labels + list(scene.outputs))
    res = model.mechanism.simulate(scene, model.params, backend=backend)
    # Slip speed -100 + (1/0.5 + 1/1.5) 60 t^2 (ramp to 0.5 s), then + 160 t: 0 at 0.875 s.
    stick = [e for e in res.events if e.kind == "stick"]
    assert [e.time for e in stick] == [pytest.approx(0.875, rel=1e-10)]
    common = 0.5 * 100 / 2.0                        # momentum: J_1 omega_0 / (J_1 + J_2)
    assert res.final(md.speed(phi1)) == pytest.approx(common, rel=1e-10)
    assert res.final(md.speed(phi2)) == pytest.approx(common, rel=1e-10)
    assert res.final("clutch.mode") == 0.0
    assert res.outputs_at([0.6])["clutch.mode"][0] == -1.0     # the load lags: backward
    heat = 0.5 * 1.5 * 100**2 / (2 * 2.0)          # J_1 J_2 omega_0^2 / (2 (J_1 + J_2))
    nodes, weights = np.polynomial.legendre.leggauss(8)
    work = 0.0
    for a, b in zip(res.t[:-1], res.t[1:]):
        times = (a + b) / 2 + (b - a) / 2 * nodes
        work += (b - a) / 2 * weights @ res.outputs_at(times)["power:clutch"]
    assert work == pytest.approx(-heat, rel=1e-8)


def test_a_loaded_clutch_locks_later_and_carries_its_share_of_the_load():
    model = md.load_model("models/clutch_engagement.py")
    res = model.mechanism.simulate(model.scenes["engage_loaded"], model.params)
    # slip(t) = -100 + 160 t^2 - (20 / 1.5) t to 0.5 s (-66.67), then grows at
    # 160 - 13.33 per second: locks at 0.5 + 66.67 / 146.67 s.
    lock = 0.5 + (100 - 40 + 20 / 1.5 * 0.5) / (160 - 20 / 1.5)
    stick = [e for e in res.events if e.kind == "stick"]
    assert [e.time for e in stick] == [pytest.approx(lock, rel=1e-9)]
    # Locked: both decelerate at M_L / (J_1 + J_2) = 10; the clutch pushes the load
    # with J_2 a + M_L = -15 + 20 = 5 N m (well within 1.25 * 60).
    assert res.final("clutch") == pytest.approx(5.0, rel=1e-9)
    assert res.final("clutch.slip") == 0.0


def test_a_clutch_not_pressed_is_free_and_engages_when_the_normal_force_appears():
    # Two shafts, the clutch's normal force 0 until 1 s (sign and Heaviside inside it),
    # then 100 N: free at first (no moment although the shafts slip), then slipping.
    drive = md.Mechanism("two shafts", [phi_1, phi_2])
    drive.link("a", J=1, angle=phi_1)
    drive.link("b", J=1, angle=phi_2)
    normal = 100 * sp.Heaviside(md.t - 1) * (1 + sp.sign(md.t - 2)) / 2 \
        + 100 * sp.Heaviside(md.t - 1) * (1 - sp.sign(md.t - 2)) / 2
    drive.clutch("clutch", normal_force=normal, mu=md.table([0, 10], [0.5, 0.3]),
                 along=phi_2 - phi_1)
    scene = md.Scene("s", initial={phi_1: 0, phi_2: 0, md.speed(phi_1): 10,
                                   md.speed(phi_2): 0}, t_end=3)
    res = drive.simulate(scene, {})
    assert res.at(1.0, md.speed(phi_1)) == pytest.approx(10.0, rel=1e-12)
    # After 1 s: mu = 0.5 - 0.02 |slip|, slip s = w_2 - w_1 from -10: s' = 2 * 100 mu(|s|)
    # = 100 - 4 |s|: s(t) = -25 + 15 exp(4 (t - 1)) until s = 0 at 1 + ln(25/15)/4.
    lock = 1 + math.log(25 / 15) / 4
    assert [e.time for e in res.events if e.kind == "stick"] == [pytest.approx(lock,
                                                                               rel=1e-9)]
    assert res.final(md.speed(phi_1)) == pytest.approx(5.0, rel=1e-10)


def test_brake_and_bearing_friction_are_frictions_with_their_laws():
    shaft = md.Mechanism("shaft", [phi_1])
    shaft.link("disc", J=2, angle=phi_1)
    shaft.brake("brake", normal_force=1000, mu=0.4, along=phi_1, geometry=0.05)   # 20 N m
    shaft.bearing_friction("bearing", md.table([0, 1], [1, 1.5]), along=phi_1)  # 1 + w/2
    res = shaft.simulate(md.Scene("stop", initial={phi_1: 0, md.speed(phi_1): 10},
                                  until=md.stopped(phi_1)), {})
    # 2 w' = -21 - w/2: w(t) = (10 + 42) exp(-t/4) - 42, zero at 4 ln(52/42).
    assert res.t_end == pytest.approx(4 * math.log(52 / 42), rel=1e-9)


# ---------------------------------------------------------------------- one-way clutches
def hub(release=0):
    """A driving hub J_h = 1 and a wheel J_w = 3 through a freewheel (the wheel may
    overrun), the hub driven by 6 cos(2 t)."""
    mech = md.Mechanism("hub", [phi_1, phi_2])
    mech.link("hub", J=1, angle=phi_1)
    mech.link("wheel", J=3, angle=phi_2)
    mech.load("drive", 6 * sp.cos(2 * md.t), along=phi_1)
    mech.freewheel("freewheel", along=phi_2 - phi_1, release=release)
    return mech


def test_freewheel_drives_while_the_drive_pushes_and_overruns_the_instant_it_pulls():
    # Locked: both accelerate at 6 cos(2t) / 4 and the wheel needs J_w a = 4.5 cos(2t)
    # from the freewheel, which changes sign at t = pi/4: there the wheel overruns at
    # the speed 0.75 sin(pi/2) = 0.75 and keeps it; the hub runs on by its drive.
    scene = md.Scene("s", initial={phi_1: 0, phi_2: 0, md.speed(phi_1): 0,
                                   md.speed(phi_2): 0}, t_end=2,
                     outputs=["freewheel", "freewheel.mode"])
    res = hub().simulate(scene, {})
    slip = [e for e in res.events if e.kind == "slip"]
    assert [e.time for e in slip] == [pytest.approx(math.pi / 4, rel=1e-9)]
    assert res.final(md.speed(phi_2)) == pytest.approx(0.75, rel=1e-9)
    # the hub after pi/4: 0.75 + 3 (sin 2t - 1), behind the wheel (never ahead)
    assert res.final(md.speed(phi_1)) == pytest.approx(0.75 + 3 * (math.sin(4) - 1), rel=1e-9)
    t = np.linspace(0, 2, 801)
    rates = res.at(t)
    assert np.all(rates["phidot_2"] - rates["phidot_1"] >= -1e-9)
    assert res.outputs_at([0.5])["freewheel"][0] == pytest.approx(4.5 * math.cos(1.0),
                                                                  rel=1e-9)
    assert res.final("freewheel.mode") == 1.0


def test_a_release_threshold_keeps_the_freewheel_locked_until_it_is_exceeded():
    # With release = 3 N m the freewheel holds the wheel back until 4.5 cos(2t) = -3.
    scene = md.Scene("s", initial={phi_1: 0, phi_2: 0, md.speed(phi_1): 0,
                                   md.speed(phi_2): 0}, t_end=2)
    res = hub(release=3).simulate(scene, {})
    slip = [e for e in res.events if e.kind == "slip"]
    assert [e.time for e in slip] == [pytest.approx(math.acos(-3 / 4.5) / 2, rel=1e-9)]


def test_a_freewheel_driven_backward_at_the_start_locks_by_an_impact():
    # Hub at 2 rad/s, wheel at rest: the wheel would fall behind. Locking is a plastic
    # impact: common speed (1 * 2 + 3 * 0) / 4, energy lost 1 * 3 * 2^2 / (2 * 4).
    mech = hub()
    scene = md.Scene("s", initial={phi_1: 0, phi_2: 0, md.speed(phi_1): 2,
                                   md.speed(phi_2): 0}, t_end=0.1)
    res = mech.simulate(scene, {})
    impact = [e for e in res.events if e.kind == "impact"]
    assert len(impact) == 1 and impact[0].time == 0.0
    assert impact[0].value == pytest.approx(3 * 0.5, rel=1e-12)        # J_w * 0.5
    assert impact[0].energy == pytest.approx(1.5, rel=1e-12)
    assert res.y[2, 0] == pytest.approx(0.5, rel=1e-12)


def test_one_way_clutch_slides_forward_with_its_moment_and_locks_backward():
    # An engaged one-way clutch (moment 2, peak 1.5) overrunning: the wheel (at 5 rad/s,
    # hub at rest and held by nothing) is braked by 2 N m, the hub driven by it: slip
    # 5 - 2 (1/3 + 1) t vanishes at 15/8 s; then locked, no load: it stays locked.
    mech = md.Mechanism("hub", [phi_1, phi_2])
    mech.link("hub", J=1, angle=phi_1)
    mech.link("wheel", J=3, angle=phi_2)
    mech.one_way_clutch("clutch", 2, along=phi_2 - phi_1, peak=1.5)
    scene = md.Scene("s", initial={phi_1: 0, phi_2: 0, md.speed(phi_1): 0,
                                   md.speed(phi_2): 5}, t_end=3, outputs=["clutch.slip"])
    res = mech.simulate(scene, {})
    assert [(e.kind, e.time) for e in res.events] == [("stick", pytest.approx(15 / 8,
                                                                             rel=1e-10))]
    assert res.final(md.speed(phi_1)) == pytest.approx(15 / 4, rel=1e-10)   # momentum
    assert res.final("clutch.slip") == 0.0


# ---------------------------------------------------------------------------- tables
def test_table_interpolates_and_extrapolates_through_the_end_points():
    table = md.table([0, 1, 3], [2, 4, 0])
    assert [float(table(v)) for v in (-1, 0, 0.5, 1, 2, 3, 4)] == [0, 2, 3, 4, 2, 0, -2]


def test_table_in_a_load_compiles_with_its_breakpoints_as_switches():
    # A spring written as a table of the stretch (k = 100 up to 0.1 m, 300 beyond):
    # released from 0.2 m, the mass (1 kg) feels 100 * 0.1 + 300 * 0.1 = 40 N.
    law = md.table([0, 0.1, 0.2], [0, 10, 40])
    mech = md.Mechanism("tabled spring", [x], units={x: "m"})
    mech.link("mass", m=1, x=x)
    mech.load("spring", -law(x), along=x)
    res = mech.simulate(md.Scene("s", initial={x: 0.2, md.speed(x): 0}, t_end=1e-3), {})
    a = res.accelerations[0][0]
    assert a == pytest.approx(-40.0, rel=1e-12)
    # through x = 0.1 the stiffness changes; the work of the table (its integral, 0.5 +
    # 2.5 J) becomes the kinetic energy at x = 0
    res = mech.simulate(md.Scene("s", initial={x: 0.2, md.speed(x): 0}, t_end=0.2), {})
    speed_at_zero = math.sqrt(2 * (0.5 * 100 * 0.01 + (10 * 0.1 + 0.5 * 300 * 0.01)))
    assert abs(res.peak(md.speed(x))[1]) == pytest.approx(speed_at_zero, rel=1e-8)


@pytest.mark.parametrize("xs, ys, match", [
    ([0, 1], [1], "equal length"), ([0], [1], "at least two"),
    ([0, 0], [1, 2], "increase strictly"), ([0, "a"], [1, 2], "string"),
])
def test_bad_tables_are_refused_naming_the_culprit(xs, ys, match):
    with pytest.raises(md.DeclarationError, match=match):
        md.table(xs, ys, name="mu")


def test_switching_functions_compile_inside_the_new_elements():
    # A one-way clutch's moment Max(0, 4 - 2 t): the wheel (J = 3, 5 rad/s) overruns the
    # hub (J = 1, at rest); slip 5 - (4/3) (4 t - t^2) reaches 0 at t = 1.5 s.
    mech = md.Mechanism("hub", [phi_1, phi_2])
    mech.link("hub", J=1, angle=phi_1)
    mech.link("wheel", J=3, angle=phi_2)
    mech.one_way_clutch("clutch", sp.Max(0, 4 - 2 * md.t), along=phi_2 - phi_1)
    res = mech.simulate(md.Scene("s", initial={phi_1: 0, phi_2: 0, md.speed(phi_1): 0,
                                               md.speed(phi_2): 5}, t_end=2), {})
    assert [e.time for e in res.events if e.kind == "stick"] == [pytest.approx(1.5,
                                                                              rel=1e-10)]
    # A lossy gear whose input-side bearing loss (Heaviside of t) and efficiency (Min of
    # the speed) switch: input J = 1 driven by 10, output J = 4 (ratio 2, so 1 + 1 = 2
    # at the input). Until 0.5 s eta = min(1, ...) = 1: 10 / 2; then (10 - 3) / 2.
    phi_a, phi_b = md.coordinates("phi_a phi_b")
    gear = md.Mechanism("gear", [phi_a, phi_b])
    gear.link("input", J=1, angle=phi_a)
    gear.link("output", J=4, angle=phi_b)
    gear.load("drive", 10, along=phi_a)
    gear.lossy_gear("gear", input=phi_a, output=phi_b, ratio=2,
                    eta_forward=sp.Min(1, 2 + md.speed(phi_a)),
                    bearing_forward=3 * sp.Heaviside(md.t - 0.5))
    res = gear.simulate(md.Scene("s", initial={phi_a: 0, phi_b: 0, md.speed(phi_a): 0,
                                               md.speed(phi_b): 0}, t_end=1), {})
    assert res.at(0.5, md.speed(phi_a)) == pytest.approx(2.5, rel=1e-9)
    assert res.final(md.speed(phi_a)) == pytest.approx(2.5 + 3.5 * 0.5, rel=1e-9)

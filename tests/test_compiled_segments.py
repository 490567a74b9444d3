"""Segments with stuck friction elements, one-way clutches, stops (impacts, resting
contact), switches and closed loops on the compiled kernels (issue 25): each checked on
both backends against an independent reference (closed forms worked by hand), and the
bundled scenes compared between the compiled path and scipy, the reference."""
import dataclasses
import math

import numpy as np
import pytest
import sympy as sp

import mechdyn as md

BACKENDS = ["auto", "scipy"]


def run(model, scene_name, backend, params=None):
    scene = dataclasses.replace(model.scenes[scene_name], backend=backend)
    res = model.mechanism.simulate(scene, params or model.params)
    expected = {"compiled"} if backend == "auto" else {"scipy"}
    assert set(res.stats["backends"]) == expected, res.stats["backends"]
    return res


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_brake_stops_a_disc_and_then_holds_it_against_a_smaller_load(backend):
    # J = 2 spinning at 3 rad/s, brake 1.5 N m: sliding, the disc stops at J w0 / T = 4 s;
    # a load of 1 N m from t = 5 s is below the brake's capacity: held, speed exactly 0.
    phi = md.coordinate("phi")
    mech = md.Mechanism("braked disc", [phi])
    mech.link("disc", J=2, angle=phi)
    mech.friction("brake", 1.5, along=phi)
    mech.load("push", sp.Heaviside(md.t - 5), along=phi)
    scene = md.Scene("stop", initial={phi: 0, md.speed(phi): 3}, t_end=8, backend=backend)
    res = mech.simulate(scene, {})
    assert set(res.stats["backends"]) == ({"compiled"} if backend == "auto" else {"scipy"})
    stick = [e for e in res.events if e.kind == "stick"]
    assert len(stick) == 1 and stick[0].time == pytest.approx(4.0, rel=1e-10)
    assert res.final(md.speed(phi)) == 0.0
    assert res.final(phi) == pytest.approx(3 * 4 / 2, rel=1e-10)     # w0 t / 2
    assert not [e for e in res.events if e.kind == "slip"]


@pytest.mark.parametrize("backend", BACKENDS)
def test_static_friction_holds_until_the_pull_exceeds_it_then_slides(backend):
    # A block (m = 2) held by friction 3 N (peak 1.5: holds up to 4.5 N) pulled by
    # F = t N: it breaks away at t = 4.5 s and then accelerates at (t - 3) / 2.
    x = md.coordinate("x")
    mech = md.Mechanism("block", [x])
    mech.link("block", m=2, x=x)
    mech.friction("floor", 3, along=x, peak=1.5)
    mech.load("pull", md.t, along=x)
    scene = md.Scene("pull", initial={x: 0, md.speed(x): 0}, t_end=6, backend=backend)
    res = mech.simulate(scene, {})
    slip = [e for e in res.events if e.kind == "slip"]
    assert len(slip) == 1 and slip[0].time == pytest.approx(4.5, rel=1e-9)
    # v(6) = integral of (t - 3) / 2 from 4.5 to 6
    assert res.final(md.speed(x)) == pytest.approx((6**2 - 4.5**2) / 4 - 1.5 * 1.5, rel=1e-9)


@pytest.mark.parametrize("backend", BACKENDS)
def test_slider_friction_does_not_stick_at_the_dead_centres(backend):
    # A crank (J = 0.05, R = 0.1, rod 0.4) coasting from 19.5 rad/s at a dead centre
    # against 5 N of slider friction: the slider stops at every dead centre while the
    # crank turns on; the crank stops once F times the slider's path has used up
    # J w0^2 / 2 = 9.50625 J: 1.90125 m, nine strokes of 0.2 m from the outer dead
    # centre (x = 0.5) and 0.10125 m out from the inner one (x = 0.3).
    phi = md.coordinate("phi")
    x = 0.1 * sp.cos(phi) + sp.sqrt(0.4**2 - 0.1**2 * sp.sin(phi) ** 2)
    crank = md.Mechanism("slider-crank", [phi])
    crank.link("crank", J=0.05, angle=phi)
    crank.link("slider", m=2.0, x=x)
    crank.friction("slider friction", 5.0, along=x)
    scene = md.Scene("coast", initial={phi: 0, md.speed(phi): 19.5}, t_end=6,
                     backend=backend)
    res = crank.simulate(scene, {})
    assert set(res.stats["backends"]) == ({"compiled"} if backend == "auto" else {"scipy"})
    assert [e.kind for e in res.events if e.kind != "slip"] == ["stick"]
    assert res.final(md.speed(phi)) == 0.0
    angle = res.final(phi)
    assert 9 * math.pi < angle < 10 * math.pi
    position = 0.1 * math.cos(angle) + math.sqrt(0.4**2 - 0.1**2 * math.sin(angle) ** 2)
    assert position == pytest.approx(0.3 + 0.5 * 0.05 * 19.5**2 / 5.0 - 1.8, rel=1e-8)


@pytest.mark.parametrize("backend", BACKENDS)
def test_the_lever_bounces_by_the_law_of_restitution(backend):
    # models/hard_stop.py: J = 0.02, drive M = 4 from theta_0 = 0.5 to the stop, e = 0.6.
    J, M, THETA, E = 0.02, 4.0, 0.5, 0.6
    model = md.load_model("models/hard_stop.py")
    res = run(model, "bounce", backend)
    impacts = [e for e in res.events if e.kind == "impact"]
    t_1 = math.sqrt(2 * J * THETA / M)
    omega_1 = M * t_1 / J
    assert impacts[0].time == pytest.approx(t_1, rel=1e-10)
    assert impacts[0].value == pytest.approx((1 + E) * J * omega_1, rel=1e-10)
    for k, (a, b) in enumerate(zip(impacts[:5], impacts[1:6])):
        assert b.value / a.value == pytest.approx(E, rel=1e-8)
        assert b.time - a.time == pytest.approx(2 * E ** (k + 1) * omega_1 * J / M, rel=1e-8)
    assert res.events[-1].kind == "contact"
    assert res.final(md.coordinate("theta")) == pytest.approx(THETA, abs=1e-12)
    assert res.final("end stop") == pytest.approx(-M, rel=1e-12)


@pytest.mark.parametrize("backend", BACKENDS)
def test_the_freewheel_locks_while_pedalling_and_lets_the_wheel_overrun(backend):
    # models/freewheel.py's docstring: locked, both turn at (M_p - M_r) / (J_h + J_w)
    # = 112 rad/s^2 up to t_p = 2 s (224 rad/s); then the wheel coasts at -M_r / J_w =
    # -10 rad/s^2 (144 rad/s at 10 s) and the legs stop the pedals at
    # t_p + J_h 224 / M_b = 4.24 s.
    model = md.load_model("models/freewheel.py")
    res = run(model, "ride", backend)
    wheel, pedals = md.speed(md.coordinate("phi_w")), md.speed(md.coordinate("phi_h"))
    assert res.at(1.0, wheel) == pytest.approx(112.0, rel=1e-9)
    assert res.at(1.0, pedals) == pytest.approx(112.0, rel=1e-9)
    assert res.final(wheel) == pytest.approx(144.0, rel=1e-9)
    stops = [e for e in res.events if e.kind == "stick" and e.name == "legs"]
    assert stops and stops[0].time == pytest.approx(4.24, rel=1e-9)
    assert res.final(pedals) == 0.0


@pytest.mark.parametrize("backend", BACKENDS)
def test_the_worm_hoist_lifts_coasts_up_and_locks(backend):
    # models/worm_hoist.py's docstring: lifting, the drum accelerates at
    # (i eta M - m g r) / (J_d + m r^2 + eta i^2 J_m) = 43.8 / 8.9 rad/s^2; with the motor
    # off at t_m = 1 s it decelerates at m g r / 8.9 = 196.2 / 8.9, stops at
    # 1 + 43.8 / 196.2 s and stays locked (self-locking: the load cannot drive the worm).
    model = md.load_model("models/worm_hoist.py")
    res = run(model, "lift", backend)
    drum = md.speed(md.coordinate("phi_d"))
    assert res.at(0.5, drum) == pytest.approx(0.5 * 43.8 / 8.9, rel=1e-9)
    stop = 1 + 43.8 / 196.2
    assert res.at(1.1, drum) == pytest.approx(43.8 / 8.9 - 0.1 * 196.2 / 8.9, rel=1e-9)
    stick = [e for e in res.events if e.kind == "stick"]
    assert stick and stick[0].time == pytest.approx(stop, rel=1e-9)
    assert res.final(drum) == 0.0


def _compare(model_path, scene_name, rtol):
    """The compiled path against scipy: same events (kinds, elements; times within
    ``rtol`` of the run's length), the same final state within ``rtol``."""
    model = md.load_model(model_path)
    compiled, reference = run(model, scene_name, "auto"), run(model, scene_name, "scipy")
    assert [(e.kind, e.name) for e in compiled.events] == \
        [(e.kind, e.name) for e in reference.events]
    span = reference.t_end
    for a, b in zip(compiled.events, reference.events):
        assert abs(a.time - b.time) <= rtol * span
    assert compiled.t_end == pytest.approx(reference.t_end, rel=rtol)
    scale = 1.0 + np.abs(reference.y[:, -1])
    assert np.all(np.abs(compiled.y[:, -1] - reference.y[:, -1]) <= rtol * scale)


@pytest.mark.parametrize("model_path, scene_name", [
    ("models/shoe_brake.py", "braking"), ("models/clutch_engagement.py", "engage")])
def test_friction_scenes_agree_with_scipy(model_path, scene_name):
    _compare(model_path, scene_name, 1e-7)


@pytest.mark.slow
@pytest.mark.parametrize("model_path, scene_name", [
    ("models/clutch_engagement.py", "engage_loaded"), ("models/hoist_drive.py", "lower_brake"),
    ("models/worm_hoist.py", "hold"), ("models/hard_stop.py", "bounce"),
    ("models/motor_startup.py", "braking"), ("models/press_cycle.py", "startup"),
    ("models/fourbar_flywheel.py", "startup"), ("models/quick_return.py", "startup"),
    ("models/watt_sixbar.py", "startup"), ("models/toggle_press.py", "startup")])
def test_bundled_scenes_agree_with_scipy(model_path, scene_name):
    _compare(model_path, scene_name, 1e-5)


def _loop_with_one_sided_spring():
    """A conservative crank-rocker four-bar (gravity) whose rocker meets a one-sided
    spring, a ``Piecewise`` of position: energy ``T + V + k/2 max(theta_3 - th0, 0)^2``
    is conserved (the spring's potential is continuous across the switch)."""
    a, b, c, d, k, th0 = 0.1, 0.35, 0.3, 0.4, 40.0, 1.9
    phi, th2, th3 = md.coordinates("phi theta_2 theta_3")
    mech = md.Mechanism("four-bar on a spring", [phi, th2, th3], independent=[phi])
    pin = (a * sp.cos(phi), a * sp.sin(phi))
    mech.link("crank", J=0.002, angle=phi)
    mech.link("coupler", m=1.5, J=1.5 * b**2 / 12, x=pin[0] + b / 2 * sp.cos(th2),
              y=pin[1] + b / 2 * sp.sin(th2), angle=th2)
    mech.link("rocker", m=1.2, J=1.2 * c**2 / 12, x=d + c / 2 * sp.cos(th3),
              y=c / 2 * sp.sin(th3), angle=th3)
    mech.loop("ABCD", (a, phi), (b, th2), (-c, th3), (-d, 0))
    mech.gravity(9.81)
    mech.load("spring", sp.Piecewise((-k * (th3 - th0), th3 > th0), (0, True)), along=th3)
    return mech, (phi, th2, th3), (k, th0)


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_closed_loop_with_a_switch_delivers_the_tolerance_asked_for(backend):
    """The energy error falls with rtol down to 1e-10 (below 10 rtol at every
    tolerance). The projection onto the loop after each switch must not make the
    switch fire again (chattering, then muted: the error stayed near 1e-8)."""
    mech, (phi, th2, th3), (k, th0) = _loop_with_one_sided_spring()
    errors = []
    for rtol in (1e-7, 1e-8, 1e-10):
        scene = md.Scene("free", initial={phi: 0, md.speed(phi): 30.0, th2: 1.2, th3: 1.9},
                         t_end=2.0, rtol=rtol, backend=backend)
        res = mech.simulate(scene, {})
        assert set(res.stats["backends"]) == ({"compiled"} if backend == "auto"
                                              else {"scipy"})
        assert res.stats["segments"] > 10               # every switch is a segment
        kinetic, potential = res.energy()
        total = kinetic + potential + 0.5 * k * np.maximum(res[th3] - th0, 0.0) ** 2
        errors.append(float(np.max(np.abs(total - total[0]))) / kinetic[0])
        assert errors[-1] < 10 * rtol, (rtol, errors)
    assert errors[0] > errors[1] > errors[2]


@pytest.mark.slow
def test_the_six_bar_error_falls_with_the_tolerance_on_both_backends():
    """watt_sixbar (two loops, a switching load on a speed) against scipy at rtol
    1e-12: the final state within 10 rtol at 1e-8 and 1e-10 on both backends."""
    model = md.load_model("models/watt_sixbar.py")
    scene = model.scenes["startup"]

    def final(**options):
        res = model.mechanism.simulate(dataclasses.replace(scene, **options), model.params)
        return res.y[:, -1]
    reference = final(backend="scipy", rtol=1e-12)
    for rtol in (1e-8, 1e-10):
        for backend in BACKENDS:
            error = np.max(np.abs(final(backend=backend, rtol=rtol) - reference)
                           / (1.0 + np.abs(reference)))
            assert error < 10 * rtol, (backend, rtol, error)


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_run_after_the_values_or_the_mechanism_changed_uses_the_new_ones(backend):
    # The checked values and the start are kept per scene and values for the next run:
    # a dict changed in place, or a changed mechanism, must not get the kept ones.
    # A moment M swings J through 0.5 rad to a stop: impact at sqrt(2 J 0.5 / M).
    theta = md.coordinate("theta")
    J, M = sp.symbols("J M", positive=True)
    lever = md.Mechanism("lever", [theta])
    lever.link("lever", J=J, angle=theta)
    lever.load("drive", M, along=theta)
    lever.stop("end stop", along=theta, lower=-1, upper=0.5, restitution=0)
    scene = md.Scene("swing", initial={theta: 0, md.speed(theta): 0}, t_end=0.3,
                     backend=backend)
    params = {J: 0.02, M: 4}

    def impact():
        return next(e.time for e in lever.simulate(scene, params).events
                    if e.kind == "impact")
    assert impact() == pytest.approx(math.sqrt(2 * 0.02 * 0.5 / 4), rel=1e-10)
    assert impact() == pytest.approx(math.sqrt(2 * 0.02 * 0.5 / 4), rel=1e-10)   # again
    params[J] = 0.08                                           # the same dict, changed
    assert impact() == pytest.approx(math.sqrt(2 * 0.08 * 0.5 / 4), rel=1e-10)
    lever.load("brake", -3, along=theta)                       # net 1 N m
    assert impact() == pytest.approx(math.sqrt(2 * 0.08 * 0.5 / 1), rel=1e-10)
    scene.initial[theta] = 0.3                 # the scene's start changed in place: 0.2 rad
    assert impact() == pytest.approx(math.sqrt(2 * 0.08 * 0.2 / 1), rel=1e-10)


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_brake_holds_the_middle_coordinate_while_the_others_move(backend):
    # q2 (the second of three) is held by a brake far above its load; q1 carries both
    # masses (1.5 + 0.7 kg) under sin(3 t) from rest: q1 = (t/3 - sin(3 t)/9) / 2.2; the
    # free disc on q3 turns on at its 2 rad/s. A held coordinate fixes its own speed and
    # acceleration, no other's.
    q1, q2, q3 = md.coordinate("q1"), md.coordinate("q2"), md.coordinate("q3")
    mech = md.Mechanism("held middle", [q1, q2, q3])
    mech.link("carriage", m=sp.Rational(3, 2), x=q1)
    mech.link("slider", m=sp.Rational(7, 10), x=q1 + q2)
    mech.link("disc", J=1, angle=q3)
    mech.friction("brake", 10, along=q2)
    mech.load("push", sp.sin(3 * md.t), along=q1)
    scene = md.Scene("push", initial={q1: 0, q2: 0.3, q3: 0, md.speed(q1): 0,
                                      md.speed(q2): 0, md.speed(q3): 2}, t_end=5,
                     rtol=1e-10, backend=backend)
    res = mech.simulate(scene, {})
    assert set(res.stats["backends"]) == ({"compiled"} if backend == "auto" else {"scipy"})
    assert not [e for e in res.events if e.kind == "slip"]
    assert res.final(q2) == 0.3 and res.final(md.speed(q2)) == 0.0
    assert res.final(q1) == pytest.approx((5 / 3 - math.sin(15) / 9) / 2.2, rel=1e-8)
    assert res.final(q3) == pytest.approx(10.0, rel=1e-10)


def test_the_scipy_backend_never_compiles_the_scene_for_the_kernels(monkeypatch):
    # backend="scipy" asks for no numba code: the scene's compiled form is not even built
    # (a compilation takes seconds and is announced); a free disc turns at its speed.
    from mechdyn.simulate import methods

    def compile_for_kernels(*args):
        raise AssertionError("compiled for the kernels under backend='scipy'")
    monkeypatch.setattr(methods, "compiled_functions", compile_for_kernels)
    phi = md.coordinate("phi")
    mech = md.Mechanism("scipy disc", [phi])
    mech.link("disc", J=2, angle=phi)
    scene = md.Scene("turn", initial={phi: 0, md.speed(phi): 3}, t_end=2, backend="scipy")
    res = mech.simulate(scene, {})
    assert set(res.stats["backends"]) == {"scipy"}
    assert res.final(phi) == pytest.approx(6.0, rel=1e-9)

"""Closed forms and inverse dynamics in detail: the printed solution, the classification
of a scene (not of the whole mechanism), parameters that remove a dependence, and the
driving moment of a uniformly accelerated disc with Coulomb friction, by hand."""
import math

import pytest
import sympy as sp

import mechdyn as md

phi = md.coordinate("phi")


def test_printed_closed_form_of_the_shoe_brake():
    # Worked example 1: omega = 100 - 2 t, phi = 100 t - t^2, at rest at t = 50, 2500 rad.
    brake = md.load_model("models/shoe_brake.py")
    sol = md.closed_form(brake.mechanism, brake.scenes["braking"], brake.params)
    assert str(sol).splitlines()[:4] == [
        str(sol.classification), "  phidot(t) = 100 - 2*t", "  phi(t) = -t**2 + 100*t",
        "  stop (stopped(phi)): t = 50, phi = 2500, phidot = 0"]


def test_an_irrational_stop_is_printed_exactly_and_as_a_number():
    # The coasting yoke stops where cos(phi) = 3/4 (energy: J w0^2/2 = F l (1 - cos phi)).
    yoke = md.load_model("models/scotch_yoke.py")
    q = yoke.mechanism.coordinates[0]
    coast = md.Scene("coast", effects=["resistance"], initial={q: 0, md.speed(q): 5},
                     until=md.stopped(q))
    text = str(md.closed_form(yoke.mechanism, coast, yoke.params))
    assert "phi = acos(3/4) (= 0.722734247813), phidot = 0" in text
    assert "  phidot(phi) = " in text and "  t(phi) = " in text


def test_classification_is_of_the_scene_not_the_whole_mechanism():
    # Braking: brake and constant load only -> case 1; the whole machine has the Kloss
    # motor, a moment of the speed -> case 2.
    motor = md.load_model("models/motor_startup.py")
    braking = md.classify(motor.mechanism, motor.scenes["braking"], motor.params)
    assert str(braking).startswith("case 1:")
    assert str(md.classify(motor.mechanism, None, motor.params)).startswith("case 2:")


def test_a_parameter_of_zero_removes_a_dependence():
    a, b = sp.symbols("a b")
    disc = md.Mechanism("disc", [phi])
    disc.link("disc", J=2, angle=phi)
    disc.load("drive", a + b * md.speed(phi), along=phi)
    scene = md.Scene("run", initial={phi: 0, md.speed(phi): 1}, t_end=1)
    assert str(md.classify(disc, scene, {a: 1, b: 0})).startswith("case 1:")
    assert str(md.classify(disc, scene, {a: 1, b: 2})).startswith("case 2:")


def test_classify_errors_say_classify():
    a, b = md.coordinates("a b")
    pair = md.Mechanism("pair", [a, b])
    pair.link("A", J=1, angle=a)
    pair.link("B", J=1, angle=b)
    with pytest.raises(md.AnalyticError, match=r"^classify: 'pair' has 2 coordinates"):
        md.classify(pair)


def braked_disc():
    disc = md.Mechanism("disc", [phi])
    disc.link("disc", J=2, angle=phi)
    disc.load("drive", 0, along=phi)
    disc.friction("bearing", 5, along=phi)
    return disc


@pytest.mark.parametrize("eps, omega0, moment", [
    (3, 4, 2 * 3 + 5),        # forward: friction resists with 5
    (-3, 4, 2 * -3 + 5),      # decelerating, still forward
    (3, -4, 2 * 3 - 5),       # backward: friction pushes forward
    (-3, 0, 2 * -3 - 5),      # from rest, backward
])
def test_uniformly_accelerated_disc_needs_J_eps_plus_friction_against_the_motion(
        eps, omega0, moment):
    # J phi'' = M_drive - 5 sign(omega): M_drive = J eps + 5 sign(omega), the sense of
    # motion taken from omega0, or from eps when starting at rest.
    motion = md.uniform_acceleration(eps, omega0=omega0, phi0=1, duration=0.5)
    assert motion.law == 1 + omega0 * md.t + sp.Rational(eps, 2) * md.t ** 2
    drive = md.driving_moment(braked_disc(), motion, drive="drive")
    assert drive.expression == moment
    assert drive.mean == pytest.approx(moment) and drive.peak == pytest.approx(abs(moment))


@pytest.mark.parametrize("call, culprit", [
    (lambda: md.uniform_acceleration("3"), "uniform_acceleration: eps"),
    (lambda: md.uniform_acceleration(3, omega0="1"), "uniform_acceleration: omega0"),
    (lambda: md.uniform_acceleration(3, phi0="1"), "phi0"),
])
def test_uniform_acceleration_names_a_bad_argument(call, culprit):
    with pytest.raises(md.DeclarationError, match=rf"^{culprit}: got the string"):
        call()


@pytest.mark.parametrize("omega, moment", [(10, 5), (-10, -5)])
def test_uniform_rotation_of_a_braked_disc_needs_the_friction_moment(omega, moment):
    # Constant speed: no inertia term; friction 5 against the sense of rotation.
    motion = md.uniform_rotation(omega, phi0=2)
    assert motion.law == 2 + omega * md.t
    assert float(motion.window) == pytest.approx(2 * math.pi / 10)     # one revolution
    drive = md.driving_moment(braked_disc(), motion, drive="drive")
    assert drive.expression == moment and drive.mean == pytest.approx(moment)
    assert drive.rms == pytest.approx(abs(moment))


def test_statistics_need_a_time_window_and_every_parameter():
    J = sp.Symbol("J", positive=True)
    disc = md.Mechanism("disc", [phi])
    disc.link("disc", J=J, angle=phi)
    disc.load("drive", 0, along=phi)
    no_window = md.driving_moment(braked_disc(), md.uniform_acceleration(3), drive="drive")
    with pytest.raises(md.ParameterError, match=r"no numeric time window \(give duration=\)"):
        no_window.mean
    unknown = md.driving_moment(disc, md.uniform_acceleration(3, duration=1), drive="drive")
    with pytest.raises(md.ParameterError, match=r"give values of \['J'\]"):
        unknown.mean
    known = md.driving_moment(disc, md.uniform_acceleration(3, duration=1), {J: 2},
                              drive="drive")
    assert known.mean == pytest.approx(6.0)


@pytest.mark.parametrize("call, culprit", [
    (lambda: md.uniform_rotation("10"), "uniform_rotation: omega"),
    (lambda: md.uniform_rotation(10, phi0="1"), "phi0"),
])
def test_uniform_rotation_names_a_bad_argument(call, culprit):
    with pytest.raises(md.DeclarationError, match=rf"^{culprit}: got the string"):
        call()


def test_driving_moment_takes_the_loads_of_the_scene_only():
    # Without the bearing friction in the scene, only J eps = 2 * 3 = 6 is needed.
    disc = braked_disc()
    scene = md.Scene("frictionless", effects=["drive"], initial={phi: 0, md.speed(phi): 4},
                     t_end=1)
    motion = md.uniform_acceleration(3, omega0=4, duration=0.5)
    assert md.driving_moment(disc, motion, scene=scene, drive="drive").expression == 6
    assert md.driving_moment(disc, motion, drive="drive").expression == 11


def test_released_from_rest_the_sense_of_motion_comes_from_the_moment():
    # J = 2 on a spring k = 8 released at phi = 1: the spring pulls back, so the speed is
    # negative: omega(phi) = -sqrt(k/J (1 - phi^2)) = -2 sqrt(1 - phi^2); phi = 0 is
    # reached after a quarter period, pi/2 sqrt(J/k) = pi/4, at omega = -2.
    disc = md.Mechanism("disc", [phi])
    disc.link("disc", J=2, angle=phi)
    disc.spring("spring", 8, stretch=phi)
    release = md.Scene("release", initial={phi: 1, md.speed(phi): 0},
                       until=md.reaches(phi, 0))
    sol = md.closed_form(disc, release, {})
    assert float(sol.stop.t) == pytest.approx(math.pi / 4, rel=1e-9)
    assert float(sol.stop.omega) == pytest.approx(-2.0, rel=1e-12)
    assert sol.function("omega(phi)")(0.5) == pytest.approx(-2 * math.sqrt(0.75), rel=1e-12)

"""Closed forms, the five-case classification and inverse dynamics (mechdyn.derive.analytic).

Every reference value is worked out here by hand (or taken from the worked examples),
never from the code under test.
"""
import dataclasses
import math
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import quad

import mechdyn as md
from mechdyn.cli import main

MODELS = Path(__file__).resolve().parent.parent / "models"
t = md.t
phi = md.coordinate("phi")


def model(name):
    return md.load_model(MODELS / f"{name}.py")


def disc(J=2, name="disc"):
    """A disc of inertia J on the coordinate phi (loads added by each test)."""
    mech = md.Mechanism(name, [phi])
    mech.link("disc", J=J, angle=phi)
    return mech


def scene(speed, until=(), t_end=None, name="run"):
    return md.Scene(name, initial={phi: 0, md.speed(phi): speed}, until=until, t_end=t_end)


# ---------------------------------------------------------------- the worked examples
def test_shoe_brake_stops_after_50_s_and_2500_rad_exactly():
    brake = model("shoe_brake")
    sol = md.closed_form(brake.mechanism, brake.scenes["braking"], brake.params)
    # M_fr = f 2P R = 0.8 N m, eps = -0.8 / 0.4 = -2 rad/s^2, from 100 rad/s.
    assert sol.classification.case == 1
    assert sp.expand(sol["omega(t)"] - (100 - 2 * t)) == 0
    assert sp.expand(sol["phi(t)"] - (100 * t - t**2)) == 0
    assert sol.stop.t == 50 and sol.stop.t.is_Integer
    assert sol.stop.phi == 2500 and sol.stop.phi.is_Integer
    assert float(sol.stop.phi / (2 * sp.pi)) == pytest.approx(397.9, abs=0.05)


def test_rope_hoist_phi2_has_the_worked_example_coefficients_as_exact_rationals():
    hoist = model("rope_hoist")
    sol = md.closed_form(hoist.mechanism, hoist.scenes["startup"], hoist.params)
    # By hand from eps2 = (M R1 R2 - (G3 r2 + Mc) R1^2) / (I1 R2^2 + I_red2 R1^2).
    F = Fraction
    I1, R1, R2, r2, Mc = F(8), F("0.6"), F("0.4"), F("0.2"), F(2000)
    G3 = 400 * F("9.81")
    I_red2 = 150 * F("0.3") ** 2 + 400 * r2**2
    denominator = I1 * R2**2 + I_red2 * R1**2
    slope = 200 * R1 * R2 / denominator                             # of eps2 in t
    offset = (4200 * R1 * R2 - (G3 * r2 + Mc) * R1**2) / denominator
    expected = slope / 6 * t**3 + offset / 2 * t**2 + 3 * t       # omega2(0) = 3, phi2(0) = 0
    phi2 = sol["phi(t)"]
    assert sp.expand(phi2 - sp.sympify(expected)) == 0
    coefficients = sp.Poly(phi2, t).all_coeffs()
    assert all(c.is_Rational for c in coefficients)
    assert [float(c) for c in coefficients] == pytest.approx([0.67227, 0.22992, 3, 0],
                                                             abs=1e-4)


def test_planetary_train_needs_21_76_N_m_for_its_uniform_start_up():
    train = model("planetary_2kh")
    start_up = md.uniform_acceleration(20 * sp.pi / 3, duration=3)   # 600 rpm in 3 s
    needed = md.driving_moment(train.mechanism, start_up, train.params, drive="drive")
    # M1 = M_H / 3 + I_red eps = 5 + 0.8 * 20 pi / 3.
    assert sp.simplify(needed.expression - (5 + sp.Rational(4, 5) * 20 * sp.pi / 3)) == 0
    assert float(needed.expression) == pytest.approx(21.76, abs=0.005)
    assert needed.mean == pytest.approx(5 + 0.8 * 20 * math.pi / 3, rel=1e-12)


def test_scotch_yoke_driving_moment_for_uniform_rotation_is_the_textbook_expression():
    yoke = model("scotch_yoke")
    omega = sp.Symbol("omega", positive=True)
    q = md.plain(yoke.mechanism.coordinates[0])
    m3, l, F3 = sp.symbols("m_3 l F_3", positive=True)
    needed = md.driving_moment(yoke.mechanism, md.uniform_rotation(omega), drive="drive")
    expected = m3 * l**2 * sp.sin(q) * sp.cos(q) * omega**2 + F3 * l * sp.sin(q)
    assert sp.simplify(needed.expression - expected) == 0
    assert "M_{\\mathrm{drive}}" in needed.latex()


def test_scotch_yoke_driving_moment_mean_rms_and_peak_over_a_revolution():
    yoke = model("scotch_yoke")
    needed = md.driving_moment(yoke.mechanism, md.uniform_rotation(10), yoke.params,
                               drive="motor")
    # M = A sin(2 phi) / 2 + B sin(phi), A = m3 l^2 omega^2 = 2, B = F3 l = 1: both terms
    # average to zero over a revolution and are orthogonal, so RMS^2 = A^2/8 + B^2/2.
    A, B = 2.0 * 0.1**2 * 10**2, 10.0 * 0.1
    # mean and RMS are quad's at epsabs = epsrel = 1e-12 (mechdyn.derive.analytic)
    assert needed.mean == pytest.approx(0.0, abs=1e-12)
    assert needed.rms == pytest.approx(math.sqrt(A**2 / 8 + B**2 / 2), rel=1e-10)
    angles = np.linspace(0, 2 * np.pi, 200001)
    dense_peak = np.max(np.abs(A / 2 * np.sin(2 * angles) + B * np.sin(angles)))
    assert needed.peak == pytest.approx(dense_peak, rel=1e-8)


def test_run_down_of_the_planetary_train_with_the_drive_removed():
    train = model("planetary_2kh")
    q = train.mechanism.coordinates[0]
    run_down = md.Scene("run-down", effects=["carrier load"], until=md.stopped(q),
                        initial={q: 0, md.speed(q): 20 * sp.pi})
    sol = md.closed_form(train.mechanism, run_down, train.params)
    # Decelerated by M_H / 3 = 5 N m on I_red = 0.8: t = I w0 / 5, phi = I w0^2 / (2 * 5).
    assert sol.stop.t == sp.Rational(4, 5) * 20 * sp.pi / 5
    assert sol.stop.phi == sp.Rational(4, 5) * (20 * sp.pi) ** 2 / 10


# ----------------------------------------------------------------- the other cases
def dc_shunt():
    I, M0, w0 = sp.symbols("I M_0 omega_0", positive=True)
    mech = disc(J=I, name="DC shunt start-up")
    mech.load("motor", M0 * (1 - md.speed(phi) / w0), along=phi)
    return mech, (I, M0, w0)


def test_dc_shunt_start_up_approaches_no_load_speed_with_time_constant_I_w0_over_M0():
    mech, (I, M0, w0) = dc_shunt()
    sol = md.closed_form(mech, scene(0, t_end=10))
    # I dw/dt = M0 (1 - w/w0) is linear: w = w0 (1 - exp(-t/tau)), tau = I w0 / M0.
    tau = I * w0 / M0
    assert sol.classification.case == 2
    assert sp.simplify(sol["omega(t)"] - w0 * (1 - sp.exp(-t / tau))) == 0
    assert sp.simplify(sol["phi(t)"] - w0 * (t - tau * (1 - sp.exp(-t / tau)))) == 0


def test_dc_shunt_reaches_90_percent_speed_after_tau_ln_10():
    mech, (I, M0, w0) = dc_shunt()
    params = {I: 0.5, M0: 20, w0: 100}
    sol = md.closed_form(mech, scene(0, until=md.reaches(md.speed(phi), 90)), params)
    tau = 0.5 * 100 / 20
    assert float(sol.stop.t) == pytest.approx(tau * math.log(10), rel=1e-14)
    assert sol.function("t(omega)")(50.0) == pytest.approx(tau * math.log(2), rel=1e-14)


def yoke_case_3(speed=5):
    yoke = model("scotch_yoke")
    q = yoke.mechanism.coordinates[0]
    start = md.Scene("coast", initial={q: 0, md.speed(q): speed}, t_end=0.4)
    return yoke, start


def test_energy_integral_of_the_scotch_yoke_gives_omega_of_phi():
    yoke, start = yoke_case_3()
    sol = md.closed_form(yoke.mechanism, start, yoke.params)
    # By hand: I(phi) w^2 / 2 = I(0) w0^2 / 2 + M1 phi + F3 l (cos(phi) - 1),
    # I(phi) = J1A + m3 l^2 sin(phi)^2; J1A = 0.02, m3 = 2, l = 0.1, M1 = 2, F3 = 10.
    q = md.plain(yoke.mechanism.coordinates[0])
    inertia = sp.Rational(1, 50) + 2 * sp.Rational(1, 100) * sp.sin(q) ** 2
    work = 2 * q + 10 * sp.Rational(1, 10) * (sp.cos(q) - 1)
    hand = sp.sqrt((sp.Rational(1, 50) * 25 + 2 * work) / inertia)
    assert sol.classification.case == 3
    assert sp.simplify(sol["omega(phi)"] ** 2 - hand**2) == 0
    angles = np.linspace(0, 3, 7)
    assert sol.function("omega(phi)")(angles) == pytest.approx(
        [float(hand.subs(q, a)) for a in angles], rel=1e-13)


def test_spring_case_2_time_by_quadrature_matches_the_arcsine():
    k = sp.Symbol("k", positive=True)
    mech = disc(J=2)
    mech.spring("spring", k, stretch=phi)
    sol = md.closed_form(mech, scene(3, until=md.stopped(phi)), {k: 8})
    # w = sqrt(k/J) = 2; phi = (3/2) sin(2 t): t(phi) = asin(2 phi / 3) / 2, the stop at
    # a quarter period pi / 4, phi = 3/2.
    angles = np.array([0.0, 0.5, 1.0, 1.4])
    # t(phi) is scipy's quad asked for 1e-12 relative (mechdyn.derive.analytic._QUAD)
    assert sol.function("t(phi)")(angles) == pytest.approx(np.arcsin(2 * angles / 3) / 2,
                                                          rel=1e-12)
    assert float(sol.stop.t) == pytest.approx(math.pi / 4, rel=1e-10)
    assert sol.stop.phi == sp.Rational(3, 2)
    assert "t(phi)" in sol.quadrature


@pytest.mark.parametrize("moment, case", [
    (lambda: -3 - 2 * md.speed(phi) - 5 * phi, 4),             # M(phi, omega)
    (lambda: sp.sin(t) - md.speed(phi), 4),                     # M(t, omega): mixed
])
def test_cases_4_and_mixed_are_numerical(moment, case):
    mech = disc()
    mech.load("load", moment(), along=phi)
    kind = md.classify(mech, scene(1, t_end=1))
    assert (kind.case, kind.closed_form) == (case, False)
    assert "numerical integration" in kind.description
    assert "(mixed)" in kind.description          # M_red of two of t, phi, omega
    with pytest.raises(md.AnalyticError, match="no closed form.*simulate"):
        md.closed_form(mech, scene(1, t_end=1))


def test_case_5_is_numerical():
    yoke = model("scotch_yoke")
    q = yoke.mechanism.coordinates[0]
    yoke.mechanism.damper("oil", 0.1, stretch=q)
    kind = md.classify(yoke.mechanism)
    assert (kind.case, kind.inertia_varies, kind.closed_form) == (5, True, False)
    assert kind.moment_depends_on == ("phi", "omega")


def test_classification_of_the_integrable_cases_in_words():
    assert md.classify(model("shoe_brake").mechanism).case == 1
    hoist = md.classify(model("rope_hoist").mechanism)
    assert (hoist.case, hoist.moment_depends_on) == (2, ("t",))
    assert "the time t" in hoist.description and "mixed" not in hoist.description
    yoke = md.classify(model("scotch_yoke").mechanism)
    assert (yoke.case, yoke.inertia_varies) == (3, True)


# ------------------------------------------------------------------------ bad input
def test_multi_dof_mechanism_is_refused_with_a_way_out():
    a, b = md.coordinates("a b")
    two = md.Mechanism("two discs", [a, b])
    two.link("one", J=1, angle=a)
    two.link("two", J=1, angle=b)
    two.spring("shaft", 10, stretch=a - b)
    with pytest.raises(md.AnalyticError, match="2 coordinates.*one-DOF.*simulate"):
        md.classify(two)
    with pytest.raises(md.MechdynError, match="one-DOF"):
        md.driving_moment(two, md.uniform_rotation(1))


def test_friction_starting_at_rest_is_left_to_the_simulation():
    mech = disc()
    mech.friction("brake", 1, along=phi)
    with pytest.raises(md.AnalyticError, match="at rest with friction"):
        md.closed_form(mech, scene(0, t_end=1))


def test_unknown_drive_and_missing_parameters_are_named():
    yoke = model("scotch_yoke")
    with pytest.raises(md.AnalyticError, match="no load named or tagged 'pump'"):
        md.driving_moment(yoke.mechanism, md.uniform_rotation(1), drive="pump")
    needed = md.driving_moment(yoke.mechanism, md.uniform_rotation(1), drive="drive")
    with pytest.raises(md.ParameterError, match="F_3"):
        needed.mean
    with pytest.raises(md.AnalyticError, match="md.Motion"):
        md.driving_moment(yoke.mechanism, 10)


def test_cli_solve_prints_classification_and_stop(capsys):
    path = str(MODELS / "shoe_brake.py")
    assert main(["equations", path, "--scene", "braking", "--solve", "--format", "text"]) == 0
    out = capsys.readouterr().out
    assert "case 1" in out and "t = 50" in out and "= 2500" in out
    assert main(["equations", path, "--solve"]) == 2
    assert "--solve needs --scene" in capsys.readouterr().err


# ------------------------------------------------- agreement with the simulation
def tight(scene_):
    return dataclasses.replace(scene_, rtol=1e-12, atol=1e-12)


def test_brake_simulation_agrees_with_the_closed_form():
    brake = model("shoe_brake")
    res = brake.mechanism.simulate(tight(brake.scenes["braking"]), brake.params)
    assert res.t_end == pytest.approx(50.0, rel=1e-8)
    assert res.final(brake.mechanism.coordinates[0]) == pytest.approx(2500.0, rel=1e-8)


def test_rope_hoist_simulation_agrees_with_the_closed_form():
    hoist = model("rope_hoist")
    q = hoist.mechanism.coordinates[0]
    sol = md.closed_form(hoist.mechanism, hoist.scenes["startup"], hoist.params)
    res = hoist.mechanism.simulate(tight(hoist.scenes["startup"]), hoist.params)
    times = np.linspace(0, 3, 31)
    exact = sol.function("phi(t)")(times)
    assert res.at(times, q) == pytest.approx(exact, rel=1e-8, abs=1e-8 * exact.max())
    assert res.final(md.speed(q)) == pytest.approx(float(sol["omega(t)"].subs(t, 3)), rel=1e-8)


def test_dc_shunt_simulation_agrees_with_the_closed_form():
    mech, (I, M0, w0) = dc_shunt()
    params = {I: 0.5, M0: 20, w0: 100}
    start = scene(0, until=md.reaches(md.speed(phi), 90))
    sol = md.closed_form(mech, start, params)
    res = mech.simulate(tight(start), params)
    times = np.linspace(0, res.t_end, 25)
    exact = sol.function("omega(t)")(times)
    assert res.at(times, md.speed(phi)) == pytest.approx(exact, rel=1e-8, abs=1e-8 * 90)
    assert res.t_end == pytest.approx(float(sol.stop.t), rel=1e-8)


def test_scotch_yoke_case_3_simulation_agrees_with_the_energy_integral():
    yoke, start = yoke_case_3()
    q = yoke.mechanism.coordinates[0]
    sol = md.closed_form(yoke.mechanism, start, yoke.params)
    res = yoke.mechanism.simulate(tight(start), yoke.params)
    assert sol.function("omega(phi)")(res[q]) == pytest.approx(res[md.speed(q)], rel=1e-8)
    assert sol.function("t(phi)")(res[q][1:]) == pytest.approx(res.t[1:], rel=1e-8)


def test_spring_stop_simulation_agrees_with_the_closed_form():
    k = sp.Symbol("k", positive=True)
    mech = disc(J=2)
    mech.spring("spring", k, stretch=phi)
    swing = scene(3, until=md.stopped(phi))
    sol = md.closed_form(mech, swing, {k: 8})
    res = mech.simulate(tight(swing), {k: 8})
    assert res.t_end == pytest.approx(float(sol.stop.t), rel=1e-8)
    assert res.final(phi) == pytest.approx(float(sol.stop.phi), rel=1e-8)


def test_speed_dependent_moment_without_antiderivative_uses_quadrature_and_agrees():
    mech = disc(J=2)
    mech.load("drag", -(1 + md.speed(phi) + sp.exp(-md.speed(phi))), along=phi)
    coast = scene(10, until=md.stopped(phi))
    sol = md.closed_form(mech, coast)
    assert sol.quadrature == ("t(omega)", "phi(omega)")
    assert any("numeric quadrature" in note for note in sol.notes)
    res = mech.simulate(tight(coast), {})
    assert res.t_end == pytest.approx(float(sol.stop.t), rel=1e-8)
    assert res.final(phi) == pytest.approx(float(sol.stop.phi), rel=1e-8)
    # Both against the quadratures written here: J w' = -(1 + w + e^-w), so
    # t_stop = int_0^10 J dw / (1 + w + e^-w), phi_stop = int_0^10 J w dw / (1 + w + e^-w).
    t_stop = quad(lambda w: 2 / (1 + w + math.exp(-w)), 0, 10, epsabs=1e-13, epsrel=1e-13)[0]
    phi_stop = quad(lambda w: 2 * w / (1 + w + math.exp(-w)), 0, 10, epsabs=1e-13,
                    epsrel=1e-13)[0]
    assert res.t_end == pytest.approx(t_stop, rel=1e-8)
    assert res.final(phi) == pytest.approx(phi_stop, rel=1e-8)


def test_coasting_yoke_stops_at_its_turning_point_and_never_reaches_beyond():
    yoke = model("scotch_yoke")
    q = yoke.mechanism.coordinates[0]

    def coast(until):
        return md.Scene("coast", effects=["resistance"], initial={q: 0, md.speed(q): 5},
                        until=until)
    sol = md.closed_form(yoke.mechanism, coast(md.stopped(q)), yoke.params)
    # Energy: J1A w0^2 / 2 = 0.25 = F3 l (1 - cos(phi)) = 1 - cos(phi): cos(phi) = 3/4.
    assert sol.stop.phi == sp.acos(sp.Rational(3, 4))
    res = yoke.mechanism.simulate(tight(coast(md.stopped(q))), yoke.params)
    assert res.t_end == pytest.approx(float(sol.stop.t), rel=1e-8)
    beyond = md.closed_form(yoke.mechanism, coast(md.reaches(q, 1)), yoke.params)
    assert beyond.stop is None
    assert any("not reached" in note for note in beyond.notes)


def test_kloss_start_up_gives_t_of_omega_without_hanging_on_its_inversion():
    motor = model("motor_startup")
    start = motor.scenes["startup"]
    sol = md.closed_form(motor.mechanism, start, motor.params)
    assert "omega(t)" not in sol.relations and not sol.quadrature
    res = motor.mechanism.simulate(tight(start), motor.params)
    assert res.t_end == pytest.approx(float(sol.stop.t), rel=1e-8)
    # Both against the quadrature written here: (J_m + J_f) w' = M_kloss(w) - M_L with
    # M_kloss = 2 M_k / (s/s_k + s_k/s), s = 1 - w/omega_s, from rest to 95 % of the
    # steady speed omega_s (1 - s_0), s_0 = s_k (M_k - sqrt(M_k^2 - M_L^2)) / M_L.
    J, M_k, s_k, w_s, M_L = 5.0, 200.0, 0.2, 157.08, 60.0
    s_0 = s_k * (M_k - math.sqrt(M_k**2 - M_L**2)) / M_L

    def moment(w):
        slip = 1 - w / w_s
        return 2 * M_k / (slip / s_k + s_k / slip) - M_L
    t_stop = quad(lambda w: J / moment(w), 0, 0.95 * w_s * (1 - s_0), epsabs=1e-13,
                  epsrel=1e-13)[0]
    assert res.t_end == pytest.approx(t_stop, rel=1e-8)

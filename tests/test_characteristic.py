"""Motor and load characteristics: operating points and their stability against closed
forms."""
import math
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

import mechdyn as md
from mechdyn import cli

ROOT = Path(__file__).resolve().parents[1]


def _drive(load):
    phi = md.coordinate("phi")
    machine = md.Mechanism("drive", [phi])
    machine.link("rotor", J=2.0, angle=phi)
    M_k, s_k, omega_s = sp.symbols("M_k s_k omega_s", positive=True)
    machine.load("motor", md.motors.kloss(M_k, s_k, omega_s)(md.speed(phi)), along=phi)
    machine.load("load", load(phi), along=phi)
    return machine, {M_k: 200, s_k: 0.2, omega_s: 157.08}


def test_an_induction_motor_on_a_heavy_load_has_a_stable_and_an_unstable_point():
    """Kloss 2 M_k s s_k / (s^2 + s_k^2) = M_L at s = s_k (M_k -+ sqrt(M_k^2 - M_L^2)) / M_L:
    the small slip is stable (the motor's moment falls with speed), the slip beyond the
    breakdown slip s_k unstable (it rises with speed, the constant load does not)."""
    machine, params = _drive(lambda phi: -150)
    curves = md.characteristic(machine, params=params)
    root = math.sqrt(200**2 - 150**2)
    slips = [0.2 * (200 + root) / 150, 0.2 * (200 - root) / 150]
    assert [p.speed for p in curves.points] == pytest.approx(
        [157.08 * (1 - s) for s in slips], rel=1e-10)
    assert [p.stable for p in curves.points] == [False, True]
    assert all(p.moment == pytest.approx(150, rel=1e-10) for p in curves.points)
    assert curves.points[0].motor_slope > 0 > curves.points[1].motor_slope
    assert curves.drive == ("motor",)


def test_a_position_dependent_load_counts_with_its_mean_over_a_cycle():
    """A DC shunt motor M_0 (1 - w/w_0) against c (1 + cos phi): the mean load is c, so
    the machine runs on average at w_0 (1 - c / M_0)."""
    phi = md.coordinate("phi")
    machine = md.Mechanism("press", [phi])
    machine.link("crank", J=1.0, angle=phi)
    machine.load("motor", md.motors.dc_shunt(80, 120)(md.speed(phi)), along=phi)
    machine.load("work", -20 * (1 + sp.cos(phi)), along=phi)
    curves = md.characteristic(machine)
    (point,) = curves.points
    assert point.speed == pytest.approx(120 * (1 - 20 / 80), rel=1e-10) and point.stable
    assert any("mean over a cycle" in note for note in curves.notes)


def test_a_speed_dependent_load_line():
    """Fan load k w^2 on a DC shunt motor: M_0 (1 - w/w_0) = k w^2; the load's slope
    2 k w exceeds the motor's -M_0/w_0, so the point is stable."""
    phi = md.coordinate("phi")
    fan = md.Mechanism("fan", [phi])
    fan.link("rotor", J=0.3, angle=phi)
    fan.load("motor", md.motors.dc_shunt(100, 200)(md.speed(phi)), along=phi)
    fan.load("air", -0.005 * md.speed(phi) ** 2, along=phi)
    (point,) = md.characteristic(fan).points
    assert point.speed == pytest.approx(100.0, rel=1e-10)
    assert point.load_slope == pytest.approx(2 * 0.005 * 100) and point.stable
    assert point.motor_slope == pytest.approx(-100 / 200)


def test_errors_name_the_problem():
    two = md.load_model(ROOT / "models" / "two_mass_drive.py")
    with pytest.raises(md.MechdynError, match="2 coordinates"):
        md.characteristic(two.mechanism, two.scenes["start"], two.params)
    machine, params = _drive(lambda phi: -150)
    with pytest.raises(md.MechdynError, match="no load named or tagged 'engine'"):
        md.characteristic(machine, params=params, drive="engine")
    with pytest.raises(md.MechdynError, match="give values for"):
        md.characteristic(machine)


def test_the_command_prints_the_points_and_plots(capsys, tmp_path):
    figure = tmp_path / "ml.png"
    status = cli.main(["characteristic", str(ROOT / "models" / "motor_startup.py"),
                       "--scene", "startup", "--units", "speed=rpm", "--plot", str(figure)])
    out = capsys.readouterr().out
    assert status == 0 and figure.read_bytes()[:4] == b"\x89PNG"
    # Kloss motor M_k = 200, s_k = 0.2 at 1500 rpm against M_L = 60 N m
    slip = 0.2 * (200 - math.sqrt(200**2 - 60**2)) / 60
    rpm = 157.08 * (1 - slip) * 30 / math.pi
    assert f"stable at {rpm:.6g} rpm, 60 N*m" in out


def _press(condition_of):
    """A crank press: crank r = 0.1 m, rod l = 0.4 m, slider at x = r cos phi +
    sqrt(l^2 - r^2 sin^2 phi); a pressing force F = 20 kN over the last 10 mm of the
    stroke (where ``condition_of(x, xdot)`` holds); a DC shunt motor M_0 (1 - w / w_0),
    M_0 = 100 N m, w_0 = 50 rad/s."""
    phi = md.coordinate("phi")
    r, l, F = 0.1, 0.4, 20000.0
    x = r * sp.cos(phi) + sp.sqrt(l ** 2 - r ** 2 * sp.sin(phi) ** 2)
    press = md.Mechanism("press", [phi])
    press.link("crank", J=1.0, angle=phi)
    press.load("motor", md.motors.dc_shunt(100, 50)(md.speed(phi)), along=phi)
    x0 = r + l - 0.01
    press.load("pressing", sp.Piecewise((-F, condition_of(x - x0, sp.diff(x, md.t))),
                                        (0, True)), along=x)
    return press


def test_a_short_pressing_pulse_counts_with_its_exact_work_per_cycle():
    """Pressing on the way in only (x > x0 and x' > 0): the work per cycle is F times
    10 mm, so the mean load is F 0.01 / (2 pi) = 31.83 N m and the operating speed
    w_0 (1 - M_L / M_0) (a 360-point grid gave a load 1.7 % off); the condition of
    position and speed is evaluated elementwise (it was a ValueError)."""
    press = _press(lambda above, xdot: (above > 0) & (xdot > 0))
    curves = md.characteristic(press, speeds=(1.0, 60.0))
    mean = 20000.0 * 0.01 / (2 * math.pi)
    (point,) = curves.points
    assert point.moment == pytest.approx(mean, rel=1e-9)
    assert point.speed == pytest.approx(50 * (1 - mean / 100), rel=1e-9) and point.stable


def test_a_moment_pulse_near_the_dead_centre_counts_with_its_exact_width():
    """A moment M = 500 N m against the crank wherever x > x0 (10 mm before the outer
    dead centre): x = x0 at cos phi_1 = (x0^2 - l^2 + r^2) / (2 x0 r), so it acts over
    2 phi_1 of each turn and the mean load is M phi_1 / pi."""
    phi = md.coordinate("phi")
    r, l = 0.1, 0.4
    x0 = r + l - 0.01
    x = r * sp.cos(phi) + sp.sqrt(l ** 2 - r ** 2 * sp.sin(phi) ** 2)
    press = md.Mechanism("press", [phi])
    press.link("crank", J=1.0, angle=phi)
    press.load("motor", md.motors.dc_shunt(100, 50)(md.speed(phi)), along=phi)
    press.load("pressing", sp.Piecewise((-500.0, x > x0), (0, True)), along=phi)
    phi_1 = math.acos((x0 ** 2 - l ** 2 + r ** 2) / (2 * x0 * r))
    (point,) = md.characteristic(press, speeds=(1.0, 60.0)).points
    assert point.moment == pytest.approx(500.0 * phi_1 / math.pi, rel=1e-9)


def test_a_pulse_on_both_strokes_does_no_work_per_cycle():
    """Pressing whenever x > x0 (in and out): F dx/dphi integrates to zero over a cycle,
    so the motor runs free at w_0."""
    press = _press(lambda above, xdot: above > 0)
    (point,) = md.characteristic(press, speeds=(1.0, 60.0)).points
    assert point.speed == pytest.approx(50.0, rel=1e-9)


def test_a_switch_that_moves_with_the_speed_is_averaged_exactly_at_each_speed():
    """A load c = 3000 N m acting where phi + w/100 lies in (1, 1.05): its switching
    positions move with the speed, so its knots are found per speed; at every speed of
    the range the window lies inside the cycle, so the mean is 0.05 c / (2 pi)."""
    phi = md.coordinate("phi")
    machine = md.Mechanism("window", [phi])
    machine.link("rotor", J=1.0, angle=phi)
    machine.load("motor", md.motors.dc_shunt(100, 50)(md.speed(phi)), along=phi)
    window = phi + md.speed(phi) / 100
    machine.load("knock", sp.Piecewise((-3000.0, (window > 1) & (window < 1.05)), (0, True)),
                 along=phi)
    curves = md.characteristic(machine, speeds=(0.0, 60.0))
    mean = 3000.0 * 0.05 / (2 * math.pi)
    assert np.allclose(curves.load, mean, rtol=1e-9, atol=0)
    (point,) = curves.points
    assert point.moment == pytest.approx(mean, rel=1e-9)
    assert point.speed == pytest.approx(50 * (1 - mean / 100), rel=1e-9)


def test_the_command_averages_a_load_of_position_and_speed(capsys, tmp_path):
    """`mechdyn characteristic` on the crank press pressing on the way in (it ended in
    an internal ValueError, exit 3): the point of the closed form, mean load
    F 0.01 / (2 pi)."""
    model = tmp_path / "press.py"
    model.write_text(
        "import sympy as sp\nimport mechdyn as md\n"
        "phi = md.coordinate('phi')\n"
        "x = 0.1 * sp.cos(phi) + sp.sqrt(0.4**2 - 0.1**2 * sp.sin(phi)**2)\n"
        "mechanism = md.Mechanism('press', [phi])\n"
        "mechanism.link('crank', J=1.0, angle=phi)\n"
        "mechanism.load('motor', md.motors.dc_shunt(100, 50)(md.speed(phi)), along=phi)\n"
        "mechanism.load('pressing', sp.Piecewise((-20000.0, (x > 0.49) & "
        "(sp.diff(x, md.t) > 0)), (0, True)), along=x)\n"
        "params = {}\n"
        "scenes = {'run': md.Scene('run', initial={phi: 0, md.speed(phi): 30}, t_end=1)}\n")
    status = cli.main(["characteristic", str(model), "--scene", "run"])
    out = capsys.readouterr().out
    mean = 20000.0 * 0.01 / (2 * math.pi)
    assert status == 0 and f"stable at {50 * (1 - mean / 100):.6g} rad/s, {mean:.6g} N*m" in out

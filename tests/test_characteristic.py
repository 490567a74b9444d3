"""Motor and load characteristics: operating points and their stability against closed
forms."""
import math
from pathlib import Path

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

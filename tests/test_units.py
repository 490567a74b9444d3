"""Units: values with units (to_si, --param), the dimension check of every element's
contribution, display units (rpm in and out)."""
import math
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

import mechdyn as md
from mechdyn import cli
from mechdyn.units import UnitError, convert, dimension, to_si

ROOT = Path(__file__).resolve().parents[1]
MODELS = sorted((ROOT / "models").glob("*.py"))


# ------------------------------------------------------------------------ to_si
def test_numbers_are_si_and_texts_convert_exactly():
    assert to_si(20, "N") == 20.0 and to_si(np.float64(2.5)) == 2.5
    assert to_si("0.02 kN", "N") == 20.0          # the float 20.0, not 20.000000000000004
    assert to_si("2.3 kN", "N") == 2300.0
    assert to_si("20 mm", "m") == 0.02 and to_si("20mm") == 0.02
    assert to_si("1500 rpm", "rad/s") == pytest.approx(50 * math.pi, rel=1e-15)
    assert to_si("90 deg", "rad") == pytest.approx(math.pi / 2, rel=1e-15)
    assert to_si("0.5 kg m^2", "kg*m^2") == 0.5
    assert to_si("9.81 m/s^2", "m/s^2") == 9.81
    assert to_si("1450 N*m/rad", "N*m/rad") == 1450.0
    assert to_si("2*pi/3 rad") == pytest.approx(2 * math.pi / 3)
    assert to_si("100/s", "rad/s") == 100.0
    assert to_si("3 t", "kg") == 3000.0            # metric tonnes


def test_pint_quantities_convert():
    ureg = md.units.registry()
    assert to_si(ureg.Quantity(2, "kN"), "N") == 2000.0
    with pytest.raises(UnitError, match="does not fit"):
        to_si(ureg.Quantity(2, "kg"), "N")


@pytest.mark.parametrize("text, unit, message", [
    ("2 kg", "N", "kg is a mass but N \\(a force\\) is expected"),
    ("3 kNm", "N*m", "read as kilonumber_meter"),
    ("25 Hz", "rad/s", "Hz counts cycles"),
    ("2 furlongs_per_fortnight", None, "unknown unit"),
    ("1 degC", None, "offset"),
    ("kN", "N", "expected a number before the unit"),
    ("12 kg m2", "kg*m^2", "a power is written with \\^: kg\\*m\\^2\\)"),
    ("3 mm3", None, "written with \\^: mm\\^3\\)"),
])
def test_wrong_units_are_named(text, unit, message):
    with pytest.raises(UnitError, match=message):
        to_si(text, unit)


@pytest.mark.parametrize("text", [
    "2 __import__('os').system('true')", "2 os.system", "2 m[0]", "2 lambda",
    "2 m; import os", "2 m^x", "2 m**(2**100)",
])
def test_unit_texts_are_never_evaluated(text):
    with pytest.raises(md.MechdynError):
        to_si(text)


def test_dimensions_of_units():
    assert dimension("kN*mm") == dimension("N*m") == dimension("J")
    assert dimension("rpm") == dimension("1/s")               # angles are dimensionless
    assert dimension("N*m/rad") == dimension("N*m")
    assert float(convert(1.5, "kW", "W")[0]) == 1500.0
    with pytest.raises(UnitError, match="cannot show"):
        convert(1.0, "N", "N*m")


# ----------------------------------------------------------- the command line
def _run(capsys, *argv):
    status = cli.main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return status, out, err


def test_param_with_a_unit_gives_exactly_the_si_result(capsys, tmp_path):
    brake = ROOT / "models" / "shoe_brake.py"
    plain, kilo = tmp_path / "plain.csv", tmp_path / "kilo.csv"
    status, out_plain, _ = _run(capsys, "simulate", brake, "--scene", "braking",
                                "--param", "P=20", "--csv", plain)
    assert status == 0
    status, out_kilo, _ = _run(capsys, "simulate", brake, "--scene", "braking",
                               "--param", "P=0.02 kN", "--csv", kilo)
    assert status == 0
    assert plain.read_text() == kilo.read_text()

    def summary(out):                    # without the timing and the file written
        return [line for line in out.splitlines()
                if not line.endswith(" ms") and not line.startswith("wrote")]
    assert summary(out_plain) == summary(out_kilo)


def test_param_with_a_wrong_unit_is_a_usage_error(capsys):
    status, _, err = _run(capsys, "simulate", ROOT / "models" / "shoe_brake.py", "--scene",
                          "braking", "--param", "P=20 N*m")
    assert status == 2
    assert "parameter P: '20 N*m'" in err and "N (a force) is expected" in err


def test_rpm_in_and_out(capsys):
    """omega_s = 1500 rpm is 50 pi rad/s; the summary in rpm shows speeds times 30/pi."""
    motor = ROOT / "models" / "motor_startup.py"
    model = md.load_model(motor)
    params = {**model.params, model.param_symbol("omega_s"): 50 * math.pi}
    result = model.mechanism.simulate(model.scenes["braking"], params)
    status, out, _ = _run(capsys, "simulate", motor, "--scene", "braking",
                          "--param", "omega_s=1500 rpm", "--units", "speed=rpm")
    assert status == 0
    peak_rpm = float(out.split("peak ")[1].split(" rpm")[0])
    assert peak_rpm == pytest.approx(result.y[1][0] * 30 / math.pi, rel=1e-5)
    status, _, err = _run(capsys, "simulate", motor, "--scene", "braking",
                          "--units", "speed=Hz")
    assert status == 2 and "Hz counts cycles" in err


def test_a_warm_run_imports_no_pint(tmp_path, share_kernels):
    """pint is imported when a unit is first met; its facts are cached, so `import
    mechdyn` and a second run of a model with units never import it."""
    share_kernels(tmp_path)
    env = {**os.environ, "MECHDYN_CACHE": str(tmp_path), "PYTHONPATH": str(ROOT)}
    script = ("import sys, mechdyn as md\n"
              "assert 'pint' not in sys.modules\n"
              "m = md.load_model(sys.argv[1])\n"
              "m.mechanism.simulate(m.scenes['braking'], m.params).summary()\n"
              "print('pint' in sys.modules)")
    model = str(ROOT / "models" / "shoe_brake.py")
    runs = [subprocess.run([sys.executable, "-c", script, model], env=env, check=True,
                           capture_output=True, text=True).stdout.strip() for _ in range(2)]
    assert runs == ["True", "False"]


# -------------------------------------------------------------- dimension checks
@pytest.mark.parametrize("path", MODELS, ids=[p.stem for p in MODELS])
def test_every_bundled_model_declares_units_and_passes(path):
    model = md.load_model(path)
    mech = model.mechanism
    used = set()
    for element in mech.elements.values():
        for expr in element.expressions().values():
            used |= {s.name for s in expr.free_symbols if s != md.t}
    assert used <= set(mech.parameter_units), used - set(mech.parameter_units)
    mech.check_dimensions()
    for scene in model.scenes.values():
        mech.check_dimensions(scene)


def _disc(units, moment):
    phi = md.coordinate("phi")
    disc = md.Mechanism("disc", [phi], units=units)
    disc.link("disc", J=sp.Symbol("J"), angle=phi)
    disc.load("drive", moment, along=phi)
    return disc


@pytest.mark.parametrize("model, name, unit, message", [
    ("scotch_yoke", "F_3", "N*m", "load 'resistance': value * d(along)/dphi has dimension "
     "kg*m^3/s^2 but the equation of phi needs N*m (a moment)"),
    ("shoe_brake", "P", "N*m", "friction 'shoe': moment * d(along)/dphi"),
    ("hoist_drive", "E_k", "N/m", "spring 'rope': k * stretch * d(stretch)/dphi has "
     "dimension N (a force) but the equation of phi needs N*m (a moment)"),
    ("hoist_drive", "d_r", "N*m*s", "damper 'rope damping'"),
    ("cam_follower", "m_2", "kg*m", "link 'follower': m = m_2 has dimension kg*m but a mass "
     "needs kg"),
    ("rope_hoist", "M_t", "N*m", "load 'motor': value = M_0 + M_t*t: adds M_t*t (N*m*s) to "
     "M_0 (N*m)"),
    ("motor_startup", "s_k", "rad/s", "load 'motor'"),
    ("press_flywheel", "l", "kg", "link 'ram': y = "),
])
def test_a_wrong_unit_names_the_element_and_both_dimensions(model, name, unit, message):
    loaded = md.load_model(ROOT / "models" / f"{model}.py")
    mech = loaded.mechanism
    mech.declare_units({loaded.param_symbol(name): unit})
    with pytest.raises(md.DeclarationError) as error:
        mech.check_dimensions()
    assert message in str(error.value)


def test_the_check_runs_when_equations_are_derived():
    J, F = sp.symbols("J F", positive=True)
    disc = _disc({J: "kg*m^2", F: "N"}, F)
    with pytest.raises(md.DeclarationError, match="load 'drive'.*needs N\\*m"):
        disc.equations()
    with pytest.raises(md.DeclarationError, match="load 'drive'"):
        disc.simulate(md.Scene("s", initial={disc.coordinates[0]: 0,
                                             md.speed(disc.coordinates[0]): 0}, t_end=1),
                      {J: 1, F: 1})
    assert _disc({J: "kg*m^2", F: "N*m"}, F).equations().dof == 1


def test_missing_units_are_listed():
    J, F = sp.symbols("J F", positive=True)
    with pytest.raises(md.DeclarationError, match="not for F;"):
        _disc({J: "kg*m^2"}, F).equations()
    assert _disc({}, F).equations().dof == 1          # no units: nothing is checked


def test_numbers_in_expressions():
    """Exact numbers are dimensionless; a decimal is an SI value of unknown unit."""
    J, F, r = sp.symbols("J F r", positive=True)
    phi = md.coordinate("phi")
    _disc({J: "kg*m^2", F: "N", r: "m"}, F * r / 2).check_dimensions()
    _disc({J: "kg*m^2", F: "N"}, 9.81 * F).check_dimensions()          # unchecked term
    with pytest.raises(md.DeclarationError, match="adds F \\(N\\*m\\) to 2 \\(dimensionless\\)"):
        _disc({J: "kg*m^2", F: "N*m"}, F + 2).check_dimensions()
    with pytest.raises(md.DeclarationError, match="sin takes a dimensionless argument"):
        _disc({J: "kg*m^2", F: "N*m", r: "m"}, F * sp.sin(r * phi)).check_dimensions()


def test_scene_stop_conditions_and_initial_values_are_checked():
    J, F, w = sp.symbols("J F omega", positive=True)
    disc = _disc({J: "kg*m^2", F: "N*m", w: "rad/s"}, F)
    phi = disc.coordinates[0]
    good = md.Scene("s", initial={phi: 0, md.speed(phi): w}, until=md.reaches(md.speed(phi), 2 * w))
    disc.check_dimensions(good)
    bad = md.Scene("s", initial={phi: w, md.speed(phi): 0}, until=md.reaches(phi, 1))
    with pytest.raises(md.SceneError, match="initial value of phi = omega"):
        disc.check_dimensions(bad)


def test_unit_declarations_are_checked_where_given():
    J = sp.Symbol("J")
    with pytest.raises(md.DeclarationError, match="unit of J"):
        _disc({J: "kg*m^"}, 1)
    with pytest.raises(md.DeclarationError, match="must be a text"):
        _disc({J: 2}, 1)


# ------------------------------------------------------------------ display units
def test_display_units_in_summary_csv_and_plot(tmp_path):
    model = md.load_model(ROOT / "models" / "motor_startup.py")
    result = model.mechanism.simulate(model.scenes["startup"], model.params)
    assert result.units == {"phi": "rad", "motor": "N*m", "power:motor": "W"}
    text = result.summary(units={"speed": "rpm", "power": "kW"})
    final_rpm = result.final(md.speed(model.mechanism.coordinates[0])) * 30 / math.pi
    assert f"speed final {final_rpm:.6g}" in text and " rpm" in text
    peak_time, peak_power = result.peak("power:motor")      # from the dense output
    assert peak_power >= np.max(np.abs(result["power:motor"]))   # at least the step points'
    power = next(line for line in text.splitlines() if "power:motor:" in line)
    assert power.startswith(f"  power:motor: peak {peak_power / 1000:.6g}, final ")
    assert power.endswith(" kW")                        # the unit once, after both
    assert re.search(r"\n  motor: peak 200, final [0-9.e+-]+ N\*m\n", text)
    path = tmp_path / "run.csv"
    result.to_csv(path, units="speed=rpm,motor=kN*m")
    header = path.read_text().splitlines()[0].split(",")
    assert header[:3] == ["t [s]", "phi [rad]", "phidot [rpm]"]
    assert "motor [kN*m]" in header and "power:motor [W]" in header
    with pytest.raises(md.MechdynError, match="neither a kind"):
        result.summary(units={"sped": "rpm"})


@pytest.mark.parametrize("text", ["3 Nm", "3 kNm", "3 Nm", "3 kNm"])   # twice: remembered
def test_newton_metres_written_nm_are_refused_not_read_as_a_length(text):
    # pint reads "Nm" as number_meter (a length, 1e-9 m): "3 Nm" was 3e-9 silently,
    # "3 kNm" 3e6 with no unit expected. An engineer writing Nm means N*m.
    with pytest.raises(md.UnitError, match="N\\*m"):
        md.to_si(text)
    with pytest.raises(md.UnitError, match="N\\*m"):
        md.to_si(text, "N*m")

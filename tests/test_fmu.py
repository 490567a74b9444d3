"""A scene as an FMI 2.0 Model Exchange FMU, run by FMPy (a real FMI client that is not
mechdyn): its trajectory agrees with mechdyn's run, its model description validates, a
PI controller closed around it in FMPy reaches its set point as the closed form says,
and what cannot be exported is refused by name, leaving no file behind."""
import ctypes
import glob
import math
import re
import shutil
import zipfile
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

import mechdyn as md
from mechdyn import cli
from mechdyn.declare.elements import Constraint
from mechdyn.report.fmu import FmuCompilerError, FmuError, export_fmu

fmpy = pytest.importorskip("fmpy", reason="the FMU tests need FMPy: pip install '.[fmu]'")
from fmpy.validation import validate_fmu  # noqa: E402

if not any(shutil.which(c) for c in ("cc", "gcc", "clang")):
    pytest.skip("exporting an FMU needs a C compiler (cc, gcc or clang)",
                allow_module_level=True)

ROOT = Path(__file__).resolve().parents[1]
RTOL = 1e-6


def model(name):
    return md.load_model(str(ROOT / "models" / f"{name}.py"))


def states_of(path):
    """The names of the FMU's continuous states, in order."""
    description = fmpy.read_model_description(str(path))
    return [unknown.variable.derivative.name for unknown in description.derivatives]


def fmpy_final(path, scene, start_values=None):
    """FMPy's CVode run of the FMU at a tight tolerance: (end time, final state)."""
    names = states_of(path)
    result = fmpy.simulate_fmu(str(path), relative_tolerance=1e-12, output=names,
                               stop_time=scene.time_limit, start_values=start_values or {})
    return result["time"][-1], np.array([result[n][-1] for n in names])


def assert_agrees(path, mechanism, scene, params, start=None):
    t_end, final = fmpy_final(path, scene)
    reference = mechanism.simulate(scene, params, start=start)
    expected = reference.y[:, -1]
    assert t_end == pytest.approx(reference.t_end, rel=RTOL)
    scale = np.maximum(np.abs(expected), 1.0)      # relative, speeds near zero absolute
    assert np.all(np.abs(final - expected) <= RTOL * scale), (final, expected)


@pytest.fixture(scope="module")
def exported(tmp_path_factory):
    """FMUs built once for this module: name -> (path, model, scene)."""
    folder = tmp_path_factory.mktemp("fmus")
    built = {}
    for model_name, scene_name in (("motor_startup", "startup"), ("hoist_drive", "lift_start"),
                                   ("two_mass_drive", "start")):
        m = model(model_name)
        path = folder / f"{model_name}_{scene_name}.fmu"
        export_fmu(m.mechanism, m.scenes[scene_name], m.params, path)
        built[model_name] = (path, m, m.scenes[scene_name])
    return built


# ------------------------------------------------------------ FMPy agrees with mechdyn
@pytest.mark.parametrize("name", ["motor_startup", "hoist_drive", "two_mass_drive"])
def test_fmpy_runs_the_exported_scene_to_mechdyns_final_state(exported, name):
    # motor_startup ends on a stop condition (an event indicator terminating the run),
    # hoist_drive switches a lossy efficiency by the direction of power flow starting
    # from rest, two_mass_drive has two coordinates (the Cholesky solve in C)
    path, m, scene = exported[name]
    assert_agrees(path, m.mechanism, scene, m.params)


def test_the_stop_condition_ends_fmpys_run_where_the_closed_form_says(exported):
    # motor_startup stops at 95 % of the steady speed omega_s (1 - s), s the stable slip
    path, m, scene = exported["motor_startup"]
    _, final = fmpy_final(path, scene)
    values = {str(k): v for k, v in m.params.items()}
    M_k, s_k, M_L, omega_s = (values[n] for n in ("M_k", "s_k", "M_L", "omega_s"))
    steady = omega_s * (1 - s_k * (M_k - math.sqrt(M_k ** 2 - M_L ** 2)) / M_L)
    assert final[1] == pytest.approx(0.95 * steady, rel=1e-9)


def test_a_parameter_set_in_fmpy_changes_the_run_as_it_changes_mechdyns(exported):
    # a heavier load M_L = 100 N m: slower start-up, an earlier stop (lower steady speed)
    path, m, scene = exported["motor_startup"]
    names = states_of(path)
    result = fmpy.simulate_fmu(str(path), relative_tolerance=1e-12, output=names,
                               start_values={"M_L": 100.0})
    params = {k: v for k, v in m.params.items() if str(k) != "M_L"} | {"M_L": 100.0}
    reference = m.mechanism.simulate(scene, params)
    assert result["time"][-1] == pytest.approx(reference.t_end, rel=RTOL)
    assert result["time"][-1] != pytest.approx(fmpy_final(path, scene)[0], rel=1e-3)
    for i, name in enumerate(names):
        assert result[name][-1] == pytest.approx(reference.y[i, -1], rel=RTOL)


def test_the_model_description_validates_with_units_starts_and_sources(exported):
    path, m, scene = exported["motor_startup"]
    assert validate_fmu(str(path)) == []
    description = fmpy.read_model_description(str(path), validate=True)
    variables = {v.name: v for v in description.modelVariables}
    units = {u.name: u.baseUnit for u in description.unitDefinitions}
    assert variables["J_m"].causality == "parameter"
    assert float(variables["J_m"].start) == 0.5 and variables["J_m"].unit == "kg.m2"
    assert (units["kg.m2"].kg, units["kg.m2"].m, units["kg.m2"].s) == (1, 2, 0)
    assert variables["phi"].unit == "rad" and variables["phidot"].unit == "rad/s"
    assert variables["der(phidot)"].unit == "rad/s2"
    assert "load 'motor'" in variables["M_k"].description
    assert [v.causality for v in (variables["motor"], variables["power:motor"],
                                  variables["energy"])] == ["output"] * 3
    assert variables["motor"].unit == "N.m" and variables["power:motor"].unit == "W"
    assert description.numberOfEventIndicators == 1
    assert float(description.defaultExperiment.tolerance) == scene.rtol
    names = zipfile.ZipFile(path).namelist()
    assert {"sources/model.c", "sources/fmi2_glue.c", "sources/fmi2_header.h"} <= set(names)
    assert any(n.startswith("binaries/") for n in names)


def test_the_energy_outputs_hold_the_kinetic_energy_of_the_final_speed(exported):
    # two_mass_drive: T = (J_1 omega_1^2 + J_2 omega_2^2)/2 from the final state
    path, m, scene = exported["two_mass_drive"]
    names = states_of(path)
    result = fmpy.simulate_fmu(str(path), relative_tolerance=1e-10, stop_time=scene.t_end,
                               output=names + ["kinetic_energy", "potential_energy", "energy"])
    values = {str(k): v for k, v in m.params.items()}
    speeds = [result[n][-1] for n in names[len(names) // 2:]]
    inertias = [values[n] for n in ("J_1", "J_2")]
    kinetic = sum(J * w ** 2 for J, w in zip(inertias, speeds)) / 2
    assert result["kinetic_energy"][-1] == pytest.approx(kinetic, rel=1e-12)
    assert result["energy"][-1] == pytest.approx(
        result["kinetic_energy"][-1] + result["potential_energy"][-1], rel=1e-12)


# ------------------------------------------------------------------ inputs: a PI loop
M_CTRL, K_P, K_I, W_SET = sp.symbols("M_ctrl K_p K_i w_s")


def drive(motor):
    """A flywheel J with bearing damping c against a constant load M_L, driven by the
    moment ``motor(phi)``."""
    phi = md.coordinate("phi")
    J, c, M_L = sp.symbols("J c M_L", positive=True)
    mechanism = md.Mechanism("Flywheel drive", [phi], units={
        J: "kg*m^2", c: "N*m*s", M_L: "N*m", M_CTRL: "N*m", K_P: "N*m*s", K_I: "N*m",
        W_SET: "1/s"})
    mechanism.link("flywheel", J=J, angle=phi)
    mechanism.damper("bearing", c, stretch=phi)
    mechanism.load("load", -M_L, along=phi)
    mechanism.load("motor", motor(phi), along=phi)
    scene = md.Scene("run", initial={phi: 0, md.speed(phi): 0}, t_end=5)
    return mechanism, scene, {J: 2.0, c: 0.5, M_L: 20.0}


KP, KI, SET = 20.0, 50.0, 100.0           # N m s, N m, rad/s


def closed_form(t):
    """J phi'' + (c + Kp) phi' + Ki phi = Kp w + Ki w t - M_L from rest: characteristic
    roots -4 and -6.25 (2 s^2 + 20.5 s + 50), particular solution w t + B."""
    B = (-0.5 * SET - 20.0) / KI
    C2 = (SET - 4 * -B) / (6.25 - 4)          # C1 + C2 = -B, 4 C1 + 6.25 C2 = w
    C1 = -B - C2
    phi = SET * t + B + C1 * np.exp(-4 * t) + C2 * np.exp(-6.25 * t)
    omega = SET - 4 * C1 * np.exp(-4 * t) - 6.25 * C2 * np.exp(-6.25 * t)
    return phi, omega


def instantiated(path):
    """The FMU loaded by FMPy, initialised and in continuous-time mode."""
    from fmpy.fmi2 import FMU2Model
    description = fmpy.read_model_description(str(path))
    unpacked = fmpy.extract(str(path), unzipdir=str(path.with_suffix("")))
    fmu = FMU2Model(guid=description.guid, unzipDirectory=unpacked,
                    modelIdentifier=description.modelExchange.modelIdentifier)
    fmu.instantiate()
    fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    fmu.newDiscreteStates()
    fmu.enterContinuousTimeMode()
    return fmu


def test_a_pi_speed_controller_around_the_fmu_reaches_its_set_point(tmp_path):
    from scipy.integrate import solve_ivp
    mechanism, scene, params = drive(lambda phi: M_CTRL)
    path = tmp_path / "flywheel.fmu"
    mechanism.export_fmu(scene, {**params, M_CTRL: 0.0}, path, inputs=["motor"])
    description = fmpy.read_model_description(str(path))
    assert {v.name: v.causality for v in description.modelVariables}["M_ctrl"] == "input"
    assert validate_fmu(str(path)) == []
    fmu = instantiated(path)
    moment = [v.valueReference for v in description.modelVariables if v.name == "M_ctrl"]

    def loop(t, y):                           # y = [phi, omega, integral of the error]
        error = SET - y[1]
        fmu.setReal(moment, [KP * error + KI * y[2]])
        fmu.setTime(t)
        fmu.setContinuousStates((ctypes.c_double * 2)(*y[:2]), 2)
        dx = (ctypes.c_double * 2)()
        fmu.getDerivatives(dx, 2)
        return [dx[0], dx[1], error]
    run = solve_ivp(loop, (0, 5), [0, 0, 0], method="DOP853", rtol=1e-12, atol=1e-12)
    fmu.terminate()
    fmu.freeInstance()
    phi, omega = closed_form(5.0)
    assert run.y[1, -1] == pytest.approx(omega, rel=1e-9) and omega == pytest.approx(SET)
    assert run.y[0, -1] == pytest.approx(phi, rel=1e-9)
    # the controller's steady moment carries the load and the bearing: M_L + c w
    assert KP * (SET - run.y[1, -1]) + KI * run.y[2, -1] == pytest.approx(70.0, rel=1e-6)
    # the same loop in mechdyn: the PI moment in closed form, the error's integral
    # being w t - phi from rest
    pi, _, _ = drive(lambda p: K_P * (W_SET - md.speed(p)) + K_I * (W_SET * md.t - p))
    result = pi.simulate(scene, {**params, K_P: KP, K_I: KI, W_SET: SET})
    assert result.y[1, -1] == pytest.approx(run.y[1, -1], rel=RTOL)
    assert result.y[0, -1] == pytest.approx(run.y[0, -1], rel=RTOL)


def test_an_input_must_be_a_parameter_or_a_load_of_one(tmp_path):
    mechanism, scene, params = drive(lambda phi: 2 * M_CTRL)
    with pytest.raises(FmuError, match="input 'motor': the load's value 2\\*M_ctrl"):
        mechanism.export_fmu(scene, {**params, M_CTRL: 0}, tmp_path / "x.fmu",
                             inputs=["motor"])
    with pytest.raises(FmuError, match="input 'torque': not a parameter"):
        mechanism.export_fmu(scene, {**params, M_CTRL: 0}, tmp_path / "x.fmu",
                             inputs=["torque"])
    assert list(tmp_path.iterdir()) == []


# ------------------------------------------------------------- refusals and bad input
@pytest.mark.parametrize("model_name, scene_name, culprit", [
    ("shoe_brake", "braking", "friction 'shoe'"),
    ("hard_stop", "bounce", "stop 'end stop'"),
    ("fourbar_flywheel", "startup", "closed loop 'ABCD'"),
    ("freewheel", "ride", "one-way clutch 'freewheel'"),
])
def test_switching_elements_and_loops_are_refused_by_name(capsys, tmp_path, model_name,
                                                          scene_name, culprit):
    out = tmp_path / "x.fmu"
    status = cli.main(["fmu", str(ROOT / "models" / f"{model_name}.py"), "--scene",
                       scene_name, "--out", str(out)])
    err = capsys.readouterr().err
    assert status == 2 and culprit in err and "cannot be exported as an FMU" in err
    assert list(tmp_path.iterdir()) == []


def test_bad_input_is_a_named_error_with_exit_status_2_and_no_file(capsys, tmp_path):
    out = tmp_path / "x.fmu"
    motor = str(ROOT / "models" / "motor_startup.py")
    for argv, message in (
            (["--scene", "nope"], "no scene 'nope'"),
            (["--scene", "startup", "--input", "M_ctrl"], "input 'M_ctrl': not a parameter"),
            (["--scene", "startup", "--param", "M_k=x"], "parameter M_k")):
        status = cli.main(["fmu", motor, "--out", str(out), *argv])
        assert status == 2 and message in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


def test_a_parameter_without_a_value_is_named(tmp_path):
    m = model("motor_startup")
    params = {k: v for k, v in m.params.items() if str(k) != "M_L"}
    with pytest.raises(md.MechdynError, match="M_L"):
        export_fmu(m.mechanism, m.scenes["startup"], params, tmp_path / "x.fmu")
    assert list(tmp_path.iterdir()) == []


def test_an_output_without_a_c_form_or_with_a_taken_name_is_refused(tmp_path):
    mechanism, scene, params = drive(lambda phi: M_CTRL)
    phi = mechanism.coordinates[0]
    odd = md.Scene("odd", initial=scene.initial, t_end=1,
                   outputs={"bessel": sp.besselj(0, phi)})
    with pytest.raises(FmuError, match="output 'bessel'.*no C form"):
        export_fmu(mechanism, odd, {**params, M_CTRL: 1}, tmp_path / "x.fmu")
    taken = md.Scene("taken", initial=scene.initial, t_end=1, outputs={"phi": 2 * phi})
    with pytest.raises(FmuError, match="output 'phi' has the name of a state"):
        export_fmu(mechanism, taken, {**params, M_CTRL: 1}, tmp_path / "x.fmu")
    assert list(tmp_path.iterdir()) == []


def test_without_a_c_compiler_the_command_says_so(capsys, tmp_path, monkeypatch):
    monkeypatch.setenv("PATH", str(tmp_path))         # no cc, gcc or clang there
    monkeypatch.delenv("CC", raising=False)
    status = cli.main(["fmu", str(ROOT / "models" / "gear_pair.py"), "--scene", "startup",
                       "--out", str(tmp_path / "x.fmu")])
    assert status == 2 and "needs a C compiler" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


def test_a_failing_build_leaves_no_file_behind(tmp_path, monkeypatch):
    monkeypatch.setenv("CC", shutil.which("false") or "false")
    m = model("gear_pair")
    with pytest.raises(FmuCompilerError, match="the C compiler"):
        export_fmu(m.mechanism, m.scenes["startup"], m.params, tmp_path / "x.fmu")
    assert list(tmp_path.iterdir()) == []


# --------------------------------------------------------------- every bundled scene
def bundled_scenes():
    for path in sorted(glob.glob(str(ROOT / "models" / "*.py"))):
        for name in md.load_model(path).scenes:
            yield Path(path).stem, name


@pytest.mark.slow
@pytest.mark.parametrize("model_name, scene_name", list(bundled_scenes()))
def test_every_bundled_scene_exports_and_agrees_with_mechdyn_or_is_refused_by_name(
        tmp_path, model_name, scene_name):
    m = model(model_name)
    scene = m.scenes[scene_name]
    eqs = m.mechanism.equations(scene)
    start = None
    if not scene.initial:          # a later phase: it starts where the first scene ends
        first = next(iter(m.scenes.values()))
        start = m.mechanism.simulate(first, m.params).y[:, -1]
    path = tmp_path / "scene.fmu"
    switching = eqs.switching or eqs.constraints
    if switching:
        with pytest.raises(FmuError, match="cannot be exported as an FMU yet") as refusal:
            export_fmu(m.mechanism, scene, m.params, path, start=start)
        named = list(eqs.switching) or [name for name, e in m.mechanism.elements.items()
                                        if isinstance(e, Constraint)]
        assert any(repr(name) in str(refusal.value) for name in named)
        assert not path.exists()
        return
    export_fmu(m.mechanism, scene, m.params, path, start=start)
    assert validate_fmu(str(path)) == []
    assert_agrees(path, m.mechanism, scene, m.params, start=start)


def test_derivatives_without_a_real_value_are_an_fmi_error_not_nan(tmp_path):
    # a push sqrt(1 - phi) + 1 on a disc J = 1 has no real value beyond phi = 1
    from fmpy.fmi1 import FMICallException
    phi = md.coordinate("phi")
    disc = md.Mechanism("disc", [phi])
    disc.link("disc", J=1, angle=phi)
    disc.load("push", sp.sqrt(1 - phi) + 1, along=phi)
    path = tmp_path / "disc.fmu"
    disc.export_fmu(md.Scene("run", initial={phi: 0, md.speed(phi): 0}, t_end=3), {}, path)
    fmu = instantiated(path)
    dx = (ctypes.c_double * 2)()
    fmu.setContinuousStates((ctypes.c_double * 2)(0.5, 3.0), 2)
    fmu.getDerivatives(dx, 2)
    assert list(dx) == [3.0, pytest.approx(math.sqrt(0.5) + 1, rel=1e-15)]
    fmu.setContinuousStates((ctypes.c_double * 2)(2.0, 3.0), 2)
    with pytest.raises(FMICallException, match="fmi2GetDerivatives"):
        fmu.getDerivatives(dx, 2)
    fmu.freeInstance()


def test_a_switch_that_chatters_stops_fmpys_run_with_an_error(tmp_path):
    # a drag 3 sign(omega) against a drive of 1 holds the disc once it stops at t = 1 s:
    # sign flips at every event in that instant (mechdyn's own run exceeds its budget)
    from fmpy.fmi1 import FMICallException
    phi = md.coordinate("phi")
    disc = md.Mechanism("disc", [phi])
    disc.link("disc", J=1, angle=phi)
    disc.load("drive", 1, along=phi)
    disc.load("drag", -3 * sp.sign(md.speed(phi)), along=phi)
    path = tmp_path / "disc.fmu"
    disc.export_fmu(md.Scene("run", initial={phi: 0, md.speed(phi): 2}, t_end=3), {}, path)
    with pytest.raises(FMICallException, match="fmi2NewDiscreteStates"):
        fmpy.simulate_fmu(str(path), relative_tolerance=1e-10)


@pytest.mark.slow
def test_fmpy_builds_the_binary_from_the_fmus_sources_alone(exported, tmp_path):
    # another platform builds the FMU from sources/: FMPy's own CMake build
    if not shutil.which("cmake"):
        pytest.skip("FMPy's build from sources needs cmake")
    from fmpy.build import build_platform_binary
    path, m, scene = exported["two_mass_drive"]
    unpacked = Path(fmpy.extract(str(path), unzipdir=str(tmp_path / "unpacked")))
    shutil.rmtree(unpacked / "binaries")
    (tmp_path / "build").mkdir()
    build_platform_binary(unpacked, build_dir=tmp_path / "build")
    assert_agrees(unpacked, m.mechanism, scene, m.params)


# ------------------------------------------- issue 37: start on a switch, derived values
@pytest.mark.parametrize("push", [1.0, -1.0])
def test_a_run_from_rest_on_a_switching_surface_takes_the_side_the_acceleration_gives(
        tmp_path, push):
    """A disc J = 1 at rest at phi = 0, a push F, a one-sided spring -k Max(phi, 0),
    k = 100: pushed forward the spring acts from the start, phi = F/k (1 - cos 10 t);
    pushed back it never acts, phi = F t^2 / 2 (the speed is zero at the start, so only
    the acceleration tells the side)."""
    phi = md.coordinate("phi")
    F, k = sp.symbols("F k")
    disc = md.Mechanism("disc", [phi])
    disc.link("disc", J=1, angle=phi)
    disc.load("push", F, along=phi)
    disc.load("spring", -k * sp.Max(phi, 0), along=phi)
    scene = md.Scene("rest", initial={phi: 0, md.speed(phi): 0}, t_end=2.0)
    path = tmp_path / "disc.fmu"
    disc.export_fmu(scene, {F: push, k: 100.0}, path)
    result = fmpy.simulate_fmu(str(path), relative_tolerance=1e-10, output=["phi"])
    expected = push / 100 * (1 - math.cos(20.0)) if push > 0 else push * 2.0 ** 2 / 2
    assert result["phi"][-1] == pytest.approx(expected, rel=1e-5)
    assert disc.simulate(scene, {F: push, k: 100.0}).final(phi) == pytest.approx(
        expected, rel=1e-6)


@pytest.mark.parametrize("loads", [
    lambda phi, t: [-100 * sp.Max(phi, 0), 2 * sp.Heaviside(phi) + 1],
    lambda phi, t: [-100 * sp.Max(phi, 0), sp.Piecewise((3, (t > 0.5) & (t < 1)), (1, True))],
    lambda phi, t: [-100 * sp.Max(phi, 0), 1 - 2 * sp.Heaviside(-phi)],  # both sides hold
    lambda phi, t: [-50 * sp.Abs(phi), sp.Heaviside(t - 0.2) - 0.5]])
def test_mixed_switches_from_rest_on_their_surface_agree_with_mechdyns_driver(tmp_path,
                                                                              loads):
    # Max, Heaviside, Abs and a time pulse, all zero at the start at rest (the old glue
    # was off by 0.03 to 2000 here); where both sides would hold (the third), the
    # driver's side
    phi = md.coordinate("phi")
    disc = md.Mechanism("disc", [phi])
    disc.link("disc", J=1, angle=phi)
    for index, value in enumerate(loads(phi, md.t)):
        disc.load(f"load {index}", value, along=phi)
    scene = md.Scene("rest", initial={phi: 0, md.speed(phi): 0}, t_end=2.0)
    path = tmp_path / "disc.fmu"
    disc.export_fmu(scene, {}, path)
    result = fmpy.simulate_fmu(str(path), relative_tolerance=1e-10, output=["phi"])
    expected = disc.simulate(scene, {}).final(phi)
    assert result["phi"][-1] == pytest.approx(expected, rel=1e-6, abs=1e-9)


def test_a_parameter_given_as_an_expression_is_calculated_in_the_fmu(tmp_path):
    """Q = 2 k: a disc J = 1 with a spring k and a load -Q phi swings at omega =
    sqrt(3 k); setting k = 9 in FMPy gives cos(sqrt(27)) at t = 1, as mechdyn does with
    k = 9, and Q is a calculated parameter that cannot be set."""
    from fmpy.fmi1 import FMICallException
    phi = md.coordinate("phi")
    J, k, Q = sp.symbols("J k Q", positive=True)
    disc = md.Mechanism("disc", [phi])
    disc.link("disc", J=J, angle=phi)
    disc.spring("spring", k, phi)
    disc.load("extra", -Q * phi, along=phi)
    scene = md.Scene("swing", initial={phi: 1, md.speed(phi): 0}, t_end=1.0)
    path = tmp_path / "disc.fmu"
    disc.export_fmu(scene, {J: 1.0, k: 1.0, Q: 2 * k}, path)
    assert validate_fmu(str(path)) == []
    variables = {v.name: v for v in fmpy.read_model_description(str(path)).modelVariables}
    assert variables["Q"].causality == "calculatedParameter"
    assert variables["k"].causality == "parameter"
    result = fmpy.simulate_fmu(str(path), relative_tolerance=1e-12, output=["phi", "Q"],
                               start_values={"k": 9.0})
    assert result["phi"][-1] == pytest.approx(math.cos(math.sqrt(27.0)), abs=1e-7)
    assert result["Q"][-1] == 18.0
    mechdyn_run = disc.simulate(scene, {J: 1.0, k: 9.0, Q: 2 * k}).final(phi)
    assert result["phi"][-1] == pytest.approx(mechdyn_run, abs=1e-7)
    # refused by the FMU's fmi2SetReal (FMICallException) or, in FMPy 0.3.4, before it by
    # FMPy's check of the description's initial="calculated" (a plain Exception)
    with pytest.raises(Exception, match='fmi2SetReal|"Q" has inital=calculated') as refused:
        fmpy.simulate_fmu(str(path), start_values={"Q": 5.0})
    assert isinstance(refused.value, FMICallException) or "fmi2SetReal" not in str(refused.value)
    with pytest.raises(FmuError, match="input 'Q': parameter Q is given as 2\\*k"):
        disc.export_fmu(scene, {J: 1.0, k: 1.0, Q: 2 * k}, tmp_path / "in.fmu",
                        inputs=["Q"])


@pytest.mark.parametrize("label", ["time", "der(phi)"])
def test_an_output_may_not_take_a_name_fmi_reserves(tmp_path, label):
    # FMPy's result keeps the time under "time": an output of that name was lost
    mechanism, scene, params = drive(lambda phi: M_CTRL)
    phi = mechanism.coordinates[0]
    odd = md.Scene("odd", initial=scene.initial, t_end=1, outputs={label: 2 * phi})
    with pytest.raises(FmuError, match=rf"output '{re.escape(label)}' takes a name FMI tools "
                                       "reserve"):
        export_fmu(mechanism, odd, {**params, M_CTRL: 1}, tmp_path / "x.fmu")
    assert list(tmp_path.iterdir()) == []

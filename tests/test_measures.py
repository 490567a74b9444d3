"""Named measures (md.measure) against closed forms and independent integrations, and
sweeps of them equal to loops over simulate / steady_running, bit for bit."""
import dataclasses
import json
import math
from pathlib import Path

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import quad, solve_ivp

import mechdyn as md
from mechdyn import cli

ROOT = Path(__file__).resolve().parents[1]
PRESS = ROOT / "models" / "press_flywheel.py"
BRAKE = ROOT / "models" / "shoe_brake.py"


# ---------------------------------------------------------------- small machines
def spinning_disc(J=2.0, M=3.0, A=5.0):
    """A disc under a constant moment M recording the moment, its power and A sin(phi)."""
    phi = md.coordinate("phi")
    disc = md.Mechanism("spinning disc", [phi])
    disc.link("disc", J=J, angle=phi)
    disc.load("drive", M, along=phi)
    return disc, phi, {"wave": A * sp.sin(phi), "power": "power:drive", "drive": "drive"}


def shunt_machine():
    """The steady-running example: J w w' = 400 (1 - w/110) + 20 cos(phi)."""
    phi = md.coordinate("phi")
    J = sp.Symbol("J", positive=True)
    machine = md.Mechanism("machine", [phi])
    machine.link("crank and flywheel", J=J, angle=phi)
    machine.load("motor", md.motors.dc_shunt(400, 110)(md.speed(phi)), along=phi)
    machine.load("process", 20 * sp.cos(phi), along=phi)
    scene = md.Scene("run", initial={phi: 0, md.speed(phi): 100}, t_end=1,
                     outputs=["process", "power:process", "power:motor"])
    return machine, scene, {J: 2}


@pytest.fixture(scope="module")
def press():
    model = md.load_model(PRESS)
    scene = dataclasses.replace(model.scenes["steady"], outputs=(
        "motor", "workpiece", "power:motor", "power:workpiece"))
    return model, scene, {str(k): v for k, v in model.params.items()}


# ---------------------------------------------------------------- of a run
def test_energy_of_a_constant_moment_over_a_run_is_the_moment_times_the_angle():
    """W = M * angle; the angle from phi = w0 t + M t^2 / (2 J)."""
    disc, phi, outputs = spinning_disc(J=2.0, M=3.0)
    res = disc.simulate(md.Scene("run", initial={phi: 0.5, md.speed(phi): 1.5}, t_end=2.5,
                                 outputs=outputs), {})
    angle = 1.5 * 2.5 + 3.0 * 2.5 ** 2 / (2 * 2.0)
    assert md.measure("energy:drive")(res) == pytest.approx(3.0 * angle, rel=1e-10)
    assert md.measure("final:phi")(res) == res.final(phi) == pytest.approx(0.5 + angle,
                                                                             rel=1e-12)
    assert md.measure("t_end")(res) == 2.5


def test_rms_and_peak_of_a_sinusoid_over_whole_turns():
    """A free disc at w turns uniformly: A sin(phi) over 3 whole turns has the RMS
    A / sqrt(2) and the peak magnitude A."""
    disc, phi, outputs = spinning_disc(M=0.0, A=5.0)
    w = 4.0
    res = disc.simulate(md.Scene("turns", initial={phi: 0.3, md.speed(phi): w},
                                 t_end=3 * 2 * math.pi / w, outputs=outputs), {})
    assert md.measure("rms:wave")(res) == pytest.approx(5.0 / math.sqrt(2), rel=1e-9)
    assert abs(md.measure("peak:wave")(res)) == pytest.approx(5.0, rel=1e-10)
    assert md.measure("energy:drive")(res) == 0.0


def test_stop_angle_and_time_of_the_shoe_brake_are_the_closed_form():
    """omega_0 = 100, eps = 2 f P R / I = 2 rad/s^2: t = 50 s, angle 2500 rad."""
    brake = md.load_model(BRAKE)
    res = brake.mechanism.simulate(brake.scenes["braking"], brake.params)
    assert md.measure("stop_angle")(res) == pytest.approx(2500.0, rel=1e-10)
    assert md.measure("stop_angle:phi")(res) == md.measure("stop_angle")(res)
    assert md.measure("t_end")(res) == pytest.approx(50.0, rel=1e-10)
    timed = dataclasses.replace(brake.scenes["braking"], until=(), t_end=10, backend="scipy")
    with pytest.raises(md.MeasureError, match="did not stop at a stop condition"):
        md.measure("stop_angle")(brake.mechanism.simulate(timed, brake.params))


# ---------------------------------------------------------------- of a steady cycle
def test_per_cycle_measures_match_an_independent_integration_in_time():
    """From the periodic state, integrate the time equation J w' = M(w) + 20 cos(phi)
    over one cycle time with scipy, carrying the integrals of f^2 and of the powers:
    the peak of 20 cos(phi) is 20 (at phi = 0), its RMS and the energies per cycle
    (the process's: integral of 20 cos dphi = 0)."""
    machine, scene, params = shunt_machine()
    running = md.steady_running(machine, scene, params)
    phi0, w0 = running.initial

    def f(t, z):
        phi, w = z[0], z[1]
        motor, process = 400 * (1 - w / 110), 20 * math.cos(phi)
        return [w, (motor + process) / 2, process ** 2, process * w, motor * w]
    ref = solve_ivp(f, (0, running.cycle_time), [phi0, w0, 0, 0, 0], method="DOP853",
                    rtol=1e-12, atol=1e-12).y[:, -1]
    assert ref[0] == pytest.approx(phi0 + 2 * math.pi, rel=1e-9)
    assert md.measure("peak:process")(running) == pytest.approx(20.0, rel=1e-12)
    assert md.measure("rms:process")(running) == pytest.approx(
        math.sqrt(ref[2] / running.cycle_time), rel=1e-8)
    assert md.measure("energy:process")(running) == pytest.approx(ref[3], abs=1e-8)
    assert md.measure("energy:motor")(running) == pytest.approx(ref[4], abs=1e-8)
    assert md.measure("mean_speed")(running) == running.omega_mean == pytest.approx(
        2 * math.pi / running.cycle_time)
    assert md.measure("fluctuation")(md.flywheel(machine, scene, params, 0.01, "J")) == \
        pytest.approx(0.01, rel=1e-6)


def test_the_press_does_the_work_of_the_pulse_per_stroke(press):
    """The workpiece takes integral F(phi) s'(phi) dphi per cycle whatever the speed
    (quad of the closed form), and the motor gives it (gravity stores, returns)."""
    model, scene, p = press
    running = md.steady_running(model.mechanism, scene, p)
    r, l, F, phi_w, beta = 0.05, 0.25, 60e3, 5 * math.pi / 6, math.pi / 6

    def taken(phi):
        ds = r * math.sin(phi) + r * r * math.sin(phi) * math.cos(phi) / math.sqrt(
            l * l - r * r * math.sin(phi) ** 2)
        pulse = (math.cos(phi - phi_w) - math.cos(beta)) / (1 - math.cos(beta))
        return F * max(pulse, 0.0) * ds
    work, _ = quad(taken, phi_w - beta, phi_w + beta, epsabs=1e-10, epsrel=1e-12)
    assert md.measure("energy:workpiece")(running) == pytest.approx(-work, rel=1e-7)
    assert md.measure("energy:motor")(running) == pytest.approx(work, rel=1e-7)


# ---------------------------------------------------------------- refused by name
@pytest.mark.parametrize("spec, words", [
    ("fluctuaton", "unknown measure 'fluctuaton' (did you mean fluctuation?); measures: "
                   "mean_speed, fluctuation"),
    ("peek:motor", "did you mean peak?"),
    ("rms", "needs an argument: rms:OUTPUT"),
    ("t_end:phi", "takes no argument"),
    (3.5, "a measure is a name"),
    (lambda result: 1.0, "give the measure"),
])
def test_bad_measures_are_refused_by_name(spec, words):
    with pytest.raises(md.MeasureError) as refused:
        md.measure(spec)
    assert words in str(refused.value)


def test_a_measure_of_the_wrong_outcome_or_output_says_what_to_do():
    machine, scene, params = shunt_machine()
    running = md.steady_running(machine, scene, params)
    with pytest.raises(md.MeasureError, match="t_end is a measure of a run"):
        md.measure("t_end")(running)
    with pytest.raises(md.MeasureError, match=r"no output 'proces' \(did you mean process"):
        md.measure("peak:proces")(running)
    plain = dataclasses.replace(scene, outputs=("process",))
    with pytest.raises(md.MeasureError, match="add 'power:motor' to its outputs"):
        md.measure("energy:motor")(md.steady_running(machine, plain, params))
    disc, phi, outputs = spinning_disc()
    res = disc.simulate(md.Scene("run", initial={phi: 0, md.speed(phi): 1}, t_end=1,
                                 outputs=outputs), {})
    with pytest.raises(md.MeasureError, match="fluctuation is a measure of steady running"):
        md.measure("fluctuation")(res)
    with pytest.raises(md.MeasureError, match="did you mean phidot"):
        md.measure("final:phidt")(res)


# ---------------------------------------------------------------- sweeps
def cycles(result):
    """A user's measure: turns of the crank over the run."""
    return result.final("phi") / (2 * math.pi)


def test_a_steady_sweep_equals_a_loop_over_steady_running_exactly(press, tmp_path):
    model, scene, p = press
    names = ["fluctuation", "mean_speed", "peak:motor", "rms:motor", "energy:motor"]
    out = tmp_path / "press.csv"
    table = md.sweep(model.mechanism, scene, p, {"J_f": [0.75, 3.0]}, workers=1,
                     out=out, progress=False, measures=names)
    assert table.columns == ["J_f", *names, "error"] and table.default_y == "fluctuation"
    for row in table.rows:
        running = md.steady_running(model.mechanism, scene, {**p, "J_f": row["J_f"]})
        assert [row[n] for n in names] == [md.measure(n)(running) for n in names]
        assert row["error"] == ""
    record = json.loads(Path(f"{out}.meta.json").read_text())
    assert record["measures"] == names and record["outcome"].startswith("steady running")
    assert table.units["mean_speed"] == "rad/s" and table.units["peak:motor"] == "N*m"


def test_a_run_sweep_equals_a_loop_over_simulate_exactly_with_a_users_measure(tmp_path):
    brake = md.load_model(BRAKE)
    scene = brake.scenes["braking"]
    specs = ["stop_angle", "t_end", md.Measure(cycles, unit="1")]
    out = tmp_path / "brake.csv"
    table = md.sweep(brake.mechanism, scene, brake.params, {"P": [20.0, 40.0]}, out=out,
                     progress=False, measures=specs)
    assert table.columns == ["P", "stop_angle", "t_end", "reason", "cycles", "error"]
    params = {str(k): v for k, v in brake.params.items()}
    for row in table.rows:
        res = brake.mechanism.simulate(scene, {**params, "P": row["P"]})
        assert [row["stop_angle"], row["t_end"], row["cycles"]] == \
            [md.measure(s)(res) for s in specs]
        assert row["stop_angle"] == pytest.approx(50000 / row["P"], rel=1e-9)
    key = json.loads(Path(f"{out}.meta.json").read_text())["measures"][2]
    assert key.startswith("cycles = test_measures.cycles (code ")


def test_a_sweep_refuses_measures_it_cannot_take_before_any_point(press):
    model, scene, p = press
    with pytest.raises(md.MeasureError, match="fluctuation is a measure of steady running"):
        md.sweep(model.mechanism, scene, p, {"J_f": [1.0]}, progress=False,
                 measures=["fluctuation"], steady=False)
    with pytest.raises(md.MeasureError, match="t_end is a measure of a run"):
        md.sweep(model.mechanism, scene, p, {"J_f": [1.0]}, progress=False,
                 measures=["fluctuation", "t_end"])
    brake = md.load_model(BRAKE)
    with pytest.raises(md.SceneError, match="no periodic regime"):
        md.sweep(brake.mechanism, brake.scenes["braking"], brake.params, {"P": [1.0]},
                 progress=False, steady=True)


def test_print_of_a_sweep_is_a_table_and_long_ones_are_cut():
    brake = md.load_model(BRAKE)
    table = md.sweep(brake.mechanism, brake.scenes["braking"], brake.params,
                     {"P": list(np.linspace(10.0, 100.0, 50))}, progress=False,
                     measures=["t_end"])
    lines = str(table).splitlines()
    assert lines[0] == "sweep over P: 50 points (rows 21 to 30 left out)"
    assert lines[1].split() == ["P", "[N]", "t_end", "[s]", "reason"]
    assert lines[2].split() == ["10", "100", "stopped(phi)"] and len(lines) == 42
    assert "<table>" in table._repr_html_() and len(repr(table)) < 80


def test_reprs_are_one_short_line(press):
    model, scene, p = press
    sized = md.flywheel(model.mechanism, scene, p, 0.02, "J_f")
    machine, shunt_scene, params = shunt_machine()
    x = md.coordinate("x")
    osc = md.Mechanism("oscillator", [x])
    osc.link("mass", m=1, x=x)
    osc.spring("spring", 4, stretch=x)
    osc.damper("damper", 0.4, stretch=x)
    osc.load("force", sp.cos(md.t), along=x)
    periodic = md.periodic_steady_state(osc, md.Scene("steady", t_end=1), {})
    for shown in (sized, sized.running, periodic, periodic.floquet, periodic.result,
                  md.steady_running(machine, shunt_scene, params)):
        text = repr(shown)
        assert "\n" not in text and len(text) < 160 and "array" not in text, text
    assert "delta = 0.02" in repr(sized) and "omega_mean = " in repr(sized.running)


def test_per_period_measures_of_a_forced_oscillator_are_its_amplitude():
    """x'' + 0.4 x' + 4 x = cos t: amplitude 1 / sqrt(9.16); RMS amplitude / sqrt(2);
    the damper takes integral 0.4 x'^2 dt = 0.4 pi (amplitude)^2 per period."""
    x = md.coordinate("x")
    osc = md.Mechanism("oscillator", [x])
    osc.link("mass", m=1, x=x)
    osc.spring("spring", 4, stretch=x)
    osc.damper("damper", 0.4, stretch=x)
    osc.load("force", sp.cos(md.t), along=x)
    scene = md.Scene("steady", t_end=1, outputs={"x": x, "power": "power:force"})
    periodic = md.periodic_steady_state(osc, scene, {})
    amplitude = 1 / math.sqrt(9.16)
    assert abs(md.measure("peak:x")(periodic)) == pytest.approx(amplitude, rel=1e-8)
    assert md.measure("rms:x")(periodic) == pytest.approx(amplitude / math.sqrt(2), rel=1e-8)
    assert md.measure("energy:force")(periodic) == pytest.approx(0.4 * math.pi * amplitude ** 2,
                                                                 rel=1e-8)


# ---------------------------------------------------------------- command line
def run(capsys, *argv):
    try:
        status = cli.main([str(a) for a in argv])
    except SystemExit as exit_:
        status = exit_.code
    out, err = capsys.readouterr()
    return status, out, err


def test_cli_sweep_measures_write_the_values_of_steady_running(capsys, tmp_path, press):
    model, _, p = press
    out = tmp_path / "press.csv"
    status, text, _ = run(capsys, "sweep", PRESS, "--scene", "steady", "--grid", "J_f=1,2",
                          "--measure", "fluctuation", "--measure", "mean_speed", "--out", out)
    assert status == 0 and "fluctuation" in text.splitlines()[0]
    import csv
    with open(out, newline="") as handle:
        rows = list(csv.DictReader(handle))
    for row in rows:
        running = md.steady_running(model.mechanism, model.scenes["steady"],
                                    {**p, "J_f": float(row["J_f"])})
        assert float(row["fluctuation"]) == running.delta
        assert float(row["mean_speed"]) == running.omega_mean
    status, _, err = run(capsys, "sweep", PRESS, "--scene", "steady", "--grid", "J_f=1",
                         "--measure", "fluctuaton")
    assert status == 2 and "did you mean fluctuation?" in err
    status, text, err = run(capsys, "sweep", PRESS, "--scene", "steady", "--grid", "J_f=1")
    assert status == 0 and "--steady or --measure fluctuation sweeps its steady running" in err
    status, text, _ = run(capsys, "sweep", PRESS, "--scene", "steady", "--grid", "J_f=1,2",
                          "--steady")
    header = text.splitlines()[0].split()
    assert status == 0 and header[:5] == ["J_f", "[kg*m^2]", "mean_speed", "[rad/s]",
                                          "fluctuation"]


def test_cli_periodic_sizes_the_flywheel_and_takes_a_speed_guess(capsys, press):
    model, scene, p = press
    status, text, _ = run(capsys, "periodic", PRESS, "--scene", "steady", "--flywheel-for",
                          "0.02", "--inertia", "J_f", "--speed-guess", "98 rpm")
    sized = md.flywheel(model.mechanism, model.scenes["steady"], p, 0.02, "J_f")
    assert status == 0 and f"flywheel J_f = {sized.inertia:.6g} for delta = 0.02" in text
    assert f"{sized.inertia:.6g}" == "1.42061"        # the model's docstring: 1.42
    status, _, err = run(capsys, "periodic", ROOT / "models" / "slider_crank.py", "--scene",
                         "startup")
    assert status != 0 and "--speed-guess" in err
    status, text, _ = run(capsys, "periodic", ROOT / "models" / "slider_crank.py", "--scene",
                          "startup", "--speed-guess", "100")
    assert status == 0 and "coefficient of speed fluctuation" in text
    status, _, err = run(capsys, "periodic", PRESS, "--scene", "steady", "--flywheel-for",
                         "0.02")
    assert status != 0 and "--inertia NAME" in err


@pytest.mark.parametrize("backend", ["auto", "scipy"])
def test_steady_running_on_either_backend_and_a_stall_named(backend):
    """The cycle map on the compiled kernels and on scipy: the linearised closed form
    delta = 2 A / (w sqrt((J w)^2 + b^2)), A = 20, b = 400/110, w = 110, J = 2 (second
    order in the fluctuation: 1e-4 relative); both agree to the integration tolerance.
    A motor of 5 N m cannot pull 50 cos(phi) through the cycle from 1 rad/s: it stalls
    (kinetic energy 1 + 5 pi/2 + 50 at pi/2, then the half turn takes 100 - 5 pi)."""
    machine, scene, params = shunt_machine()
    on = dataclasses.replace(scene, backend=backend)
    running = md.steady_running(machine, on, params)
    linear = 2 * 20 / (110 * math.sqrt((2 * 110) ** 2 + (400 / 110) ** 2))
    assert running.delta == pytest.approx(linear, rel=1e-4)
    other = md.steady_running(machine, dataclasses.replace(
        scene, backend="scipy" if backend == "auto" else "auto"), params)
    assert running.delta == pytest.approx(other.delta, rel=1e-7)
    assert running.omega_mean == pytest.approx(other.omega_mean, rel=1e-10)
    phi = machine.coordinates[0]
    weak = md.Mechanism("weak machine", [phi])
    weak.link("crank", J=2, angle=phi)
    weak.load("motor", md.motors.dc_shunt(5, 110)(md.speed(phi)), along=phi)
    weak.load("process", 50 * sp.cos(phi), along=phi)
    with pytest.raises(md.PeriodicError, match="stalls at phi = "):
        md.steady_running(weak, dataclasses.replace(on, outputs=()), {},
                          speed_guess=1.0)


def test_a_measure_that_fails_at_a_point_keeps_the_points_other_measures():
    """A brake bounded at 30 s: P = 10 N stops at 100 s, so it has no stop angle (NaN,
    the error named in the row) but its t_end, 30 s, is kept; P = 40 N stops at 25 s."""
    brake = md.load_model(BRAKE)
    scene = dataclasses.replace(brake.scenes["braking"], t_end=30)
    table = md.sweep(brake.mechanism, scene, brake.params, {"P": [10.0, 40.0]},
                     progress=False, measures=["stop_angle", "t_end"])
    short, full = table.rows
    assert math.isnan(short["stop_angle"]) and short["t_end"] == 30.0
    assert short["error"].startswith("stop_angle: MeasureError: stop_angle: the run did not "
                                     "stop at a stop condition")
    assert full["error"] == "" and full["stop_angle"] == pytest.approx(1250.0, rel=1e-9)
    assert table.failed == [short]

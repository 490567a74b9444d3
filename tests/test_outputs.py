"""Results for people: named outputs, uniform sampling, plots labelled with units and
events clear of the curves, closed forms printed for reading."""
import csv
import math
import re
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

import mechdyn as md
from mechdyn import cli

ROOT = Path(__file__).resolve().parents[1]
LONG_INTEGER = re.compile(r"(?<![\d.])\d{13,}(?![\d.])")     # an exact number's digits


@pytest.fixture(scope="module")
def brake():
    return md.load_model(ROOT / "models" / "shoe_brake.py")


def _rows(path):
    with open(path, newline="") as handle:
        rows = list(csv.reader(handle))
    return rows[0], np.array(rows[1:], dtype=float)


# ------------------------------------------------------------------ named outputs
def test_named_outputs_label_results_csv_and_plots(tmp_path):
    """The yoke's position l cos(phi) named "yoke travel" and the spring named "shaft
    moment": both labels reach the result, the CSV header and the plot legend."""
    model = md.load_model(ROOT / "models" / "two_mass_drive.py")
    phi_1, phi_2 = model.mechanism.coordinates
    scene = md.Scene("start", initial=model.scenes["start"].initial, t_end=0.1,
                     outputs={"twist": phi_1 - phi_2, "shaft moment": "shaft",
                              "motor power": "power:motor moment"})
    res = model.mechanism.simulate(scene, model.params)
    k = float(model.params[model.param_symbol("k")])
    assert np.allclose(res["shaft moment"], k * res["twist"], rtol=1e-12, atol=1e-12)
    assert np.allclose(res["twist"], res[phi_1] - res[phi_2], rtol=1e-12, atol=1e-15)
    assert res.units == {"phi_1": "rad", "phi_2": "rad", "twist": "",
                         "shaft moment": "N*m", "motor power": "W"}
    header, _ = _rows(res.to_csv(tmp_path / "run.csv"))
    assert header[-3:] == ["twist", "shaft moment", "motor power"]
    figure = res.plot()
    legends = {text.get_text() for ax in figure.axes if ax.get_legend()
               for text in ax.get_legend().get_texts()}
    assert {"twist", "shaft moment", "motor power"} <= legends


def test_unnamed_expression_outputs_read_in_plain_symbols(brake):
    phi = brake.mechanism.coordinates[0]
    scene = md.Scene("b", initial={phi: 0, md.speed(phi): 100}, until=md.stopped(phi),
                     outputs=[2 * phi, md.speed(phi) ** 2])
    res = brake.mechanism.simulate(scene, brake.params)
    assert list(res.outputs) == ["2*phi", "phidot**2"]
    assert res[2 * phi][-1] == pytest.approx(5000.0, rel=1e-9)       # 2 * 2500 rad
    with pytest.raises(md.SceneError, match="two outputs are labelled 'shoe'"):
        md.Scene("b", t_end=1, outputs=["shoe", "shoe"])


# ------------------------------------------------------------------- sampling
def test_uniform_sampling_of_the_csv_follows_the_closed_form(brake, tmp_path):
    """Braking: phi = 100 t - t^2, omega = 100 - 2 t, eps = -2 until the stop at 50 s."""
    res = brake.mechanism.simulate(brake.scenes["braking"], brake.params)
    header, rows = _rows(res.to_csv(tmp_path / "brake.csv", sample=0.5))
    assert header == ["t", "phi", "phidot", "phiddot"]
    t = rows[:, 0]
    assert len(t) == 101 and t.tolist() == [k / 2 for k in range(101)]
    moving = t < 50
    assert rows[moving, 1] == pytest.approx(100 * t[moving] - t[moving] ** 2, rel=1e-9)
    assert rows[moving, 2] == pytest.approx(100 - 2 * t[moving], rel=1e-9, abs=1e-9)
    assert rows[moving, 3] == pytest.approx(-2.0, rel=1e-12)
    assert rows[-1, 1:3] == pytest.approx([2500.0, 0.0], abs=1e-7)


def test_sample_times_are_exact_multiples(brake):
    res = brake.mechanism.simulate(brake.scenes["braking"], brake.params)
    times = res.sample_times(0.001)
    assert len(times) == 50001 and times[300] == 0.3 and times[-1] == 50.0
    # k / 1000, the nearest double to each multiple (k * 0.001 misses 282 of the first 2000)
    assert times[:2000].tolist() == [k / 1000 for k in range(2000)]
    assert res.sample_times(7.0)[-2:].tolist() == [49.0, res.t_end]    # the end is kept
    assert res.sample_times(0.3)[:4] == pytest.approx([0.0, 0.3, 0.6, 0.9], abs=1e-15)
    with pytest.raises(md.MechdynError, match="positive time step"):
        res.sample_times(0)


def test_simulate_command_samples_and_converts(capsys, tmp_path):
    out = tmp_path / "run.csv"
    status = cli.main(["simulate", str(ROOT / "models" / "motor_startup.py"), "--scene",
                       "startup", "--csv", str(out), "--sample", "0.5", "--units",
                       "speed=rpm,power=kW"])
    assert status == 0
    header, rows = _rows(out)
    assert header == ["t [s]", "phi [rad]", "phidot [rpm]", "phiddot [rad/s^2]",
                      "motor [N*m]", "power:motor [kW]"]
    assert np.diff(rows[:-1, 0]) == pytest.approx(0.5)
    # power = moment * speed: kW from N*m and rpm
    assert rows[:, 5] == pytest.approx(rows[:, 4] * rows[:, 2] * math.pi / 30 / 1000,
                                       rel=1e-9, abs=1e-12)
    assert "peak 1381.25 rpm" in capsys.readouterr().out


# ---------------------------------------------------------------------- plots
def test_axes_carry_units_and_events_sit_above_the_curves(brake):
    scene = md.Scene("b", initial=brake.scenes["braking"].initial,
                     until=brake.scenes["braking"].until, outputs=["shoe", "power:shoe"])
    res = brake.mechanism.simulate(scene, brake.params)
    figure = res.plot(units={"speed": "rpm"})
    strip, *axes = figure.axes
    assert [ax.get_ylabel() for ax in axes] == ["speed [rpm]", "position [rad]",
                                               "moment [N m]", "power [W]"]
    assert axes[-1].get_xlabel() == "time t [s]"
    # the event labels are in the strip, no text inside the data axes but legends
    assert any("stick shoe" in text.get_text() for text in strip.texts)
    assert all(not ax.texts for ax in axes)
    # a thin line at the event time in every panel
    for ax in axes:
        assert any(np.allclose(line.get_xdata(), 50.0) for line in ax.lines)


# ------------------------------------------------------------- closed forms, printed
def test_solve_prints_readable_relations_with_numbers(capsys):
    status = cli.main(["equations", str(ROOT / "models" / "motor_startup.py"), "--scene",
                       "startup", "--solve", "--format", "text"])
    out = capsys.readouterr().out
    assert status == 0
    model = md.load_model(ROOT / "models" / "motor_startup.py")
    stop = md.closed_form(model.mechanism, model.scenes["startup"], model.params).stop
    assert f"t = {float(stop.t):.12g}" in out and f"phi = {float(stop.phi):.12g}" in out
    assert "I*pi" not in out and not LONG_INTEGER.search(out.split("case 2")[1])


@pytest.mark.slow
def test_solve_of_the_rigid_hoist_has_no_complex_logarithms(capsys):
    """The hoist's Kloss motor against a weight behind a lossy gearbox: sympy writes
    t(omega) with log(negative) + I pi and 60-digit rationals; printed, it is real with
    decimals, and its numbers agree with a numeric quadrature of dt = I / M domega."""
    from scipy.integrate import quad
    status = cli.main(["equations", str(ROOT / "models" / "hoist_drive.py"), "--scene",
                       "lift_start_rigid", "--solve", "--format", "text"])
    out = capsys.readouterr().out.split("case 2")[1]
    assert status == 0 and "I*pi" not in out and not LONG_INTEGER.search(out)
    model = md.load_model(ROOT / "models" / "hoist_drive.py")
    mech, scene = model.mechanism, model.scenes["lift_start_rigid"]
    solution = md.closed_form(mech, scene, model.params)
    eqs = mech.equations(scene)
    values = {s: model.params[s] for s in model.params}
    inertia = float(eqs.reduced_inertia.xreplace(values))
    moment = sp.lambdify(eqs.u[0], eqs.reduced_moment.xreplace(values))
    for omega in (40.0, 120.0):
        expected = quad(lambda w: inertia / moment(w), 0, omega)[0]
        assert solution.function("t(omega)")(omega) == pytest.approx(expected, rel=1e-9)

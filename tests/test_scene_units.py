"""Values with units wherever a value is given: scene initial values and times, stop
values (md.reaches), sweep grids, sample steps. Bare numbers stay SI.

The shoe brake of models/shoe_brake.py decelerates at f 2 P R / I = 2 rad/s^2: from
omega_0 it stops after omega_0 / 2 s and omega_0^2 / 4 rad; the hoist's load height h
is a length (m).
"""
import csv
import math
from pathlib import Path

import pytest
import sympy as sp

import mechdyn as md
from mechdyn import cli

ROOT = Path(__file__).resolve().parents[1]
BRAKE = ROOT / "models" / "shoe_brake.py"


@pytest.fixture(scope="module")
def brake():
    model = md.load_model(BRAKE)
    return model, model.mechanism.coordinates[0]


def _braking(phi, **changes):
    options = dict(effects=["shoe"], initial={phi: 0, md.speed(phi): 100},
                   until=md.stopped(phi))
    options.update(changes)
    return md.Scene("braking", **options)


def test_1500_rpm_is_exactly_50_pi_and_runs_as_the_number(brake):
    model, phi = brake
    assert md.to_si("1500 rpm", "rad/s") == 50 * math.pi
    typed = _braking(phi, initial={phi: "0 deg", md.speed(phi): "1500 rpm"})
    assert typed.initial[md.speed(phi)] == 50 * math.pi
    res = model.mechanism.simulate(typed, model.params)
    same = model.mechanism.simulate(_braking(phi, initial={phi: 0, md.speed(phi): 50 * math.pi}),
                                    model.params)
    assert res.t_end == same.t_end and res.final(phi) == same.final(phi)
    assert res.t_end == pytest.approx(25 * math.pi, rel=1e-12)            # omega_0 / 2
    assert res.final(phi) == pytest.approx(625 * math.pi ** 2, rel=1e-12)  # omega_0^2 / 4


def test_a_value_of_the_wrong_dimension_is_refused_naming_it(brake):
    model, phi = brake
    wrong = _braking(phi, initial={phi: 0, md.speed(phi): "1500 N"})
    with pytest.raises(md.SceneError, match="scene 'braking': initial value of phidot = "
                       "'1500 N': N is a force but rad/s .* is expected"):
        model.mechanism.simulate(wrong, model.params)
    with pytest.raises(md.SceneError, match="initial value of phi = '2 m': m is a length"):
        model.mechanism.check_dimensions(_braking(phi, initial={phi: "2 m",
                                                                md.speed(phi): 100}))
    with pytest.raises(md.SceneError, match="initial value of phidot: '1 blorps': unknown"):
        _braking(phi, initial={phi: 0, md.speed(phi): "1 blorps"})


def test_lengths_and_their_speeds_take_length_units():
    hoist = md.load_model(ROOT / "models" / "hoist_drive.py")
    phi, h = hoist.mechanism.coordinates
    base = hoist.scenes["lift_start"]
    scene = md.Scene("lift", effects=base.effects, t_end="20 ms",
                     initial={phi: 0, md.speed(phi): 0, h: "20 mm", md.speed(h): "0 m/s"})
    res = hoist.mechanism.simulate(scene, hoist.params)
    assert res.y[1][0] == 0.02 and res.t_end == pytest.approx(0.02, rel=1e-14)
    bad = md.Scene("lift", effects=base.effects, t_end=1,
                   initial={phi: 0, md.speed(phi): 0, h: 0, md.speed(h): "3 rpm"})
    with pytest.raises(md.SceneError, match="hdot = '3 rpm'.* but m/s \\(a velocity\\)"):
        hoist.mechanism.simulate(bad, hoist.params)


def test_times_with_units_are_converted_when_the_scene_is_made(brake):
    _, phi = brake
    scene = md.Scene("s", initial={phi: 0, md.speed(phi): 1}, t_start="500 ms",
                     t_end="2 min", max_wall_time="1 h")
    assert (scene.t_start, scene.t_end, scene.max_wall_time) == (0.5, 120.0, 3600.0)
    with pytest.raises(md.SceneError, match="t_end: '2 kg': kg is a mass but s"):
        md.Scene("s", t_end="2 kg")
    with pytest.raises(md.SceneError, match="rtol must be a number"):
        md.Scene("s", t_end=1, rtol="1e-8")


def test_stop_values_with_units(brake):
    model, phi = brake
    turns = _braking(phi, until=md.reaches(phi, "100 rev"))
    assert turns.until[0].label == "reaches(phi, 100 rev)"
    res = model.mechanism.simulate(turns, model.params)
    # 100 t - t^2 = 200 pi
    assert res.t_end == pytest.approx(50 - math.sqrt(2500 - 200 * math.pi), rel=1e-10)
    assert res.final(phi) == pytest.approx(200 * math.pi, rel=1e-12)
    slow = model.mechanism.simulate(_braking(phi, until=md.reaches(md.speed(phi), "300 rpm")),
                                    model.params)
    assert slow.t_end == pytest.approx((100 - 10 * math.pi) / 2, rel=1e-10)
    for value, message in (("20 mm", "m is a length but rad"),
                           ("2 Hz", "Hz counts cycles")):
        condition = md.reaches(md.speed(phi) if value.endswith("Hz") else phi, value)
        with pytest.raises(md.SceneError, match=message):
            model.mechanism.simulate(_braking(phi, until=condition), model.params)


def test_a_stop_value_needs_the_expression_to_have_a_unit():
    phi = md.coordinate("phi")
    k = sp.Symbol("k", positive=True)
    disc = md.Mechanism("disc", [phi])               # no units declared
    disc.link("disc", J=1, angle=phi)
    disc.load("drive", 1, along=phi)
    scene = md.Scene("spin", initial={phi: 0, md.speed(phi): 0}, t_end=10,
                     until=md.reaches(k * phi, "2 N*m"))
    with pytest.raises(md.SceneError, match="has a unit, but k in the expression has none"):
        disc.simulate(scene, {k: 1})


def _rows(path):
    with open(path) as handle:
        return list(csv.DictReader(handle))


def test_grids_and_sample_steps_with_units(capsys, tmp_path):
    runs = {}
    for name, grid in (("si", "P=10:30:3"), ("kN", "P=0.01:0.03:3 kN"),
                       ("each", "P=10 N,0.02 kN,30000 mN")):
        out = tmp_path / f"{name}.csv"
        status = cli.main(["sweep", str(BRAKE), "--scene", "braking", "--grid", grid,
                           "--workers", "1", "--out", str(out)])
        assert status == 0, capsys.readouterr().err
        runs[name] = [(row["P"], row["t_end"]) for row in _rows(out)]
    assert runs["si"] == runs["kN"] == runs["each"]
    assert [float(p) for p, _ in runs["si"]] == [10.0, 20.0, 30.0]
    status = cli.main(["sweep", str(BRAKE), "--scene", "braking", "--grid", "P=10 kN,20",
                       "--workers", "1"])
    assert status == 2 and "give every value its unit or one unit after all" in \
        capsys.readouterr().err
    for name, step in (("seconds", "0.5"), ("ms", "500 ms")):
        assert cli.main(["simulate", str(BRAKE), "--scene", "braking", "--csv",
                         str(tmp_path / f"{name}.csv"), "--sample", step]) == 0
    assert _rows(tmp_path / "seconds.csv") == _rows(tmp_path / "ms.csv")
    capsys.readouterr()

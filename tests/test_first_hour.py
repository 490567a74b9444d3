"""A newcomer's first hour (issue 29, items 2-8): motor characteristics given to a load
directly, many events grouped, the bundled models found by name from any folder, usage
errors before work with suggestions, units in sweeps and summaries (the short reprs are
checked against the docs in tests/test_docs_examples.py)."""
import re
try:
    import tomllib
except ImportError:              # Python 3.10: pytest's own dependency there reads TOML
    import tomli as tomllib
from pathlib import Path

import sympy as sp
import pytest

import mechdyn as md

ROOT = Path(__file__).resolve().parents[1]


def _cli(capsys, *argv):
    from mechdyn import cli
    try:
        status = cli.main(list(argv))
    except SystemExit as exit_:          # argparse: usage errors
        status = exit_.code
    out, err = capsys.readouterr()
    return status, out, err


# ------------------------------------------------------- 2. motor characteristics
def test_a_motor_characteristic_is_accepted_by_a_load_at_the_speed_of_its_along():
    phi = md.coordinate("phi")
    i = sp.Symbol("i", positive=True)
    direct = md.Mechanism("direct", [phi])
    direct.link("rotor", J=2, angle=phi)
    direct.load("motor", md.motors.kloss(60, 0.2, 157), along=i * phi)
    called = md.Mechanism("called", [phi])
    called.link("rotor", J=2, angle=phi)
    called.load("motor", md.motors.kloss(60, 0.2, 157)(i * md.speed(phi)), along=i * phi)
    assert sp.simplify(direct.reduced_moment() - called.reduced_moment()) == 0
    w = md.plain(md.speed(phi))
    # the motor turns at i*omega: at slip s_k = 0.2 it gives its breakdown moment 60
    at_breakdown = direct.reduced_moment().subs({w: 0.8 * 157 / 3, i: 3})
    assert float(at_breakdown) == pytest.approx(3 * 60, rel=1e-12)


def test_a_plain_function_as_a_load_value_is_refused_naming_md_motors():
    phi = md.coordinate("phi")
    m = md.Mechanism("m", [phi])
    with pytest.raises(md.DeclarationError, match=r"load 'motor'.*is a function.*md\.motors"):
        m.load("motor", lambda speed: 60 - speed, along=phi)
    assert repr(md.motors.kloss(60, 0.2, 157)) == "kloss(M_k=60, s_k=0.2, omega_sync=157)"


# ------------------------------------------------- 5. the bundled models, by name
def test_the_bundled_models_are_found_by_name_from_an_empty_folder(tmp_path, monkeypatch,
                                                                   capsys):
    monkeypatch.chdir(tmp_path)
    assert md.load_model("slider_crank").mechanism.name == "Slider-crank"
    assert md.load_model("models/shoe_brake.py").scenes["braking"].name == "braking"
    status, out, err = _cli(capsys, "models")
    assert status == 0, err
    assert re.search(r"^slider_crank  Exact slider-crank", out, re.M)
    assert "    scenes: startup" in out
    status, out, err = _cli(capsys, "simulate", "shoe_brake", "--scene", "braking")
    assert status == 0, err
    assert "ended at t = 50 s" in out


def test_the_models_folder_ships_as_package_data():
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]
    assert "mechdyn.models" in config["packages"]
    assert config["package-dir"]["mechdyn.models"] == "models"


def test_a_misspelt_model_name_gets_a_suggestion(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(md.MechdynError, match=r"slider_crnk not found \(did you mean "
                       r"slider_crank\?\)"):
        md.load_model("slider_crnk")
    (tmp_path / "my_press.py").write_text("")
    with pytest.raises(md.MechdynError, match=r"did you mean my_press\.py\?"):
        md.load_model("my_pres.py")


# ------------------------------------------- 6. usage errors before work, suggestions
@pytest.mark.parametrize("argv, message", [
    (("precision", "shoe_brake", "--scene", "braking", "--methods", "RK54"),
     "unknown method 'RK54' (did you mean RK45?)"),
    (("simulate", "motor_startup", "--scene", "startup", "--units", "speed=rmp"),
     "unknown unit 'rmp' (did you mean rpm?)"),
    (("simulate", "shoe_brake", "--scene", "brakin"), "no scene 'brakin' (did you mean braking?)"),
    (("simulate", "shoe_brak", "--scene", "braking"), "(did you mean shoe_brake?)"),
    (("linkage", "fourbar_flywheel", "--omega", "30", "--drive", "motr"),
     "no load named or tagged so (did you mean motor?)"),
    (("sweep", "shoe_brake", "--scene", "braking", "--grid", "PP=1:2:2"),
     "no parameter 'PP' (did you mean P?)"),
])
def test_usage_errors_exit_2_before_any_work_with_a_suggestion(capsys, argv, message):
    status, out, err = _cli(capsys, *argv)
    assert status == 2 and out == ""                  # nothing ran, nothing printed
    assert message in err


def test_a_scene_with_a_misspelt_method_gets_a_suggestion():
    model = md.load_model("shoe_brake")
    scene = model.scenes["braking"]
    wrong = md.Scene("braking", initial=scene.initial, until=scene.until, method="Rado")
    with pytest.raises(md.SceneError, match=r"unknown method 'Rado' \(did you mean Radau\?\)"):
        model.mechanism.simulate(wrong, model.params)


# ---------------------------------------------------------------- 3. many events
@pytest.fixture(scope="module")
def rubbing():
    """A block on a spring, Coulomb friction on its guide: it reverses ~32 times in 10 s
    (amplitude losing 2 F/k = 0.02 m a half cycle of 0.628 s)."""
    x = md.coordinate("x")
    block = md.Mechanism("block", [x], units={x: "m"})
    block.link("block", m=1, x=x)
    block.spring("spring", 100, stretch=x)
    block.friction("guide", 1, along=x)
    return block.simulate(md.Scene("release", initial={x: 1, md.speed(x): 0}, t_end=10))


def test_repeated_events_are_one_summary_line_and_all_kept(rubbing):
    slips = [e for e in rubbing.events if e.kind == "slip" and e.name == "guide"]
    assert len(slips) == len(rubbing.events) > 25          # every reversal is kept
    lines = [line for line in rubbing.summary().splitlines() if "guide" in line]
    assert lines == [f"  slip guide: {len(slips)} times, t = 0 ... "
                     f"{slips[-1].time:.4g} s"]


def test_plot_labels_group_repeated_events_and_only_what_fits(rubbing):
    pytest.importorskip("matplotlib")
    from mechdyn.simulate.events import Event
    figure = rubbing.plot()
    assert [t.get_text() for t in figure.axes[0].texts] == [
        f"slip guide: {len(rubbing.events)} times, t = 0 ... {rubbing.events[-1].time:.4g} s"]
    figure.clf()
    many = [Event(0.5 * k, "stick", f"brake {k}", "") for k in range(20)]   # 20 labels
    rubbing.events, kept = many, rubbing.events
    try:
        figure = rubbing.plot()
    finally:
        rubbing.events = kept
    figure.canvas.draw()
    renderer = figure.canvas.get_renderer()
    texts = figure.axes[0].texts
    labels = [t for t in texts if t.get_text().startswith("stick")]
    assert 2 <= len(labels) < 20
    assert texts[-1].get_text() == f"+{20 - len(labels)} event labels left out (result.events)"
    boxes = [t.get_window_extent(renderer) for t in labels]
    assert not any(a.overlaps(b) for i, a in enumerate(boxes) for b in boxes[i + 1:])


# ----------------------------------------------------------- 8. units everywhere
def test_sweep_columns_and_plot_axes_carry_units():
    pytest.importorskip("matplotlib")
    model = md.load_model("shoe_brake")
    table = md.sweep(model.mechanism, model.scenes["braking"], model.params,
                     {"P": [20, 40]}, progress=False, workers=1)
    assert [table.label(c) for c in ("P", "t_end", "final:phi", "final:phidot")] == \
        ["P [N]", "t_end [s]", "final:phi [rad]", "final:phidot [rad/s]"]
    figure = table.plot("final:phi")
    assert figure.axes[0].get_xlabel() == "P [N]"
    assert figure.axes[0].get_ylabel() == "final:phi [rad]"


def test_a_summary_writes_the_unit_once_after_final_and_peak():
    model = md.load_model("shoe_brake")
    braking = model.scenes["braking"]
    scene = md.Scene("braking", initial=braking.initial, until=braking.until,
                     outputs={"brake moment": "shoe"})
    res = model.mechanism.simulate(scene, model.params)
    line = next(line for line in res.summary().splitlines() if "brake moment" in line)
    assert re.fullmatch(r"  brake moment: peak -?[0-9.]+, final -?[0-9.]+ N\*m", line)


def test_the_repeats_help_says_what_the_runs_column_shows(capsys):
    status, out, _ = _cli(capsys, "precision", "--help")
    assert status == 0
    assert "default 3; fewer once they took 1 s, up to 5 times more" in " ".join(out.split())

"""The bundled linkages (four-bar with flywheel, Watt six-bar, quick-return, toggle
press): their scenes run, their kinematics agree with hand geometry, and `mechdyn
linkage` reports and draws them. Also a two-DOF loop (five-bar) and the LaTeX of a loop."""
import math
from pathlib import Path

import numpy as np
import pytest

import mechdyn as md
from mechdyn import cli

ROOT = Path(__file__).resolve().parents[1]
LINKAGES = ["fourbar_flywheel", "watt_sixbar", "quick_return", "toggle_press"]


def load(name):
    return md.load_model(ROOT / "models" / f"{name}.py")


@pytest.mark.slow
@pytest.mark.parametrize("name", LINKAGES)
def test_every_scene_runs_and_keeps_the_loops_closed(name):
    model = load(name)
    for scene in model.scenes.values():
        result = model.mechanism.simulate(scene, model.params)
        assert result.t_end == scene.t_end and np.all(np.isfinite(result.y))
        from mechdyn.simulate.assembly import closure_parts
        p = result.compiled.parameter_vector(model.params)
        g, _, _, _ = closure_parts(result.compiled, result.t_end, result.y[:, -1], p)
        assert np.max(np.abs(g)) < 1e-8


def test_quick_return_time_ratio_is_the_textbook_one():
    """The lever's extremes are where the crank is square to it: sin = r/d, so the two
    strokes take pi +- 2 asin(r/d) of crank angle."""
    model = load("quick_return")
    linkage = md.Linkage(model.mechanism, model.params, scene=model.scenes["steady"])
    ends = linkage.extremes("x")
    assert len(ends) == 2
    short = (ends[1][0] - ends[0][0]) % (2 * np.pi)
    r, d = 0.1, 0.3
    assert abs(short - (np.pi - 2 * math.asin(r / d))) < 1e-9
    # at both ends the lever tip B is at the same height, R sin(asin(r/d)) = R r/d to
    # either side: the ram's stroke is 2 R r / d
    assert abs(abs(ends[1][1] - ends[0][1]) - 2 * 0.5 * r / d) < 1e-9


def test_toggle_press_ram_stops_short_of_the_straight_toggle():
    model = load("toggle_press")
    linkage = md.Linkage(model.mechanism, model.params, scene=model.scenes["steady"])
    lowest = min(value for _, value in linkage.extremes("y"))
    assert -0.6 < lowest < -0.5998          # u + w = 0.6 m: straight toggle at y = -0.6


def test_five_bar_with_two_independent_cranks():
    """Two cranks (phi_1, phi_2) and two couplers meeting at P: a two-DOF loop. P is
    the intersection of two circles, by hand."""
    phi_1, phi_2, th_3, th_4 = md.coordinates("phi_1 phi_2 theta_3 theta_4")
    five = md.Mechanism("five-bar", [phi_1, phi_2, th_3, th_4], independent=[phi_1, phi_2])
    for name, angle in (("crank 1", phi_1), ("crank 2", phi_2), ("coupler 3", th_3),
                        ("coupler 4", th_4)):
        five.link(name, J=1, angle=angle)
    five.loop("P", (1, phi_1), (3, th_3), (-3, th_4), (-1, phi_2), (-2, 0))
    linkage = md.Linkage(five, guess={th_3: 1.2, th_4: 2.0})
    q = linkage.position([0.5, 2.0])
    a = np.array([math.cos(0.5), math.sin(0.5)])
    b = np.array([2 + math.cos(2.0), math.sin(2.0)])
    half = np.linalg.norm(b - a) / 2
    middle = (a + b) / 2
    normal = np.array([-(b - a)[1], (b - a)[0]]) / (2 * half)
    point = middle + math.sqrt(9 - half**2) * normal
    assert np.allclose(a + 3 * np.array([math.cos(q[2]), math.sin(q[2])]), point, atol=1e-12)
    speeds = linkage.velocity_matrix(q)            # u = S [phi_1', phi_2']
    assert speeds.shape == (4, 2) and np.allclose(speeds[:2], np.eye(2))
    # kinetic energy of unit inertias: sum of squared angular speeds = u_i' (S'S) u_i
    assert np.allclose(linkage.reduced_mass_matrix(q), speeds.T @ speeds, rtol=1e-12)
    with pytest.raises(md.LinkageError, match="2 independent coordinates"):
        linkage.sweep([0.1, 0.2])


def test_latex_of_a_loop_shows_closure_transmission_functions_and_i_red():
    model = load("fourbar_flywheel")
    text = model.mechanism.latex()
    assert "0 = g_{\\text{ABCD.x}}" in text
    assert "\\theta_{2}' &= - \\frac{a \\sin{\\left(\\phi - \\theta_{3} \\right)}}" in text
    assert "I_{\\mathrm{red}} &=" in text and "\\lambda_{1}" in text


def test_linkage_command_reports_and_draws(capsys, tmp_path):
    pytest.importorskip("matplotlib")
    figure, forces = tmp_path / "kin.png", tmp_path / "forces.png"
    status = cli.main([
        "linkage", str(ROOT / "models" / "fourbar_flywheel.py"), "--plot", str(figure),
        "--omega", "30", "--drive", "motor", "--forces", str(forces), "--points", "91"])
    out = capsys.readouterr().out
    assert status == 0
    assert "class: crank-rocker" in out and "the crank turns fully" in out
    assert "transmission angle:" in out and "joint B (revolute): peak force" in out
    assert figure.stat().st_size > 10_000 and forces.stat().st_size > 10_000


def test_linkage_command_names_a_model_without_loops(capsys):
    status = cli.main(["linkage", str(ROOT / "models" / "shoe_brake.py")])
    err = capsys.readouterr().err
    assert status == 2 and "has no loops" in err

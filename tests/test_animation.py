"""Animation: one GIF frame per sample, the links move between frames."""
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

import mechdyn as md
from mechdyn import cli

Image = pytest.importorskip("PIL.Image")
pytest.importorskip("matplotlib")
ROOT = Path(__file__).resolve().parents[1]


def _frames(path):
    gif = Image.open(path)
    frames = []
    for k in range(gif.n_frames):
        gif.seek(k)
        frames.append(np.asarray(gif.convert("RGB"), dtype=int))
    return frames


def _moved(a, b):
    """Pixels that differ below the top fifth (where the clock and title are)."""
    rows = a.shape[0] // 5
    return int(np.count_nonzero(np.any(a[rows:] != b[rows:], axis=2)))


@pytest.fixture(scope="module")
def crank():
    model = md.load_model(ROOT / "models" / "slider_crank.py")
    return model, model.mechanism.simulate(model.scenes["startup"], model.params)


def test_one_frame_per_sample_and_the_links_move(crank, tmp_path):
    model, result = crank
    film = md.animate(model.mechanism, result, model.params, tmp_path / "crank.gif",
                      sample=0.1, fps=10)
    assert film.frames == 11 and film.times[-1] == pytest.approx(result.t_end)
    frames = _frames(film.path)
    assert len(frames) == 11
    # the crank starts at rest and turns: every later frame differs from the first,
    # and consecutive frames differ once it runs
    assert all(_moved(frames[0], frame) > 100 for frame in frames[2:])
    assert all(_moved(a, b) > 50 for a, b in zip(frames[5:], frames[6:]))
    assert Image.open(film.path).info["duration"] == pytest.approx(100, abs=1)


def test_a_link_without_points_is_drawn_with_a_turning_tick(tmp_path):
    phi = md.coordinate("phi")
    disc = md.Mechanism("disc", [phi])
    disc.link("disc", J=1, angle=phi)
    disc.load("drive", 0, along=phi)
    scene = md.Scene("spin", initial={phi: 0, md.speed(phi): 2 * np.pi}, t_end=0.5)
    result = disc.simulate(scene)
    film = md.animate(disc, result, {}, tmp_path / "disc.gif", sample=0.125)
    frames = _frames(film.path)
    assert film.frames == len(frames) == 5
    assert _moved(frames[0], frames[1]) > 50          # a quarter turn apart
    assert _moved(frames[0], frames[4]) > 50          # half a turn: the tick points back


def test_animation_errors_name_the_problem(crank, tmp_path):
    model, result = crank
    with pytest.raises(md.MechdynError, match="give values for"):
        md.animate(model.mechanism, result, {}, tmp_path / "x.gif", sample=0.5)
    with pytest.raises(md.MechdynError, match="larger sample"):
        md.animate(model.mechanism, result, model.params, tmp_path / "x.gif", sample=1e-5)
    x = md.coordinate("x")
    with pytest.raises(md.DeclarationError, match="points\\[0\\] must be a pair"):
        md.Mechanism("m", [x]).link("block", m=1, x=x, points=[(x,)])
    with pytest.raises(md.DeclarationError, match="point 0 y"):
        md.Mechanism("m", [x]).link("block", m=1, x=x, points=[(x, sp.Symbol("y")
                                                                   * md.speed(x))])


def test_the_command_writes_the_gif(capsys, tmp_path):
    out = tmp_path / "yoke.gif"
    status = cli.main(["animate", str(ROOT / "models" / "scotch_yoke.py"), "--scene",
                       "startup", "--out", str(out), "--sample", "0.25"])
    assert status == 0 and "5 frames" in capsys.readouterr().out
    assert Image.open(out).n_frames == 5

"""Progress on the command line: the simulated time of t_end and the percentage on one
stderr line, for runs past two seconds, when stderr is a terminal or with --progress,
cleared at the end. Clocks are replaced by counters, so nothing depends on this
machine's speed."""
import io
import sys
import re
import types
from pathlib import Path

import pytest

from mechdyn import cli, progress
from mechdyn.simulate import driver
from mechdyn.progress import ProgressLine

ROOT = Path(__file__).resolve().parents[1]
HOIST = str(ROOT / "models" / "hoist_drive.py")        # lift_start: t_end = 2 s
PRESS = str(ROOT / "models" / "press_cycle.py")


def counter(step):
    """A clock that advances ``step`` seconds at every reading."""
    now = [0.0]

    def read():
        now[0] += step
        return now[0]
    return read


def test_the_line_waits_shows_time_and_percent_and_clears():
    stream = io.StringIO()
    clock = iter([0.0, 1.0, 2.5, 3.0]).__next__      # start, then three reports
    with ProgressLine(stream, delay=2.0, clock=clock) as line:
        line(0.4, 2.0)                                 # 1 s in: too early
        assert stream.getvalue() == ""
        line(1.0, 2.0)
        line(2.0, 2.0)
    parts = stream.getvalue().split("\r")
    assert parts[1:3] == ["mechdyn: t = 1 s of 2 s (50 %)", "mechdyn: t = 2 s of 2 s (100 %)"]
    assert parts[3] == " " * len(parts[2]) and parts[4] == ""     # blanked, back at start


def test_a_phase_counts_its_own_time():
    stream = io.StringIO()
    line = ProgressLine(stream, delay=0.0, clock=counter(1.0))
    line.phase("steady", 2, 3, t_start=10.0)
    line(15.0, 20.0)
    assert stream.getvalue() == "\rmechdyn: phase 2/3 steady: t = 15 s of 20 s (50 %)"


@pytest.fixture
def fake_clocks(monkeypatch, capsys):
    """The driver reports at every chunk of steps (its clock jumps 1 s a reading), the
    progress line is past its delay at once (10 s a reading); the scenes are compiled
    first (a compilation over a second is announced on stderr)."""
    for model, scene in ((HOIST, "lift_start"), (PRESS, "startup+steady")):
        assert cli.main(["simulate", model, "--scene", scene, "--no-progress"]) == 0
    capsys.readouterr()
    monkeypatch.setattr(driver, "time", types.SimpleNamespace(perf_counter=counter(1.0)))
    monkeypatch.setattr(progress, "time", types.SimpleNamespace(monotonic=counter(10.0)))


def _simulate(capsys, *options):
    status = cli.main(["simulate", HOIST, "--scene", "lift_start", *options])
    out, err = capsys.readouterr()
    assert status == 0, err
    return out, err


def test_progress_goes_to_stderr_and_is_cleared(capsys, fake_clocks):
    out, err = _simulate(capsys, "--progress")
    lines = err.split("\r")
    shown = [part for part in lines if part.strip()]
    assert shown and all(re.fullmatch(r"mechdyn: t = [\d.e+-]+ s of 2 s \(\d+ %\) *", part)
                         for part in shown)
    assert lines[-1] == "" and lines[-2].strip() == ""          # the line is blanked
    assert "Hoist drive" in out and "mechdyn: t =" not in out


def test_no_progress_unless_a_terminal_or_asked(capsys, monkeypatch, fake_clocks):
    _, err = _simulate(capsys)                       # stderr is not a terminal here
    assert err == ""
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True, raising=False)
    _, err = _simulate(capsys)
    assert "mechdyn: t = " in err
    _, err = _simulate(capsys, "--no-progress")
    assert err == ""


def test_a_duty_cycle_shows_its_phases(capsys, fake_clocks):
    status = cli.main(["simulate", PRESS, "--scene", "startup+steady", "--progress"])
    out, err = capsys.readouterr()
    assert status == 0, err
    assert "mechdyn: phase 1/2 startup: t = " in err
    assert re.search(r"mechdyn: phase 2/2 steady: t = [\d.]+ s of [\d.]+ s \(\d+ %\)", err)
    assert "duty cycle startup+steady: 2 phases" in out

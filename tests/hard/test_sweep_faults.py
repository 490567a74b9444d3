"""Sweeps under faults: interrupted, killed, run twice at once, resumed with other inputs,
asked for too many points. Nothing finished is lost, no worker outlives its sweep, and a
resumed file equals an uninterrupted run's.

Reference rows come from an uninterrupted sweep of the same grid; the computation of a
point does not depend on where or when it runs, so rows must be equal exactly.
"""
import csv
import json
import os
import random
import signal
import subprocess
import sys
import time
from concurrent.futures import Executor, ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pytest

import mechdyn as md
from mechdyn.analyse import sweep_tasks
from mechdyn.cli import main
from mechdyn.analyse.sweeps import SweepError, SweepFileError

ROOT = Path(__file__).resolve().parents[2]
DRIVE = str(ROOT / "models" / "two_mass_drive.py")
BRAKE = str(ROOT / "models" / "shoe_brake.py")
GRID = "k=1000:4000:400"         # about 10 ms a point compiled: seconds in all, so a
                                 # sweep is still running when it is killed


def sweep_args(out, *extra):
    return ["sweep", DRIVE, "--scene", "start", "--grid", GRID, "--workers", "2",
            "--out", str(out), *extra]


def start(out, *extra):
    """A sweep in another process (SIGINT at its default: a Ctrl-C reaches it)."""
    return subprocess.Popen([sys.executable, "-m", "mechdyn.cli.command", *sweep_args(out, *extra)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env=dict(os.environ, PYTHONPATH=str(ROOT)), cwd=ROOT,
                            preexec_fn=sigint_at_default)


def sigint_at_default():
    """In the child before it starts: SIGINT as in a terminal, whatever the test runner
    set (a pytest-xdist worker ignores it, and a Python started ignoring SIGINT never
    raises KeyboardInterrupt)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def rows(path):
    with open(path, newline="") as handle:
        return list(csv.DictReader(handle))


def wait_for_rows(path, count, process, timeout=120):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if process.poll() is not None:
            pytest.fail(f"the sweep ended early: {process.communicate()}")
        if Path(path).is_file() and len(rows(path)) >= count:
            return
        time.sleep(0.05)
    pytest.fail(f"no {count} rows in {timeout} s")


def workers_of(process):
    psutil = pytest.importorskip("psutil")
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:
        children = psutil.Process(process.pid).children(recursive=True)
        if len(children) >= 2:
            return children
        time.sleep(0.05)
    pytest.fail("no worker processes seen")


def assert_ended(processes, within=5.0):
    """Each process has exited (a zombie waiting for its parent to reap it counts)."""
    psutil = pytest.importorskip("psutil")
    deadline = time.monotonic() + within
    alive = list(processes)
    while alive and time.monotonic() < deadline:
        alive = [p for p in alive if _running(p, psutil)]
        time.sleep(0.1)
    assert not alive, f"workers still running: {[p.pid for p in alive]}"


def _running(process, psutil):
    try:
        return process.status() != psutil.STATUS_ZOMBIE
    except psutil.NoSuchProcess:
        return False


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """The rows of an uninterrupted run, by k."""
    out = tmp_path_factory.mktemp("reference") / "drive.csv"
    assert main(sweep_args(out)) == 0
    table = {r["k"]: r for r in rows(out)}
    assert len(table) == 400 and not any(r["error"] for r in table.values())
    return table


def assert_same_rows(path, reference):
    found = rows(path)
    assert len({r["k"] for r in found}) == len(found)          # no point twice
    assert {r["k"]: r for r in found} == reference


@pytest.mark.slow
def test_ctrl_c_keeps_finished_rows_ends_the_workers_and_the_rerun_resumes(
        tmp_path, reference, capsys):
    out = tmp_path / "drive.csv"
    process = start(out)
    workers = workers_of(process)
    wait_for_rows(out, 3, process)
    process.send_signal(signal.SIGINT)
    _, err = process.communicate(timeout=20)
    assert process.returncode == 130 and "interrupted" in err
    assert_ended(workers)
    kept = rows(out)
    assert len(kept) >= 3 and all(r == reference[r["k"]] for r in kept)
    assert main(sweep_args(out)) == 0
    assert rows(out)[:len(kept)] == kept                      # nothing rewritten
    assert_same_rows(out, reference)


@pytest.mark.slow
def test_killed_at_random_points_then_resumed_gives_the_uninterrupted_rows(
        tmp_path, reference):
    """SIGKILL leaves no chance to clean up: the workers must end by themselves, and a
    row may be cut off in the middle. Kill at two random points, then finish."""
    out = tmp_path / "drive.csv"
    chosen = random.Random(20240917)
    for _ in range(2):
        process = start(out)
        workers = workers_of(process)
        done = len(rows(out)) if out.is_file() else 0
        wait_for_rows(out, done + chosen.randint(1, 12), process)
        time.sleep(chosen.uniform(0, 0.3))
        process.kill()
        process.communicate()
        assert_ended(workers)
    assert main(sweep_args(out)) == 0
    assert_same_rows(out, reference)


@pytest.mark.slow
def test_a_second_sweep_on_the_same_file_stops_at_once_or_waits(tmp_path, reference,
                                                                 capsys):
    out = tmp_path / "drive.csv"
    first = start(out)
    wait_for_rows(out, 1, first)
    started = time.monotonic()
    assert main(sweep_args(out)) == 2
    assert time.monotonic() - started < 5
    err = capsys.readouterr().err
    assert "in use by another sweep" in err and str(out) in err and "--wait" in err
    assert main(sweep_args(out, "--wait", "300")) == 0       # runs once the first is done
    assert first.wait(timeout=60) == 0
    assert_same_rows(out, reference)


# ------------------------------------------------------------ resuming other inputs
@pytest.fixture
def brake():
    return md.load_model(BRAKE)


def run(brake, out, params=None, **options):
    with ThreadPoolExecutor(2) as pool:
        return md.sweep(brake.mechanism, brake.scenes["braking"], params or brake.params,
                        {"P": [10.0, 20.0, 40.0]}, executor=pool, out=out, progress=False,
                        **options)


def test_resuming_with_other_fixed_values_is_refused_naming_them(brake, tmp_path):
    out = tmp_path / "brake.csv"
    run(brake, out)
    before = out.read_text()
    changed = {**{str(k): v for k, v in brake.params.items()}, "R": 0.2, "f": 0.3}
    with pytest.raises(SweepFileError) as refused:
        run(brake, out, changed)
    message = str(refused.value)
    assert "fixed parameter R was 0.1, now 0.2" in message
    assert "fixed parameter f was 0.2, now 0.3" in message and "fresh" in message
    assert out.read_text() == before                          # nothing lost
    table = run(brake, out, changed, fresh=True)              # t = I w0 / (2 f P R)
    np.testing.assert_allclose(table["t_end"], 0.4 * 100 / (2 * 0.3 * 0.2 *
                                                             np.array([10, 20, 40])),
                               rtol=1e-9)


def test_resuming_another_version_scene_or_file_without_record_is_refused(brake, tmp_path):
    out = tmp_path / "brake.csv"
    run(brake, out)
    meta = tmp_path / "brake.csv.meta.json"
    record = json.loads(meta.read_text())
    meta.write_text(json.dumps({**record, "mechdyn": "0.0.1"}))
    with pytest.raises(SweepFileError, match="mechdyn version was 0.0.1, now"):
        run(brake, out)
    meta.write_text(json.dumps({**record, "scene": {**record["scene"], "rtol": "1e-06"}}))
    with pytest.raises(SweepFileError, match="scene's rtol was 1e-06, now 1e-10"):
        run(brake, out)
    meta.unlink()
    with pytest.raises(SweepFileError, match="no record of the sweep"):
        run(brake, out)


def test_the_command_line_names_the_difference_and_starts_afresh(tmp_path, capsys):
    out = tmp_path / "brake.csv"
    args = ["sweep", BRAKE, "--scene", "braking", "--grid", "P=10,20", "--workers", "1",
            "--out", str(out)]
    assert main(args) == 0
    assert main(args + ["--param", "I=0.8"]) == 2
    err = capsys.readouterr().err
    assert "fixed parameter I was 0.4, now 0.8" in err and "--fresh" in err
    assert main(args + ["--param", "I=0.8", "--fresh"]) == 0
    assert [float(r["t_end"]) for r in rows(out)] == pytest.approx([200.0, 100.0], rel=1e-9)


# ------------------------------------------------------------------- limits
def test_a_grid_above_the_limit_is_refused_before_it_is_built(capsys, brake):
    started = time.monotonic()
    assert main(["sweep", BRAKE, "--scene", "braking", "--grid", "P=1:2:1e9"]) == 2
    assert "1,000,000,000 values" in capsys.readouterr().err
    assert main(["sweep", BRAKE, "--scene", "braking", "--grid", "P=1:2:2000",
                 "--grid", "f=0.1:0.3:1000"]) == 2
    assert "2,000,000 points (2000 x 1000)" in capsys.readouterr().err
    assert time.monotonic() - started < 10
    with pytest.raises(SweepError, match="max_points = 2"):
        md.sweep(brake.mechanism, brake.scenes["braking"], brake.params,
                 {"P": [1, 2, 3]}, max_points=2, progress=False)


@pytest.mark.parametrize("workers", ["-1", "0", "two"])
def test_a_worker_count_below_one_is_a_usage_error(workers, capsys):
    with pytest.raises(SystemExit) as exited:
        main(["sweep", BRAKE, "--scene", "braking", "--grid", "P=10", "--workers", workers])
    assert exited.value.code == 2
    assert f"--workers: '{workers}' is not a whole number >= 1" in capsys.readouterr().err


def test_a_worker_count_below_one_is_refused_by_the_api(brake):
    with pytest.raises(SweepError, match="workers = 0"):
        md.sweep(brake.mechanism, brake.scenes["braking"], brake.params, {"P": [10]},
                 workers=0, progress=False)


class _Counting(Executor):
    """A thread pool that records how many submitted tasks were unfinished at most."""

    def __init__(self):
        self.pool, self.outstanding, self.most, self.points = ThreadPoolExecutor(2), 0, 0, 0

    def submit(self, fn, *args):
        self.outstanding += 1
        self.most = max(self.most, self.outstanding)
        self.points += len(args[-1])
        future = self.pool.submit(fn, *args)
        future.add_done_callback(self._finished)
        return future

    def _finished(self, _):
        self.outstanding -= 1


def test_points_are_submitted_in_bounded_chunks(brake, monkeypatch):
    monkeypatch.setattr(sweep_tasks, "IN_FLIGHT", 8)
    executor = _Counting()
    forces = list(np.linspace(10, 100, 60))
    table = md.sweep(brake.mechanism, brake.scenes["braking"], brake.params,
                     {"P": forces}, executor=executor, progress=False)
    executor.pool.shutdown()
    assert executor.most <= 8 and executor.points == 60
    np.testing.assert_allclose(table["t_end"], 1000 / np.array(forces), rtol=1e-9)


def test_a_scene_without_outputs_never_evaluates_the_dense_output(brake, monkeypatch):
    """Only the columns asked for are computed: no peak, so no dense output."""
    def refused(*args):
        raise AssertionError("dense output evaluated for a scene without outputs")
    monkeypatch.setattr(md.Result, "outputs_at", refused)
    with ThreadPoolExecutor(1) as pool:
        table = md.sweep(brake.mechanism, brake.scenes["braking"], brake.params,
                         {"P": [10.0, 20.0]}, executor=pool, progress=False)
    assert not table.failed and list(table["t_end"]) == pytest.approx([100.0, 50.0])

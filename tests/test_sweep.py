"""Parameter sweeps: closed-form stop times, Dask gives the same rows, resume, failures.

Reference: the shoe brake's disc (inertia I) is decelerated by the constant friction
moment f * 2P * R (the lever doubles the shoe force P), so I d(omega)/dt = -2 f P R and
omega(t) = omega_0 - 2 f P R t / I: the disc stops at t = I omega_0 / (2 f P R), having
turned omega_0 t / 2 = I omega_0^2 / (4 f P R).
"""
import csv
from concurrent.futures import Executor, Future
from pathlib import Path

import numpy as np
import sympy as sp
import pytest

import mechdyn as md
from mechdyn.errors import ParameterError
from mechdyn.analyse.sweeps import SweepFileError

ROOT = Path(__file__).resolve().parents[1]
FORCES = list(np.linspace(5.0, 200.0, 50))


@pytest.fixture(scope="module")
def brake():
    return md.load_model(ROOT / "models" / "shoe_brake.py")


def _by_name(model):
    return {str(k): float(v) for k, v in model.params.items()}


@pytest.fixture(scope="module")
def local_sweep(brake, tmp_path_factory):
    out = tmp_path_factory.mktemp("sweep") / "brake.csv"
    table = md.sweep(brake.mechanism, brake.scenes["braking"], brake.params,
                     {"P": FORCES}, out=out, progress=False)     # local processes
    return table, out


class _Inline(Executor):
    """Runs each batch of points at submission, counting the points; raises
    KeyboardInterrupt (as a Ctrl-C would) at the first submission of points after
    ``interrupt_after`` points were submitted."""

    def __init__(self, interrupt_after=None):
        self.points, self.interrupt_after = 0, interrupt_after

    def submit(self, fn, *args, **kwargs):
        points = len(args[-1])
        if (self.interrupt_after is not None and points
                and self.points >= self.interrupt_after):
            raise KeyboardInterrupt
        self.points += points
        future = Future()
        future.set_result(fn(*args, **kwargs))
        return future


def _rows(path):
    with open(path, newline="") as handle:
        return list(csv.DictReader(handle))


def test_stop_times_of_50_brake_forces_match_the_closed_form(brake, local_sweep):
    table, out = local_sweep
    p = _by_name(brake)
    omega_0 = 100.0
    forces = np.array(FORCES)
    t_stop = p["I"] * omega_0 / (2 * p["f"] * forces * p["R"])
    angle = p["I"] * omega_0 ** 2 / (4 * p["f"] * forces * p["R"])
    assert len(table) == 50 and not table.failed
    np.testing.assert_allclose(table["P"], forces, rtol=0, atol=0)
    np.testing.assert_allclose(table["t_end"], t_stop, rtol=1e-9)
    np.testing.assert_allclose(table["final:phi"], angle, rtol=1e-9)
    assert set(table["reason"]) == {"stopped(phi)"}
    written = _rows(out)                     # the file holds the same rows
    assert sorted(float(r["P"]) for r in written) == sorted(FORCES)
    by_force = {float(r["P"]): float(r["t_end"]) for r in written}
    assert [by_force[x] for x in FORCES] == list(table["t_end"])


def test_a_dask_local_cluster_gives_identical_rows(brake, local_sweep):
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(processes=False, n_workers=1, threads_per_worker=2,
                                  dashboard_address=":0") as cluster, \
            distributed.Client(cluster) as client:
        table = md.sweep(brake.mechanism, brake.scenes["braking"], brake.params,
                         {"P": FORCES}, executor=client.get_executor(), progress=False)
    assert table.rows == local_sweep[0].rows
    # ... and those rows are right: t_stop = I omega_0 / (2 f P R) (shoe brake, by hand).
    p = _by_name(brake)
    np.testing.assert_allclose(
        table["t_end"], p["I"] * 100.0 / (2 * p["f"] * np.array(FORCES) * p["R"]), rtol=1e-9)


def test_an_interrupted_sweep_resumes_without_recomputing_finished_points(brake, tmp_path):
    out = tmp_path / "brake.csv"
    grid = {"P": [10.0, 20.0, 25.0, 40.0, 50.0, 80.0, 100.0, 125.0, 200.0, 250.0]}
    scene = brake.scenes["braking"]
    with pytest.raises(KeyboardInterrupt):
        md.sweep(brake.mechanism, scene, brake.params, grid,
                 executor=_Inline(interrupt_after=4), out=out, progress=False)
    finished = [float(r["P"]) for r in _rows(out)]
    assert 4 <= len(finished) < len(grid["P"]) and finished == grid["P"][:len(finished)]
    with open(out, "a") as handle:           # a crash in the middle of writing a row
        handle.write("125.0,8.0")
    resumed = _Inline()
    table = md.sweep(brake.mechanism, scene, brake.params, grid, executor=resumed,
                     out=out, progress=False)
    assert resumed.points == len(grid["P"]) - len(finished)     # only the unfinished points ran
    assert sorted(float(r["P"]) for r in _rows(out)) == sorted(grid["P"])
    np.testing.assert_allclose(table["t_end"], 1000.0 / np.array(grid["P"]), rtol=1e-9)
    again = _Inline()
    md.sweep(brake.mechanism, scene, brake.params, grid, executor=again, out=out,
             progress=False)
    assert again.points == 0


def test_a_failing_point_is_recorded_and_the_others_kept(brake, tmp_path):
    out = tmp_path / "brake.csv"
    table = md.sweep(brake.mechanism, brake.scenes["braking"], brake.params,
                     {"I": [0.4, -0.4, 0.8]}, executor=_Inline(), out=out, progress=False)
    errors = list(table["error"])
    assert errors[0] == errors[2] == ""
    assert "ParameterError" in errors[1] and "negative" in errors[1]
    assert table.failed == [table.rows[1]]
    np.testing.assert_allclose(table["t_end"][[0, 2]], [50.0, 100.0], rtol=1e-9)
    assert [r["error"] != "" for r in _rows(out)] == [False, True, False]
    rerun = _Inline()
    md.sweep(brake.mechanism, brake.scenes["braking"], brake.params,
             {"I": [0.4, -0.4, 0.8]}, executor=rerun, out=out, progress=False)
    assert rerun.points == 0


def test_an_out_file_of_another_sweep_is_refused(brake, tmp_path):
    out = tmp_path / "other.csv"
    out.write_text("k,t_end\n1.0,2.0\n")
    with pytest.raises(SweepFileError, match="another sweep"):
        md.sweep(brake.mechanism, brake.scenes["braking"], brake.params, {"P": [10]},
                 executor=_Inline(), out=out, progress=False)


def test_an_unknown_grid_parameter_names_the_parameters(brake):
    with pytest.raises(ParameterError, match="'Q' is not a parameter.*I, P, R, f"):
        md.sweep(brake.mechanism, brake.scenes["braking"], brake.params, {"Q": [1]},
                 executor=_Inline(), progress=False)


def test_output_peaks_are_found_between_steps():
    """The motor's power M(s) * omega_s * (1 - s), Kloss M(s) = 2 M_k / (s/s_k + s_k/s),
    peaks at one slip whatever the flywheel; the start-up passes through it, so every
    flywheel size must report that peak (from step points alone it came out up to 1.4 %
    low)."""
    from scipy.optimize import minimize_scalar
    model = md.load_model(ROOT / "models" / "motor_startup.py")
    M_k, s_k, omega_s = 200.0, 0.2, 157.08
    values = {str(k): float(v) for k, v in model.params.items()}
    assert (values["M_k"], values["s_k"], values["omega_s"]) == (M_k, s_k, omega_s)
    power = minimize_scalar(lambda s: -2 * M_k / (s / s_k + s_k / s) * omega_s * (1 - s),
                            bounds=(0.01, 1.0), method="bounded", options={"xatol": 1e-12})
    table = md.sweep(model.mechanism, model.scenes["startup"], model.params,
                     {"J_f": [1.0, 2.5, 4.5, 9.0]}, executor=_Inline(), progress=False)
    np.testing.assert_allclose(table["peak:power:motor"], -power.fun, rtol=1e-4)


def test_rows_are_those_of_a_loop_over_simulate_with_the_same_errors(brake):
    """The grid is checked once and the points run from a parameter template: every row
    must equal ``simulate`` at that point, a refused value keep simulate's own error, and
    an initial speed that depends on a swept value (omega_0 = 1000 R) be evaluated per
    point. Reference: t_stop = I omega_0 / (2 f P R) = 500 I / (f P), whatever R;
    the angle omega_0 t_stop / 2."""
    phi = brake.mechanism.coordinates[0]
    R = next(s for s in brake.params if str(s) == "R")
    scene = md.Scene("braking", effects=["shoe"], initial={phi: 0, md.speed(phi): 1000 * R},
                     until=md.stopped(phi))
    grid = {"P": [20.0, -3.0, 40.0], "R": [0.1, 0.2]}
    table = md.sweep(brake.mechanism, scene, brake.params, grid, executor=_Inline(),
                     progress=False)
    p = _by_name(brake)
    for row in table.rows:
        values = {**p, "P": row["P"], "R": row["R"]}
        if row["P"] < 0:
            with pytest.raises(ParameterError) as refused:
                brake.mechanism.simulate(scene, values)
            assert row["error"] == f"ParameterError: {refused.value}"
            assert "P = -3 is negative" in row["error"]
            continue
        result = brake.mechanism.simulate(scene, values)
        assert row["error"] == "" and row["t_end"] == result.t_end
        assert row["final:phi"] == result.y[0][-1] and row["final:phidot"] == result.y[1][-1]
        t_stop = 500 * p["I"] / (p["f"] * row["P"])
        assert row["t_end"] == pytest.approx(t_stop, rel=1e-9)
        assert row["final:phi"] == pytest.approx(1000 * row["R"] * t_stop / 2, rel=1e-9)
    assert len(table.failed) == 2


def test_an_efficiency_at_its_bound_passes_and_one_beyond_gets_the_exact_error():
    """An element rule evaluated on the whole grid column at once: efficiency e1 * e2
    must lie in (0, 1]; 1 exactly passes, 1.25 and 0 are refused with the words a
    plain ``simulate`` uses."""
    phi = md.coordinate("phi")
    e1, e2 = sp.symbols("e1 e2")
    disc = md.Mechanism("geared disc", [phi])
    disc.link("disc", J=1, angle=phi)
    disc.load("drive", 1, along=phi, efficiency=e1 * e2)
    scene = md.Scene("spin", initial={phi: 0, md.speed(phi): 0}, t_end=1)
    table = md.sweep(disc, scene, {"e1": 0.5, "e2": 2.0}, {"e1": [0.25, 0.5, 0.625, 0.0]},
                     executor=_Inline(), progress=False)
    for row in table.rows:
        try:
            disc.simulate(scene, {"e1": row["e1"], "e2": 2.0})
        except ParameterError as error:
            assert row["error"] == f"ParameterError: {error}"
        else:
            assert row["error"] == ""
    assert [row["error"] == "" for row in table.rows] == [True, True, False, False]
    assert "lies outside (0, 1]" in table.rows[2]["error"]
    # the drive delivers eta * 1 N*m to the unit inertia: phi(1 s) = eta / 2
    np.testing.assert_allclose(table["final:phi"][:2], [0.25, 0.5], rtol=1e-9)

"""One backend rule, from the scene and the installation only: the same call gives the
same answer whatever ran before in the process.

The slider-crank at rtol 1e-8 is run in a fresh Python process and in this one after
other work (a work-precision report on it, which runs it with other methods and
tolerances, and another model); the two final states agree to rounding. Before the
rule, ``backend="auto"`` went compiled only when the compiled form happened to be
loaded, and the two differed by 1.1e-6 relative (scipy against compiled).
"""
import json
import os
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

import mechdyn as md

ROOT = Path(__file__).resolve().parents[1]
CRANK = ROOT / "models" / "slider_crank.py"

RUN = """
import json, mechdyn as md
from dataclasses import replace
model = md.load_model({path!r})
scene = replace(model.scenes["startup"], rtol=1e-8, atol=1e-10)
res = model.mechanism.simulate(scene, model.params)
print(json.dumps({{"final": res.y[:, -1].tolist(), "backends": res.stats["backends"]}}))
"""


def crank_run(model):
    scene = replace(model.scenes["startup"], rtol=1e-8, atol=1e-10)
    return model.mechanism.simulate(scene, model.params)


@pytest.fixture(scope="module")
def fresh_process():
    pytest.importorskip("numba")
    done = subprocess.run([sys.executable, "-c", RUN.format(path=str(CRANK))],
                          capture_output=True, text=True, cwd=ROOT, timeout=600,
                          env=dict(os.environ, PYTHONPATH=str(ROOT)))
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout.strip().splitlines()[-1])


def test_the_same_call_gives_the_same_answer_after_other_work(fresh_process):
    crank = md.load_model(CRANK)
    brake = md.load_model(ROOT / "models" / "shoe_brake.py")
    brake.mechanism.simulate(brake.scenes["braking"], brake.params)       # another model
    scene = replace(crank.scenes["startup"], rtol=1e-8, atol=1e-10)
    table = md.work_precision(crank.mechanism, scene, crank.params,
                              methods=["RK45", "DOP853", "auto"], rtols=[1e-6],
                              repeats=1, reference_rtol=1e-10, check_rtol=1e-8)  # a report
    res = crank_run(crank)
    # Each row names where its steps ran: the compiled kernels for DOP853 and auto, as a
    # user's own call of that scene at that tolerance runs.
    assert [row.backend for row in table.rows] == ["scipy", "compiled", "compiled"]
    assert any(line.split()[:2] == ["method", "backend"] for line in str(table).splitlines())
    auto_row = table.rows[2]
    users_call = crank.mechanism.simulate(replace(scene, rtol=1e-6, atol=1e-8), crank.params)
    assert (auto_row.steps, auto_row.nfev) == (users_call.stats["steps"],
                                               users_call.stats["nfev"])
    np.testing.assert_allclose(res.y[:, -1], fresh_process["final"], rtol=1e-14, atol=0)
    assert res.stats["backends"] == fresh_process["backends"] == {
        "compiled": res.stats["steps"]}


def test_a_second_run_and_a_scipy_run_keep_their_backends():
    pytest.importorskip("numba")
    crank = md.load_model(CRANK)
    first, second = crank_run(crank), crank_run(crank)
    assert set(first.stats["backends"]) == set(second.stats["backends"]) == {"compiled"}
    np.testing.assert_array_equal(first.y, second.y)
    scene = replace(crank.scenes["startup"], rtol=1e-8, atol=1e-10, backend="scipy")
    on_scipy = crank.mechanism.simulate(scene, crank.params)
    assert set(on_scipy.stats["backends"]) == {"scipy"}
    # Both meet the tolerance: they agree far better than the 1e-3 the crank's motion
    # would tell apart, but they are different integrations.
    np.testing.assert_allclose(on_scipy.y[:, -1], first.y[:, -1], rtol=1e-5)


def test_a_method_only_scipy_has_runs_on_scipy_and_stuck_friction_compiled():
    pytest.importorskip("numba")
    crank = md.load_model(CRANK)
    scene = replace(crank.scenes["startup"], method="RK45", rtol=1e-6, atol=1e-8)
    assert set(crank.mechanism.simulate(scene, crank.params).stats["backends"]) == {"scipy"}
    # The clutch slips, then sticks at 0.875 s: both compiled (issue 25: the constrained
    # equations of a stuck mode have a compiled form), the same way on every run.
    clutch = md.load_model(ROOT / "models" / "clutch_engagement.py")
    runs = [clutch.mechanism.simulate(clutch.scenes["engage"], clutch.params)
            for _ in range(2)]
    stick = next(e.time for e in runs[0].events if e.kind == "stick")
    assert set(runs[0].stats["backends"]) == {"compiled"}
    assert runs[0].stats["backends"] == runs[1].stats["backends"]
    np.testing.assert_array_equal(runs[0].y, runs[1].y)
    assert 0 < stick < runs[0].t_end and int(np.sum(runs[0].t[1:] > stick)) > 0


def test_blas_runs_single_threaded_inside_a_run_and_the_setting_comes_back():
    threadpoolctl = pytest.importorskip("threadpoolctl")
    from concurrent.futures import ThreadPoolExecutor

    from mechdyn.simulate.threads import single_threaded_blas

    def blas_threads():
        return [lib["num_threads"] for lib in threadpoolctl.threadpool_info()
                if lib["user_api"] == "blas"]
    with threadpoolctl.threadpool_limits(2, user_api="blas"):
        before = blas_threads()
        with single_threaded_blas():
            assert set(blas_threads()) <= {1}
            with ThreadPoolExecutor(2) as pool:     # entered by two threads at once
                inside = list(pool.map(lambda _: _nested(single_threaded_blas,
                                                         blas_threads), range(4)))
            assert set(blas_threads()) <= {1}
        assert blas_threads() == before
    assert all(set(threads) <= {1} for threads in inside)


def _nested(context, probe):
    with context():
        return probe()


def test_sweep_points_give_the_same_rows_in_this_process_and_in_workers(monkeypatch):
    """A sweep at its defaults runs points here first, then on worker processes: where a
    point runs does not change its row (the same rule, the same compiled code)."""
    from mechdyn.analyse import sweeps
    drive = md.load_model(ROOT / "models" / "two_mass_drive.py")
    grid = {"k": [1000.0, 2500.0, 4000.0]}
    here = md.sweep(drive.mechanism, drive.scenes["start"], drive.params, grid,
                    progress=False)
    monkeypatch.setattr(sweeps, "HERE_SECONDS", 0.0)        # every point to the workers
    there = md.sweep(drive.mechanism, drive.scenes["start"], drive.params, grid,
                     progress=False)
    assert here.rows == there.rows and not here.failed



# Every bundled scene has a compiled form at its defaults, closed loops included
# (docs/kernels.md, "Which backend a run takes").
BUNDLED = sorted(path.stem for path in (ROOT / "models").glob("*.py"))


@pytest.mark.slow
@pytest.mark.parametrize("name", BUNDLED)
def test_every_bundled_scene_runs_compiled_at_its_defaults(name):
    pytest.importorskip("numba")
    model = md.load_model(ROOT / "models" / f"{name}.py")
    for scene in (s for s in model.scenes.values() if s.initial):
        runs = [model.mechanism.simulate(scene, model.params) for _ in range(2)]
        assert set(runs[0].stats["backends"]) == {"compiled"}, (scene.name, runs[0].stats)
        assert runs[1].stats["backends"] == runs[0].stats["backends"]
        np.testing.assert_array_equal(runs[1].y, runs[0].y)

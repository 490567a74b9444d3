"""Sweeps on a real Dask cluster, as users run them: a ``dask scheduler`` and two ``dask
worker`` processes on 127.0.0.1 (``tests/dask_cluster.py``), reached through the command
line (``mechdyn sweep ... --dask ADDRESS``) and the Python API
(``md.sweep(..., executor=client.get_executor())``).

References: a point's computation does not depend on the process it runs in, so the
cluster's rows must equal, bit for bit, those of a sweep in the calling process and of a
loop over ``simulate``; the shoe brake stops at t = I omega_0 / (2 f P R) = 1000 / P
(its model file), the preloaded spring swings as phi_e + (phi_0 - phi_e) cos(w t),
phi_e = q0 - M0 / k, w = sqrt(k / I).
"""
import csv
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

import mechdyn as md
from mechdyn.analyse.sweeps import SweepError

distributed = pytest.importorskip("distributed")
# A scheduler and two workers for the module: about 25 s of one core; in CI's suite,
# not in the quick loop (the quick loop stays under two minutes on 2 cores).
pytestmark = pytest.mark.slow

from dask_cluster import Cluster  # noqa: E402
from mounts import can_confine  # noqa: E402  (after the skip: needs distributed)

ROOT = Path(__file__).resolve().parents[1]
BRAKE = str(ROOT / "models" / "shoe_brake.py")
SCENES = [("shoe_brake", "braking", "P", list(np.linspace(10.0, 100.0, 12))),
          ("slider_crank", "startup", "m_3", [0.5, 1.0, 1.5, 2.0, 3.0, 4.0]),
          ("two_mass_drive", "start", "k", [1000.0, 1500.0, 2000.0, 3000.0, 4000.0])]


@pytest.fixture(scope="module")
def cluster(tmp_path_factory):
    running = Cluster(tmp_path_factory.mktemp("dask"))
    try:
        yield running.start(workers=2)
    finally:
        running.close()


@pytest.fixture
def client(cluster):
    with cluster.client() as connected:
        yield connected


def _rows(path):
    with open(path, newline="") as handle:
        return list(csv.DictReader(handle))


def _local(model, scene, grid, **options):
    return md.sweep(model.mechanism, model.scenes[scene], model.params, grid,
                    progress=False, **options)


def _cli(*arguments, timeout=120):
    """``mechdyn ARGUMENTS`` as a user runs it, in another process."""
    script = Path(sys.executable).with_name("mechdyn")
    command = [str(script)] if script.is_file() else [sys.executable, "-m", "mechdyn.cli.command"]
    path = os.pathsep.join(filter(None, [str(Path(md.__file__).parents[1]),
                                         os.environ.get("PYTHONPATH")]))
    return subprocess.Popen([*command, *arguments], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, cwd=ROOT,
                            env={**os.environ, "PYTHONPATH": path})


def _wait_for_rows(path, count, process, timeout=60):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline and process.poll() is None:
        if path.is_file() and len(path.read_text().splitlines()) > count:
            return
        time.sleep(0.01)
    raise AssertionError(f"no {count} rows in {path} before the sweep ended or {timeout} s")


def _busy_worker(client, run, timeout=60):
    """The process id of a worker that is running a task of the sweep ``run``."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline and run.poll() is None:
        busy = [worker for worker, tasks in client.processing().items() if tasks]
        pids = client.run(os.getpid, workers=busy[:1]) if busy else {}
        if pids:
            return next(iter(pids.values()))
        time.sleep(0.005)
    raise AssertionError("no worker was busy before the sweep ended")


# ---------------------------------------------------------------- rows
@pytest.mark.parametrize("name, scene, parameter, values", SCENES, ids=[s[0] for s in SCENES])
def test_rows_on_the_cluster_equal_local_rows_and_a_loop_over_simulate_bitwise(
        cluster, client, name, scene, parameter, values):
    model = md.load_model(name)
    grid = {parameter: values}
    remote = _local(model, scene, grid, executor=client.get_executor())
    local = _local(model, scene, grid)
    assert remote.rows == local.rows and not remote.failed
    symbol = next(s for s in model.params if str(s) == parameter)
    for value, row in zip(values, remote.rows):
        result = model.mechanism.simulate(model.scenes[scene], {**model.params, symbol: value})
        assert row["t_end"] == result.t_end and row["reason"] == result.reason
        assert [row[f"final:{n}"] for n in result.state_names] == \
            [float(y[-1]) for y in result.y]
    if name == "shoe_brake":
        np.testing.assert_allclose(remote["t_end"], 1000.0 / np.array(values), rtol=1e-9)


def test_the_command_line_on_the_cluster_writes_the_rows_of_a_local_sweep(cluster, tmp_path):
    out = tmp_path / "brake.csv"
    run = _cli("sweep", BRAKE, "--scene", "braking", "--grid", "P=10:100:300",
               "--dask", cluster.address, "--out", str(out))
    stdout, stderr = run.communicate(timeout=120)
    assert run.returncode == 0, stderr
    written = _rows(out)
    forces = [float(row["P"]) for row in written]
    assert sorted(forces) == list(np.linspace(10.0, 100.0, 300))
    local = _local(md.load_model(BRAKE), "braking", {"P": forces})
    assert [{c: row[c] for c in ("t_end", "final:phi", "final:phidot")} for row in local.rows] \
        == [{c: float(row[c]) for c in ("t_end", "final:phi", "final:phidot")}
            for row in written]


def test_each_worker_loads_the_compiled_scene_once_and_compiles_nothing(cluster, client):
    def count_loads():
        from mechdyn.analyse import sweep_points
        original = sweep_points._load_kernels
        sweep_points.loads = 0

        def counted(*args):
            sweep_points.loads += 1
            return original(*args)
        sweep_points._load_kernels = counted

    def loads():
        from mechdyn.analyse import sweep_points
        return sweep_points.loads

    client.run(count_loads)
    model = md.load_model("two_mass_drive")            # a scene no earlier test swept
    grid = {"k": list(np.linspace(1000.0, 4000.0, 40)), "M": [10.0, 20.0]}
    executor = client.get_executor()
    first = _local(model, "start_undamped", grid, executor=executor)
    again = _local(model, "start_undamped", grid, executor=executor)
    assert first.rows == again.rows and len(first) == 80
    counts = client.run(loads)
    assert sorted(counts.values()) == [1, 1], counts     # 160 points, 1 load a worker
    for number in (1, 2):
        assert "compiling" not in cluster.log(f"worker{number}")


# ---------------------------------------------------------------- element classes
def _spring_mechanism(spring_class, scene_backend="auto"):
    phi = md.coordinate("phi")
    I, k, q0, M0 = sp.symbols("I k q_0 M_0", positive=True)
    disc = md.Mechanism("preloaded disc", [phi])
    disc.link("disc", J=I, angle=phi)
    disc.add(spring_class("torsion", k=k, q0=q0, M0=M0, along=phi))
    swing = md.Scene("swing", initial={phi: 1, md.speed(phi): 0}, t_end=3,
                     backend=scene_backend)
    return disc, swing, {I: 2, k: 8, q0: 0.5, M0: 2}


def test_an_element_class_the_workers_import_runs_on_the_cluster(client):
    from test_custom_element import PreloadedSpring     # the README's; tests/ is on their path
    disc, swing, params = _spring_mechanism(PreloadedSpring)
    grid = {"k": [2.0, 4.0, 8.0, 16.0]}
    remote = md.sweep(disc, swing, params, grid, executor=client.get_executor(),
                      progress=False)
    local = md.sweep(disc, swing, params, grid, progress=False)
    assert remote.rows == local.rows and not remote.failed
    k = np.array(grid["k"])
    settled = 0.5 - 2 / k
    expected = settled + (1 - settled) * np.cos(np.sqrt(k / 2) * 3)
    np.testing.assert_allclose(remote["final:phi"], expected, rtol=0, atol=1e-6)


def test_an_element_class_the_workers_cannot_import_is_refused_before_the_first_row(
        cluster, client, tmp_path, monkeypatch):
    folder = tmp_path / "only_here"                 # on this process's path, not theirs
    folder.mkdir()
    (folder / "private_elements.py").write_text(
        "from test_custom_element import PreloadedSpring as Importable\n\n\n"
        "class PreloadedSpring(Importable):\n    pass\n")
    monkeypatch.syspath_prepend(str(folder))
    from private_elements import PreloadedSpring
    disc, swing, params = _spring_mechanism(PreloadedSpring, "scipy")
    out, grid = tmp_path / "swing.csv", {"k": [2.0, 4.0, 8.0, 16.0]}
    with pytest.raises(SweepError, match=r"(?s)cannot load the sweep \(ModuleNotFoundError.*"
                       r"private_elements\.PreloadedSpring.*install their module where "
                       r"the workers run"):
        md.sweep(disc, swing, params, grid, executor=client.get_executor(), out=out,
                 progress=False)
    assert _rows(out) == []
    md.sweep(disc, swing, params, {"k": grid["k"][:2]}, out=out, fresh=True,
             progress=False)                        # two rows computed here ...
    written = out.read_text()
    with pytest.raises(SweepError, match="cannot load the sweep"):   # ... not resumed there
        md.sweep(disc, swing, params, {"k": grid["k"][:2] + grid["k"][2:]}, out=out,
                 executor=client.get_executor(), progress=False)
    assert out.read_text() == written


def test_an_element_class_defined_in_a_function_is_refused_before_the_first_row(
        client, tmp_path):
    from test_custom_element import PreloadedSpring

    class LocalSpring(PreloadedSpring):
        pass
    disc, swing, params = _spring_mechanism(LocalSpring, "scipy")
    out = tmp_path / "swing.csv"
    with pytest.raises(SweepError, match="'torsion' cannot be pickled.*module level"):
        md.sweep(disc, swing, params, {"k": [2.0, 4.0]}, executor=client.get_executor(),
                 out=out, progress=False)
    assert _rows(out) == []


# ---------------------------------------------------------------- faults
def test_a_worker_killed_mid_sweep_loses_and_repeats_no_row(cluster, client, tmp_path):
    out, count = tmp_path / "brake.csv", 3000
    run = _cli("sweep", BRAKE, "--scene", "braking", "--grid", f"P=10:100:{count}",
               "--dask", cluster.address, "--out", str(out))
    try:
        _wait_for_rows(out, 1, run)
        victim = _busy_worker(client, run)
        os.kill(victim, 9)          # the worker process, amid a task; its nanny restarts it
        rows_at_the_kill = len(_rows(out))
        stdout, stderr = run.communicate(timeout=120)
    finally:
        run.kill()
    assert run.returncode == 0, stderr
    assert rows_at_the_kill < count
    written = _rows(out)
    forces = [float(row["P"]) for row in written]
    assert len(forces) == len(set(forces)) == count
    assert sorted(forces) == list(np.linspace(10.0, 100.0, count))
    np.testing.assert_allclose([float(r["t_end"]) for r in written], 1000 / np.array(forces),
                               rtol=1e-9)
    sample = forces[::97]                            # and bit for bit those of a local run
    local = _local(md.load_model(BRAKE), "braking", {"P": sample})
    by_force = {float(r["P"]): float(r["final:phi"]) for r in written}
    assert [by_force[p] for p in sample] == list(local["final:phi"])


def test_a_lost_scheduler_stops_the_sweep_and_a_rerun_completes_its_file(cluster, tmp_path):
    out, count = tmp_path / "brake.csv", 3000
    arguments = ["sweep", BRAKE, "--scene", "braking", "--grid", f"P=10:100:{count}",
                 "--out", str(out)]
    run = _cli(*arguments, "--dask", cluster.address)
    try:
        _wait_for_rows(out, 1, run)
        cluster.kill_scheduler()
        stdout, stderr = run.communicate(timeout=120)
    finally:
        run.kill()
    assert run.returncode != 0
    assert "SweepError" in stderr or "sweep:" in stderr
    assert "rows are kept" in stderr and "rerun the same sweep" in stderr, stderr
    kept = [float(row["P"]) for row in _rows(out)]
    assert len(kept) == len(set(kept)) < count
    cluster.restart()
    rerun = _cli(*arguments, "--dask", cluster.address)
    stdout, stderr = rerun.communicate(timeout=120)
    assert rerun.returncode == 0, stderr
    forces = [float(row["P"]) for row in _rows(out)]
    assert forces[:len(kept)] == kept                # resumed, not recomputed
    assert sorted(forces) == list(np.linspace(10.0, 100.0, count))
    np.testing.assert_allclose([float(r["t_end"]) for r in _rows(out)],
                               1000 / np.array(forces), rtol=1e-9)


@pytest.mark.slow          # the worker compiles the kernels and the scene in memory: 30-60 s
def test_a_worker_without_a_usable_cache_folder_compiles_in_memory_and_gives_the_rows(
        cluster, tmp_path):
    blocked = tmp_path / "a file"
    blocked.write_text("not a folder\n")
    cluster.restart(workers=0)
    try:
        cluster.add_worker(env={"MECHDYN_CACHE": str(blocked / "cache")})
        cluster.wait_for_workers(1)
        model = md.load_model(BRAKE)
        grid = {"P": list(np.linspace(10.0, 100.0, 20))}
        with cluster.client() as connected:
            remote = _local(model, "braking", grid, executor=connected.get_executor())
        assert remote.rows == _local(model, "braking", grid).rows and not remote.failed
        log = cluster.log("worker1")
        assert "CacheWarning" in log and "compiling the integration kernels" in log
    finally:
        cluster.restart()


def test_workers_with_a_read_only_and_a_full_cache_folder_compile_in_memory_and_give_the_rows(
        cluster, tmp_path):
    """Each worker's cache folder holds the compiled kernels (a copy of this session's)
    but not the scene, and refuses writes: the scene is compiled in memory, once per
    worker, with the cache's warning, and the rows are right."""
    folders = {how: tmp_path / how for how in ("read-only", "full")}
    for folder in folders.values():
        folder.mkdir()
    if not can_confine(folders["full"]):
        pytest.skip("no mount namespaces here (unshare --mount): a read-only or full "
                    "folder cannot be made for one process")
    seed = tmp_path / "seed"
    session_cache = Path(os.environ["MECHDYN_CACHE"])
    shutil.copytree(session_cache / "kernels", seed / "kernels")
    shutil.copy2(session_cache / "key", seed / "key")
    cluster.restart(workers=0)
    try:
        for how, folder in folders.items():
            cluster.add_worker(env={"MECHDYN_CACHE": str(folder)}, confine=(folder, how, seed))
        cluster.wait_for_workers(2)
        model = md.load_model(BRAKE)
        grid = {"P": list(np.linspace(10.0, 100.0, 2000))}
        with cluster.client() as connected, distributed.get_task_stream(connected) as tasks:
            remote = _local(model, "braking", grid, executor=connected.get_executor())
        assert remote.rows == _local(model, "braking", grid).rows and not remote.failed
        assert len({task["worker"] for task in tasks.data}) == 2        # both ran points
        reasons = {"worker1": "it is read-only", "worker2": "the disk is full"}
        for worker, reason in reasons.items():          # each compiled the scene in
            log = cluster.log(worker)                    # memory, saying why
            assert f"cannot write to it ({reason})" in log, log[-2000:]
        assert sorted(p.name for p in folders["read-only"].iterdir()) == ["kernels", "key"]
    finally:
        cluster.restart()

"""Sweep throughput on a two-worker Dask cluster against local processes, in one run.

    python benchmarks/cluster_throughput.py [--points 2000] [--repeats 3]

The shoe brake's braking scene over ``--points`` values of P (10 to 100 N), each figure
the whole ``md.sweep(...)`` call as a user waits for it (grid checks, batching, rows
collected in the calling process; no ``out`` file), in points per second:

* ``workers=1`` and ``workers=2``: local worker processes, started, sent the job and
  ended inside every call (that is how a local sweep runs);
* the default sweep (the calling process for the first second, then local processes);
* the cluster (``dask scheduler`` and two ``dask worker --nthreads 1`` processes with
  nannies on 127.0.0.1, as ``tests/dask_cluster.py`` starts them), through
  ``client.get_executor()``: "cold", the first sweep after the workers started (each
  worker unpickles the job and loads the compiled kernels from the shared cache), and
  "warm", the same sweep again (the workers hold the job: steady state);
* a plain loop over ``simulate`` in the calling process (the obvious alternative).

The runs of one repeat are interleaved; each figure is the best of the repeats (the
machine is shared). Also printed: the cost of a point inside a worker against the same
points in the calling process (a batch of 400 in ``_run_points``, its first point not
timed; alternating, the best of ``--repeats`` each), the same with both workers computing
at once (what two processes sharing the machine's cores give: the ceiling of any
two-worker figure), and the cluster's tasks (from Dask's task stream): how many, points per task, and the share
of the warm sweep's time the workers spent computing.
"""
from __future__ import annotations

import argparse
import math
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))

import mechdyn as md  # noqa: E402


def per_point_ms(run_points, job_blob, digest, forces):
    """ms a point in ``run_points`` (the first point of the batch not timed)."""
    rows, seconds, timed = run_points(digest, job_blob, [(p,) for p in forces])
    return 1e3 * seconds / timed


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, default=2000)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args(argv)
    os.environ.setdefault("PYTHONPATH", str(ROOT))
    from distributed import get_task_stream
    from dask_cluster import Cluster
    from mechdyn.analyse import sweep_points

    model = md.load_model(ROOT / "models" / "shoe_brake.py")
    mech, scene, params = model.mechanism, model.scenes["braking"], model.params
    forces = list(np.linspace(10.0, 100.0, args.points))
    grid = {"P": forces}
    symbol = next(s for s in params if str(s) == "P")
    reference = md.sweep(mech, scene, params, grid, progress=False)   # compiled, loaded

    def loop():
        return [mech.simulate(scene, {**params, symbol: p}) for p in forces]

    def local(workers):
        return lambda: md.sweep(mech, scene, params, grid, workers=workers, progress=False)

    best = {}

    def timed(name, run):
        started = time.perf_counter()
        table = run()
        seconds = time.perf_counter() - started
        if name != "loop":
            assert table.rows == reference.rows, name
        best[name] = min(best.get(name, float("inf")), seconds)

    with tempfile.TemporaryDirectory() as folder:
        cluster = Cluster(folder).start(workers=2)
        try:
            with cluster.client() as client:
                executor = client.get_executor()
                on_cluster = lambda: md.sweep(mech, scene, params, grid,  # noqa: E731
                                              executor=executor, progress=False)
                timed("cluster, cold", on_cluster)
                for _ in range(args.repeats):
                    for name, run in (("loop", loop), ("workers=1", local(1)),
                                      ("workers=2", local(2)), ("default", local(None)),
                                      ("cluster, warm", on_cluster)):
                        timed(name, run)
                with get_task_stream(client) as stream:
                    started = time.perf_counter()
                    on_cluster()
                    wall = time.perf_counter() - started
                tasks = [t for t in stream.data if str(t["key"]).startswith("_run_points")]
                job = _job_of(mech, scene, params)
                remote = here = float("inf")
                for _ in range(args.repeats):          # alternating, the best of each
                    remote = min(remote, client.submit(
                        per_point_ms, sweep_points._run_points, *job, forces[:400],
                        pure=False).result())
                    here = min(here, per_point_ms(sweep_points._run_points, *job,
                                                  forces[:400]))
                together = float("inf")                # both workers computing at once
                for _ in range(args.repeats):
                    pair = [client.submit(per_point_ms, sweep_points._run_points, *job,
                                          forces[:400], pure=False, workers=[address])
                            for address in client.scheduler_info()["workers"]]
                    together = min(together, max(future.result() for future in pair))
        finally:
            cluster.close()

    rate = {name: args.points / seconds for name, seconds in best.items()}
    print(f"shoe brake, braking, {args.points} points of P; best of {args.repeats}; "
          f"load average {os.getloadavg()[0]:.1f} at the end\n")
    print("| run | s | points/s | vs workers=1 |")
    print("|---|---|---|---|")
    for name in ("loop", "default", "workers=1", "workers=2", "cluster, cold", "cluster, warm"):
        print(f"| {name} | {best[name]:.2f} | {rate[name]:,.0f} | "
              f"{rate[name] / rate['workers=1']:.2f}x |")
    computing = sum(stop - start for t in tasks for kind, start, stop in
                    ((s["action"], s["start"], s["stop"]) for s in t["startstops"])
                    if kind == "compute")
    print(f"\nper point: {remote:.3f} ms in a worker, {here:.3f} ms in this process "
          f"({remote / here:.2f}x)")
    print(f"both workers at once: {together:.3f} ms a point each; the most any two "
          f"processes can give here over one: 2 x {here:.3f} / {together:.3f} = "
          f"{2 * here / together:.2f}x")
    print(f"warm sweep on the cluster: {len(tasks)} tasks (one without points), "
          f"{args.points / max(len(tasks) - 1, 1):.0f} points a task; workers computing "
          f"{computing:.2f} s of 2 x {wall:.2f} s ({computing / (2 * wall):.0%})")
    print(f"\ncluster (warm) / one local process (workers=1): "
          f"{rate['cluster, warm'] / rate['workers=1']:.2f}x (target >= 1.6x); "
          f"/ the default sweep: {rate['cluster, warm'] / rate['default']:.2f}x")


def _job_of(mech, scene, params):
    """The pickled job a sweep of P sends its workers, and its digest."""
    import hashlib
    import pickle

    from mechdyn.analyse.sweep_grid import Plan
    from mechdyn.analyse.sweep_points import _Job
    from mechdyn.compile.compiler import compile_scene
    from mechdyn.declare.parameters import ParameterSet
    compiled = compile_scene(mech, scene)
    values = ParameterSet(params, mechanism=mech, scene=scene)
    plan = Plan.of(mech, scene, None, None, 2 * math.pi, values)     # a sweep's defaults
    blob = pickle.dumps(_Job(mech, scene, dict(values.numbers), ("P",), compiled.key,
                             compiled.meta, compiled.source, {}, plan))
    return blob, hashlib.sha256(blob).hexdigest()


if __name__ == "__main__":
    main()

"""Dense output, plotting and memory: what a long run costs after it has run.

    python benchmarks/throughput.py [--repeats 3]

* Dense output: ``res.at(times)`` for 1e5 evenly spaced times, against the wall time of
  the ``simulate`` call that produced ``res`` (issue 15: under 20 %). Runs: the
  slider-crank (models/slider_crank.py) at the default tolerances over 150 s on the
  compiled backend (about 1e5 steps) and over 20 s on scipy, and the three-mass drive
  (0.5 s, a few hundred steps) on both.
* Plotting: ``res.plot(path)`` (PNG, defaults) of the 1e5-step run, the first plot of
  the process (matplotlib imported inside) and a second one (issue 15: under 2 s).
* Memory per step: the bytes a ``Result`` keeps per accepted step, and the peak during
  the run per step (``tracemalloc``, which sees numpy's buffers), per backend and
  method, for 2 states (slider-crank, 5 s) and 6 states (three-mass drive, 2 s), at
  rtol 1e-8. A compiled run's kernel fills buffers of 20,000 steps per call; what a
  short run keeps beyond its steps shows here.

Times are minima over the repeats; the compiled functions are loaded before the timing.
"""
from __future__ import annotations

import argparse
import gc
import sys
import tempfile
import time
import tracemalloc
from dataclasses import replace
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path[:0] = [str(ROOT), str(HERE)]

import mechdyn as md  # noqa: E402

POINTS = 100_000
PLOT_TARGET, DENSE_TARGET = 2.0, 0.20
# label: (model file, scene, t_end or None, backend, method)
DENSE_RUNS = {"slider-crank 150 s, compiled": ("models/slider_crank.py", "startup", 150.0,
                                               "compiled", "auto"),
              "slider-crank 20 s, scipy": ("models/slider_crank.py", "startup", 20.0,
                                           "scipy", "auto"),
              "three-mass drive 0.5 s, compiled": ("benchmarks/elastic_drive.py", "start",
                                                   None, "compiled", "auto"),
              "three-mass drive 0.5 s, scipy": ("benchmarks/elastic_drive.py", "start",
                                                None, "scipy", "auto")}
MEMORY_RUNS = [(model, scene, t_end, backend, method)
               for model, scene, t_end in (("models/slider_crank.py", "startup", 5.0),
                                           ("benchmarks/elastic_drive.py", "start", 2.0))
               for backend, method in (("scipy", "DOP853"), ("scipy", "RK45"),
                                       ("scipy", "Radau"), ("compiled", "DOP853"),
                                       ("compiled", "Rodas5P"))]


def setup(model_file, scene_name, t_end, backend, method, **options):
    model = md.load_model(ROOT / model_file)
    scene = model.scenes[scene_name]
    scene = replace(scene, backend=backend, method=method, **options,
                    **({} if t_end is None else {"t_end": t_end}))
    compiled = model.mechanism.compile(scene)
    if backend == "compiled":
        from mechdyn.compile.numba_model import numba_functions
        numba_functions(compiled)
    return model, scene


def best(run, repeats):
    times, value = [], None
    for _ in range(repeats):
        started = time.perf_counter()
        value = run()
        times.append(time.perf_counter() - started)
    return min(times), value


def dense(repeats):
    rows = []
    for label, spec in DENSE_RUNS.items():
        model, scene = setup(*spec)
        seconds, res = best(lambda: model.mechanism.simulate(scene, model.params), repeats)
        times = np.linspace(res.t[0], res.t[-1], POINTS)
        at = best(lambda: res.at(times), repeats)[0]
        rows.append({"label": label, "steps": res.stats["steps"], "run": seconds,
                     "at": at, "method": res.stats["method"], "result": res})
    return rows


def plotting(result):
    """(first plot s, second plot s) of ``result``, PNG, in a temporary folder."""
    import matplotlib
    matplotlib.use("Agg")
    with tempfile.TemporaryDirectory() as folder:
        out = []
        for k in range(2):
            started = time.perf_counter()
            figure = result.plot(Path(folder) / f"run{k}.png")
            out.append(time.perf_counter() - started)
            import matplotlib.pyplot as plt
            plt.close(figure)
    return out


def memory():
    rows = []
    for spec in MEMORY_RUNS:
        model, scene = setup(*spec, rtol=1e-8, atol=1e-10)
        model.mechanism.simulate(scene, model.params)         # warm every lazy import
        gc.collect()
        tracemalloc.start()
        before = tracemalloc.get_traced_memory()[0]
        res = model.mechanism.simulate(scene, model.params)
        gc.collect()
        kept, peak = tracemalloc.get_traced_memory()
        tracemalloc.stop()
        steps = res.stats["steps"]
        rows.append({"model": Path(spec[0]).stem, "states": len(res.y), "backend": spec[3],
                     "method": res.stats["method"], "steps": steps,
                     "kept": (kept - before) / steps, "peak": (peak - before) / steps})
        del res
    return rows


def report(dense_rows, plots, memory_rows) -> str:
    lines = [f"Dense output: `res.at(times)` for {POINTS:,} even times against the run "
             "that produced `res`:", "",
             "| run | method | steps | run s | 1e5 points s | share of the run |",
             "|---|---|---|---|---|---|"]
    for r in dense_rows:
        lines.append(f"| {r['label']} | {r['method']} | {r['steps']:,} | {r['run']:.3f} | "
                     f"{r['at']:.3f} | {r['at'] / r['run'] * 100:.1f} % |")
    long_run = dense_rows[0]
    share = long_run["at"] / long_run["run"]
    lines += ["", f"Target (the {long_run['steps']:,}-step run): under "
              f"{DENSE_TARGET * 100:.0f} % of the run: {share * 100:.1f} % "
              f"({'met' if share < DENSE_TARGET else '**missed**'}).", "",
              f"Plotting the {long_run['steps']:,}-step run (`res.plot('run.png')`, "
              f"defaults): first plot of the process {plots[0]:.2f} s (imports "
              f"matplotlib), again {plots[1]:.2f} s (target < {PLOT_TARGET:g} s: "
              f"{'met' if plots[0] < PLOT_TARGET else '**missed**'}).", "",
              "Memory per accepted step (bytes; kept: held by the `Result`; peak: the "
              "largest traced allocation during the run, per step):", "",
              "| model (states) | backend | method | steps | kept B/step | peak B/step |",
              "|---|---|---|---|---|---|"]
    for r in memory_rows:
        lines.append(f"| {r['model']} ({r['states']}) | {r['backend']} | {r['method']} | "
                     f"{r['steps']:,} | {r['kept']:.0f} | {r['peak']:.0f} |")
    return "\n".join(lines)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args(argv)
    dense_rows = dense(args.repeats)
    plots = plotting(dense_rows[0]["result"])
    memory_rows = memory()
    text = report(dense_rows, plots, memory_rows)
    print(text)
    for row in dense_rows:
        row.pop("result")
    return {"text": text, "dense": dense_rows, "plots": plots, "memory": memory_rows}


if __name__ == "__main__":
    main()

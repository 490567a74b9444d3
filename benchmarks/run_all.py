"""Every measurement in one run; writes benchmarks/RESULTS.md.

    python benchmarks/run_all.py [--repeats 3] [--runs 10] [--skip-methods]
                                 [--skip-hard-cases]

1. Derivation: benchmarks/derive.py (mechdyn vs LagrangesMethod), its output verbatim,
   and its chain ratios against the previous RESULTS.md (no regression).
2. Simulation at matched accuracy (benchmarks/simulate.py): mechdyn auto, scipy and
   compiled, the obvious path and the compiled floor on the slider-crank, the three-mass
   drive and the shoe brake.
3. Whole process (benchmarks/process.py): ``mechdyn simulate`` cold and warm, paired
   with ``python -c "import numpy, scipy.integrate"``.
4. Dense output, plotting and memory per step (benchmarks/throughput.py).
5. Sweeps (benchmarks/sweep.py): cost per point against a plain loop, 1 and 2 workers.
6. Per bundled scene (models/*.py), each in a fresh process with an empty cache:
   derivation, code generation, RHS per call, simulation; ``mechdyn simulate`` cold and
   warm.
7. Method selection: per bundled scene, the fastest solve_ivp method meeting each target
   error (``md.work_precision``), next to what ``method="auto"`` achieves.
8. The hard-case matrix (benchmarks/hard_case_matrix.py, which also writes
   benchmarks/HARD_CASES.md): its headline table.

All ratios in RESULTS.md come from this one run. Times are minima (or medians, where
said) over repeats; the machine's load at the start and the end is in the header.
"""
from __future__ import annotations

import argparse
import json
import os
import platform
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path[:0] = [str(ROOT), str(HERE)]

import mechdyn as md  # noqa: E402

METHODS = ["RK45", "DOP853", "LSODA", "Radau", "BDF"]
RTOLS = [1e-3, 1e-5, 1e-7, 1e-9]
TARGETS = [1e-3, 1e-5, 1e-7]
PROCESS_SCENES = [("models/shoe_brake.py", "braking"), ("models/slider_crank.py", "startup"),
                  ("benchmarks/elastic_drive.py", "start")]


# ------------------------------------------------------------ 6. one scene, in-process
def one_scene(model_path, scene_name, repeats):
    """Stage times of one scene in this (fresh) process, as a dict."""
    import timeit
    started = time.perf_counter()
    model = md.load_model(model_path)
    loaded = time.perf_counter()
    scene = model.scenes[scene_name]
    model.mechanism.equations(scene)
    derived = time.perf_counter()
    compiled = model.mechanism.compile(scene)
    generated = time.perf_counter()
    p = compiled.parameter_vector(model.params)
    y = [0.1 * (k + 1) for k in range(len(compiled.state_names))]
    rhs = min(timeit.repeat(lambda: compiled.rhs(0.0, y, p), number=2000,
                            repeat=repeats)) / 2000
    runs = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        result = model.mechanism.simulate(scene, model.params)
        runs.append(time.perf_counter() - t0)
    return {"load": loaded - started, "derive": derived - loaded,
            "compile": generated - derived, "rhs": rhs, "simulate": min(runs),
            "method": result.stats["method"], "steps": result.stats["steps"],
            "nfev": result.stats["nfev"], "backends": "+".join(result.stats["backends"]),
            "floor": floor_time(compiled, model.params, result, repeats)}


def floor_time(compiled, params, result, repeats):
    """The numba RK4 floor (benchmarks/kernels.py) with the scene's compiled RHS and as
    many RHS evaluations as ``result``; None without a compiled form."""
    import numpy as np
    from kernels import best_time, rk4_floor
    from mechdyn.compile.numba_model import numba_functions
    functions = numba_functions(compiled)
    if functions is None:
        return None
    p = np.asarray(compiled.parameter_vector(params), dtype=float)
    slots = len(compiled.param_names)                 # friction signs: sliding forward
    p[slots:slots + len(compiled.frictions)] = 1.0
    y0 = np.ascontiguousarray(result.y[:, 0], dtype=float)
    steps = max(1, result.stats["nfev"] // 4)
    floor = rk4_floor(functions.rhs)
    floor(y0, p, result.t_end, 1)                     # numba compiles
    return best_time(lambda: floor(y0, p, result.t_end, steps), max(repeats, 3))[0]


SKIPPED = []     # (model file, why) of bundled models that do not load


def bundled_scenes():
    for path in sorted((ROOT / "models").glob("*.py")):
        try:
            names = list(md.load_model(path).scenes)
        except md.MechdynError as error:
            SKIPPED.append((path.name, str(error)))
            continue
        yield from ((path, name) for name in names)


def stage_table(repeats):
    import process
    base = process.yardstick()
    lines = [f"Yardstick `python -c \"import numpy, scipy.integrate\"`: {base:.2f} s "
             "(median of 5).", "",
             "| model / scene | derive ms | compile ms | RHS us | simulate ms (method, "
             "steps, backend) | floor ms | x floor | cold s | warm s | warm / yardstick |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    worst = 0.0
    for path, name in bundled_scenes():
        with tempfile.TemporaryDirectory() as cache:
            env = dict(os.environ, MECHDYN_CACHE=cache)
            done = subprocess.run([sys.executable, __file__, "--one", str(path), name,
                                   "--repeats", str(repeats)], env=env, cwd=ROOT,
                                  capture_output=True, text=True)
        if done.returncode:
            lines.append(f"| {path.stem} / {name} | failed: "
                         f"{done.stderr.strip().splitlines()[-1][:80]} | | | | | | | | |")
            continue
        s = json.loads(done.stdout.strip().splitlines()[-1])
        cold, warm = process.whole_process(path, name, repeats)
        worst = max(worst, warm / base)
        lines.append(f"| {path.stem} / {name} | {s['derive'] * 1e3:.0f} | "
                     f"{s['compile'] * 1e3:.0f} | {s['rhs'] * 1e6:.1f} | "
                     f"{s['simulate'] * 1e3:.1f} ({s['method']}, {s['steps']}, "
                     f"{s['backends']}) | {_floor_cells(s)} | {cold:.2f} | {warm:.2f} | "
                     f"{warm / base:.2f}x |")
        print(lines[-1], flush=True)
    lines += ["", f"Worst warm process: {worst:.2f}x the yardstick (unpaired medians)."]
    return "\n".join(lines)


def _floor_cells(s):
    if s["floor"] is None:
        return "no compiled form | -"
    return f"{s['floor'] * 1e3:.2f} | {s['simulate'] / s['floor']:.1f}x"


def previous_section(previous_text, title):
    """A section of the previous RESULTS.md kept when its part is skipped, marked as such."""
    match = re.search(rf"^## {re.escape(title)}.*?(?=^## |\Z)", previous_text,
                      re.S | re.M)
    if not match:
        return []
    stamp = re.search(r"\d{4}-\d\d-\d\d \d\d:\d\d", previous_text)
    body = match.group(0).strip().split("\n", 1)
    return [body[0], "", f"*Not regenerated in this run: from the previous run "
            f"({stamp.group(0) if stamp else 'undated'}), its own settings.*",
            body[1] if len(body) > 1 else "", ""]


# ------------------------------------------------------------ 7. method selection
def method_table(repeats):
    lines = ["| model / scene | reference (agreement) | " + " | ".join(
        f"fastest at {t:.0e}" for t in TARGETS) + " | auto at the same targets |",
        "|---|---|" + "---|" * len(TARGETS) + "---|"]
    for path, name in bundled_scenes():
        model = md.load_model(path)
        started = time.perf_counter()
        try:
            table = md.work_precision(model.mechanism, model.scenes[name], model.params,
                                      methods=METHODS + ["auto"], rtols=RTOLS,
                                      repeats=repeats, reference_rtol=1e-13, check_rtol=1e-10)
        except md.MechdynError as error:
            lines.append(f"| {path.stem} / {name} | no reference: {str(error)[:80]} |")
            continue
        ref = table.reference
        agreement = "exact" if ref.kind == "closed form" else (
            f"{ref.agreement:.0e}" if ref.agreement is not None else "unchecked")
        fastest, autos = [], []
        for target in TARGETS:
            plain = _cheapest([r for r in table.rows if r.method != "auto"], target, ref)
            auto = _cheapest([r for r in table.rows if r.method == "auto"], target, ref)
            fastest.append(_cell(plain))
            autos.append(_cell(auto) + (f", {auto.time / plain.time:.1f}x" if auto and plain
                                        else ""))
        failed = sorted({f"{r.method} {r.rtol:.0e}" for r in table.rows if r.failed})
        lines.append(f"| {path.stem} / {name} | {ref.kind} ({agreement}) | "
                     + " | ".join(fastest) + " | " + "; ".join(autos)
                     + (f" (failed: {', '.join(failed)})" if failed else "") + " |")
        print(lines[-1], f"[{time.perf_counter() - started:.0f} s]", flush=True)
    return "\n".join(lines)


def _cheapest(rows, target, reference):
    if reference.agreement is not None and target < reference.agreement:
        return None
    meeting = [r for r in rows if not r.failed and r.error <= target]
    return min(meeting, key=lambda r: r.time) if meeting else None


def _cell(row):
    if row is None:
        return "-"
    used = row.used if row.method == "auto" else row.method
    return f"{used} {row.rtol:.0e} {row.time * 1e3:.1f} ms"


# ------------------------------------------------------------ 1. derivation
def run_derive():
    script = HERE / "derive.py"
    out = subprocess.run([sys.executable, str(script)], cwd=ROOT, check=True,
                         capture_output=True, text=True).stdout
    return out.rstrip()


def chain_ratios(text) -> dict:
    """{N: LM/md ratio} of derive.py's chain rows in ``text``."""
    return {int(n): float(r) for n, r in
            re.findall(r"chain N=(\d+)\s+[\d.]+\s+[\d.]+\s+[\d.]+\s+([\d.]+)x", text)}


def derive_section(previous_text):
    out = run_derive()
    now, before = chain_ratios(out), chain_ratios(previous_text)
    lines = ["```", out, "```", ""]
    if before:
        lines.append("Against the previous RESULTS.md (LagrangesMethod / mechdyn, chain of "
                     "N inertias): " + ", ".join(
                         f"N = {n}: {before[n]:.1f}x then, {now.get(n, float('nan')):.1f}x now"
                         for n in sorted(before)))
    return "\n".join(lines), now


# ------------------------------------------------------------ headline
def headline(machines, proc, through, sweep_rows, chain):
    import simulate as sim
    import sweep as sweep_bench
    lines = ["| figure | measured | target |", "|---|---|---|"]
    for m in machines:
        for target in sim.TARGETS:
            ob, auto = sim.cheapest(m["obvious_runs"], target), sim.cheapest(m["runs"]["auto"],
                                                                             target)
            comp = sim.cheapest(m["runs"]["compiled"], target)
            if ob and auto:
                lines.append(f"| {m['name']}, error {target:.0e}: obvious path / mechdyn auto"
                             f" | {ob['time'] / auto['time']:.1f}x | - |")
            if comp and comp.get("floor"):
                ratio = comp["time"] / comp["floor"]
                lines.append(f"| {m['name']}, error {target:.0e}: mechdyn compiled / "
                             f"compiled floor | {ratio:.1f}x | <= {sim.FLOOR_TARGET:g}x |")
    for label, m in proc.items():
        import statistics
        lines.append(f"| `mechdyn simulate {label}` warm / yardstick (paired median) | "
                     f"{statistics.median(m['warm']['ratios']):.2f}x | <= 1.3x |")
        lines.append(f"| `mechdyn simulate {label}` cold / yardstick (paired median) | "
                     f"{statistics.median(m['cold']['ratios']):.2f}x | - |")
    long_run = through["dense"][0]
    lines.append(f"| 1e5 dense points / the {long_run['steps']:,}-step run | "
                 f"{long_run['at'] / long_run['run'] * 100:.1f} % | < 20 % |")
    lines.append(f"| plotting the {long_run['steps']:,}-step run (first plot of a process) | "
                 f"{through['plots'][0]:.2f} s | < 2 s |")
    worst = max(r["sweep"] / r["peaks"] for r in sweep_rows)
    lines.append(f"| sweep, 1 worker / plain loop (worst scene) | {worst:.2f}x | "
                 f"<= {sweep_bench.TARGET}x |")
    for n in (16, 32):
        if n in chain:
            lines.append(f"| derivation, chain N = {n}: LagrangesMethod / mechdyn | "
                         f"{chain[n]:.1f}x | >= 10x |")
    return "\n".join(lines)


def header():
    import numpy
    import scipy
    import sympy
    try:
        import numba
        numba_version = f", numba {numba.__version__}"
    except ImportError:
        numba_version = ", numba not installed"
    return (f"Python {platform.python_version()}, sympy {sympy.__version__}, scipy "
            f"{scipy.__version__}, numpy {numpy.__version__}{numba_version}; "
            f"{os.cpu_count()} CPU cores")


def load():
    return os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--runs", type=int, default=10, help="paired process runs")
    parser.add_argument("--skip-methods", action="store_true",
                        help="leave out the method-selection sweep")
    parser.add_argument("--skip-hard-cases", action="store_true",
                        help="leave out the hard-case matrix (the longest part)")
    parser.add_argument("--one", nargs=2, metavar=("MODEL", "SCENE"), help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.one:
        print(json.dumps(one_scene(Path(args.one[0]), args.one[1], args.repeats)))
        return
    started, load_start = time.strftime("%Y-%m-%d %H:%M"), load()
    results = HERE / "RESULTS.md"
    previous = results.read_text() if results.exists() else ""
    sections = []

    print("derivation ...", flush=True)
    text, chain = derive_section(previous)
    sections += ["## Derivation (benchmarks/derive.py)", "", text, ""]

    print("simulation at matched accuracy ...", flush=True)
    import simulate as sim
    machines = sim.main(["--repeats", str(args.repeats)])
    sections += ["## Simulation at matched accuracy (benchmarks/simulate.py)", "",
                 sim.__doc__.split("\n\n", 2)[2].strip(), "", sim.verdicts(machines), ""]
    sections += [sim.report(m) for m in machines]

    print("whole process ...", flush=True)
    import process
    proc = {}
    for model, scene in PROCESS_SCENES:
        proc[f"{Path(model).name} --scene {scene}"] = process.measure(ROOT / model, scene,
                                                                      args.runs)
    sections += ["## Whole process (benchmarks/process.py)", "",
                 process.__doc__.split("\n\n", 2)[2].strip(), "",
                 process.report([(label, label.split()[0], label.split()[-1], m)
                                 for label, m in proc.items()], args.runs), ""]

    print("dense output, plotting, memory ...", flush=True)
    import throughput
    through = throughput.main(["--repeats", str(args.repeats)])
    sections += ["## Dense output, plotting, memory (benchmarks/throughput.py)", "",
                 through["text"], ""]

    print("sweeps ...", flush=True)
    import sweep as sweep_bench
    sweep_rows = sweep_bench.main(["--repeats", str(args.repeats)])
    sections += ["## Sweeps against a plain loop (benchmarks/sweep.py)", "",
                 sweep_bench.report(sweep_rows, 200), ""]

    print("every bundled scene ...", flush=True)
    sections += ["## Every bundled scene: stages and whole process", "",
                 "Derive, compile and RHS in a fresh process with an empty cache; simulate: "
                 "min of repeats at the scene's own method and tolerances, default settings "
                 "(backend auto); floor: a numba RK4 loop with the scene's compiled RHS and "
                 "as many RHS evaluations as that run, in the same process; "
                 "cold/warm: `python -m mechdyn.cli.command simulate MODEL --scene NAME`, medians.",
                 "", stage_table(args.repeats), ""]
    if not args.skip_methods:
        print("method selection ...", flush=True)
        sections += ["## Method selection (calibrates choose_method)", "",
                     f"Fastest method and rtol meeting each target error (worst of L2, final "
                     f"state and event times; rtols {', '.join(f'{r:.0e}' for r in RTOLS)}; "
                     "reference: closed form or DOP853 at 1e-13 checked by Radau at 1e-10; "
                     "'-': no run meets it or the target is below the reference agreement). "
                     "Last column: what method=\"auto\" picks and how much slower it is.", "",
                     method_table(args.repeats), ""]
    else:
        sections += previous_section(previous, "Method selection")
    if not args.skip_hard_cases:
        print("hard-case matrix ...", flush=True)
        import hard_case_matrix
        rows = hard_case_matrix.main([])
        sections += ["## Hard cases (benchmarks/hard_case_matrix.py)", "",
                     "`method=\"auto\"` at the default tolerances; the whole matrix (each "
                     "method at rtol 1e-10, 1e-8, 1e-6) is in benchmarks/HARD_CASES.md.", "",
                     hard_case_matrix.headline(rows), ""]
    else:
        sections += previous_section(previous, "Hard cases")
    # its own runs (a Dask scheduler and workers): kept, not run here
    sections += previous_section(previous, "Sweeps on a Dask cluster")
    sections += [f"Skipped (model file did not load): {name}: {why}"
                 for name, why in dict(SKIPPED).items()]
    parts = ["# mechdyn benchmarks", "",
             f"Written by `python benchmarks/run_all.py` ({started} to "
             f"{time.strftime('%H:%M')}). {header()}; load average {load_start:.1f} at the "
             f"start, {load():.1f} at the end (a shared machine: absolute times carry its "
             "load, ratios of runs made close together less so). mechdyn runs at its "
             "default settings (`backend=\"auto\"`, `method=\"auto\"`) unless a row "
             "names another.", "",
             "## Headline", "", headline(machines, proc, through, sweep_rows, chain), ""]
    results.write_text("\n".join(parts + sections))
    print(f"wrote {results}")


if __name__ == "__main__":
    main()

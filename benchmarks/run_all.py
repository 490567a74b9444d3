"""Every measurement in one run; writes benchmarks/RESULTS.md.

    python benchmarks/run_all.py [--repeats 3] [--skip-methods]

1. Derivation: benchmarks/derive.py (mechdyn vs LagrangesMethod), its output verbatim.
2. Simulation against the obvious path at matched accuracy, RHS per call, whole process
   cold and warm: benchmarks/simulate.py on the slider-crank and the elastic drive.
3. Per bundled scene (models/*.py), each in a fresh process with an empty cache:
   derivation, compilation (code generation), RHS per call, simulation; then the whole
   ``mechdyn simulate`` process cold (empty cache) and warm (cache hit).
4. Method selection: per bundled scene, the fastest solve_ivp method meeting each target
   error (``md.work_precision``), next to what ``method="auto"`` achieves.
5. Sweeps: benchmarks/sweep.py (cost per point against a plain loop over simulate).

All ratios in RESULTS.md come from this one run. Times are minima over repeats; the
machine is shared, so absolute times carry its load (noted in the header).
"""
from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path[:0] = [str(ROOT), str(HERE)]

import mechdyn as md  # noqa: E402
import simulate as sim_bench  # noqa: E402

METHODS = ["RK45", "DOP853", "LSODA", "Radau", "BDF"]
RTOLS = [1e-3, 1e-5, 1e-7, 1e-9]
TARGETS = [1e-3, 1e-5, 1e-7]
WARM_TARGET, COLD_TARGET = 0.7, 1.5


# ------------------------------------------------------------ 3. one scene, in-process
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
            "method": result.stats["method"], "steps": result.stats["steps"]}


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
    lines = ["| model / scene | derive ms | compile ms | RHS us | simulate ms (method, "
             "steps) | cold s | warm s |", "|---|---|---|---|---|---|---|"]
    worst_cold = worst_warm = 0.0
    for path, name in bundled_scenes():
        with tempfile.TemporaryDirectory() as cache:
            env = dict(os.environ, MECHDYN_CACHE=cache)
            done = subprocess.run([sys.executable, __file__, "--one", str(path), name,
                                   "--repeats", str(repeats)], env=env, cwd=ROOT,
                                  capture_output=True, text=True)
        if done.returncode:
            lines.append(f"| {path.stem} / {name} | failed: "
                         f"{done.stderr.strip().splitlines()[-1][:80]} | | | | | |")
            continue
        s = json.loads(done.stdout.strip().splitlines()[-1])
        cold, warm = sim_bench.whole_process(path, name, repeats)
        worst_cold, worst_warm = max(worst_cold, cold), max(worst_warm, warm)
        lines.append(f"| {path.stem} / {name} | {s['derive'] * 1e3:.0f} | "
                     f"{s['compile'] * 1e3:.0f} | {s['rhs'] * 1e6:.1f} | "
                     f"{s['simulate'] * 1e3:.1f} ({s['method']}, {s['steps']}) | "
                     f"{cold:.2f} | {warm:.2f} |")
        print(lines[-1], flush=True)
    lines += ["", f"Worst whole process: cold {worst_cold:.2f} s (target < {COLD_TARGET} s: "
              f"{_verdict(worst_cold < COLD_TARGET)}), warm {worst_warm:.2f} s (target < "
              f"{WARM_TARGET} s: {_verdict(worst_warm < WARM_TARGET)})."]
    return "\n".join(lines)


# ------------------------------------------------------------ 4. method selection
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


def _verdict(ok):
    return "met" if ok else "**missed**"


# ------------------------------------------------------------------------ main
def run_derive():
    script = HERE / "derive.py"
    if not script.exists():
        return "benchmarks/derive.py not present: derivation not measured."
    out = subprocess.run([sys.executable, str(script)], cwd=ROOT, check=True,
                         capture_output=True, text=True).stdout
    return "```\n" + out.rstrip() + "\n```"


def header():
    import numpy
    import scipy
    import sympy
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    return (f"Python {platform.python_version()}, sympy {sympy.__version__}, scipy "
            f"{scipy.__version__}, numpy {numpy.__version__}; {os.cpu_count()} CPU cores, "
            f"load average {load:.1f} at the start (a shared machine: absolute times are "
            f"inflated by others' work, ratios less so); {time.strftime('%Y-%m-%d %H:%M')}")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--skip-methods", action="store_true",
                        help="leave out the method-selection sweep (the slowest part)")
    parser.add_argument("--one", nargs=2, metavar=("MODEL", "SCENE"), help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.one:
        print(json.dumps(one_scene(Path(args.one[0]), args.one[1], args.repeats)))
        return
    parts = ["# mechdyn benchmarks", "", "Written by `python benchmarks/run_all.py`. "
             + header(), ""]
    print("derivation ...", flush=True)
    parts += ["## Derivation (benchmarks/derive.py)", "", run_derive(), ""]
    print("simulation vs the obvious path ...", flush=True)
    machines, imports = sim_bench.main(["--repeats", str(args.repeats)])
    parts += ["## Simulation against the obvious path (benchmarks/simulate.py)", "",
              sim_bench.__doc__.split("\n\n", 2)[2].strip(), ""]
    parts += [sim_bench.report(m) for m in machines]
    parts += ["| baseline process | s |", "|---|---|"]
    parts += [f"| {label} | {seconds:.2f} |" for label, seconds in imports.items()]
    parts += ["", "## Every bundled scene: stages and whole process", "",
              "Derive, compile and RHS in a fresh process with an empty cache; simulate: "
              "min of repeats at the scene's own method and tolerances; cold/warm: "
              "`python -m mechdyn.cli simulate MODEL --scene NAME`.", "",
              stage_table(args.repeats), ""]
    if not args.skip_methods:
        print("method selection ...", flush=True)
        parts += ["## Method selection (calibrates choose_method)", "",
                  f"Fastest method and rtol meeting each target error (worst of L2, final "
                  f"state and event times; rtols {', '.join(f'{r:.0e}' for r in RTOLS)}; "
                  "reference: closed form or DOP853 at 1e-13 checked by Radau at 1e-10; "
                  "'-': no run meets it or the target is below the reference agreement). "
                  "Last column: what method=\"auto\" picks and how much slower it is.", "",
                  method_table(args.repeats), ""]
    print("sweeps ...", flush=True)
    import sweep as sweep_bench
    parts += ["## Sweeps against a plain loop (benchmarks/sweep.py)", "",
              sweep_bench.report(sweep_bench.main(["--repeats", str(args.repeats)]), 200), ""]
    parts += [f"Skipped (model file did not load): {name}: {why}"
              for name, why in dict(SKIPPED).items()]
    (HERE / "RESULTS.md").write_text("\n".join(parts))
    print(f"wrote {HERE / 'RESULTS.md'}")


if __name__ == "__main__":
    main()

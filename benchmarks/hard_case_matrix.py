"""The hard-case matrix: each hard case x each method x a few tolerances.

    python benchmarks/hard_case_matrix.py [--timeout 60] [--cases NAME,...]
                                          [--methods LABEL,...] [--no-write]

Cases are benchmarks/hard_cases.py's, each with a reference that does not come from
mechdyn's integrators (closed form, matrix exponential, energy integral, MSL result).
Methods: ``auto`` (mechdyn's choice, backend ``auto``), DOP853 on scipy and compiled,
RK45, Radau, LSODA, BDF (scipy), Rodas5P (compiled). Tolerances: the scene defaults
(rtol 1e-10, atol 1e-12), 1e-8 and 1e-6 (atol = rtol / 100). The 10,000-revolution
crank runs ``auto`` and DOP853 only, at the default tolerances.

Every run is a fresh process with a time limit (``--timeout``, default 60 s): some
combinations are pathological, and that is what the matrix shows. Before the runs each
case is compiled once (generated code and, where the case has one, its numba form) into
the disk cache, so a run loads it rather than compiling. Timed is ``mech.simulate``
alone: a named compiled backend starts with the compiled functions in memory, while
``auto`` starts cold, as in a fresh process (it loads the kernels when it decides to
move to them); "again" is a second run in the same process (runs under 5 s).

Outcome: ``ok`` (error within the case's bound), ``inaccurate`` (finished, error above
the bound), ``budget`` (the step budget of one million steps exceeded), ``failed: ...``
(the error's first words), ``timeout`` (killed at the limit; a run that finished
between the limit and 30 s after it shows its figures, marked "over the limit"); the
vanishing-inertia case must fail with a named error (``named error``). Prints the tables and writes benchmarks/HARD_CASES.md.
"""
from __future__ import annotations

import argparse
import json
import math
import os
import platform
import signal
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent

# (label, method, backend)
METHODS = [("auto", "auto", "auto"), ("DOP853 scipy", "DOP853", "scipy"),
           ("DOP853 compiled", "DOP853", "compiled"), ("RK45", "RK45", "scipy"),
           ("Radau", "Radau", "scipy"), ("LSODA", "LSODA", "scipy"),
           ("BDF", "BDF", "scipy"), ("Rodas5P compiled", "Rodas5P", "compiled")]
RTOLS = [None, 1e-8, 1e-6]                  # None: the scene defaults, 1e-10 / 1e-12
LIMITED = {"free_crank_long": (("auto", "DOP853 scipy", "DOP853 compiled"), (None,))}
AGAIN_BELOW = 5.0                           # seconds: runs this short are run twice


# ------------------------------------------------------------------- one run (child)
def child(case_name, method, backend, rtol, prepare=False):
    """Run one combination in this process; print its figures as one JSON line."""
    sys.path[:0] = [str(ROOT), str(HERE)]
    import numpy as np

    import hard_cases
    import mechdyn as md
    from dataclasses import replace
    case = getattr(hard_cases, case_name)(rtol)
    scene = replace(case.scene, method=method, backend=backend)
    compiled = case.mechanism.compile(scene)
    if prepare or backend == "compiled":
        from mechdyn.compile.numba_model import numba_functions
        numba_functions(compiled)
        if prepare:
            print(json.dumps({"prepared": True}))
            return
    row = {"case": case.name, "what": case.what, "bound": case.bound}

    def once():
        started = time.perf_counter()
        try:
            result = case.mechanism.simulate(scene, case.params)
        except md.SimulationError as error:
            return time.perf_counter() - started, None, error
        except md.MechdynError as error:
            return time.perf_counter() - started, None, error
        return time.perf_counter() - started, result, None

    seconds, result, error = once()
    row["time"] = seconds
    if seconds < AGAIN_BELOW:
        row["again"] = once()[0]
    if error is not None:
        message = str(error)
        partial = getattr(error, "partial", None)
        row["message"] = message
        row["outcome"] = ("named error" if case.expect_failure
                          and isinstance(error, md.SimulationError) else
                          "budget" if "budget" in message else
                          "failed: " + _first_words(message))
        stats = partial.stats if partial is not None else {}
        row["reached"] = float(partial.t[-1]) if partial is not None else None
    else:
        stats = result.stats
        row["error"] = float(case.error(result))
        if case.expect_failure:
            row["outcome"] = "no error (wrong)"
        else:
            row["outcome"] = "ok" if row["error"] <= case.bound else "inaccurate"
    row.update(steps=stats.get("steps"), used=stats.get("method", ""),
               backends=stats.get("backends", {}),
               switches=len(stats.get("switches", [])),
               switch_list=[{**s, "t": float(s["t"])} for s in stats.get("switches", [])][:12])
    print(json.dumps(row, default=lambda x: float(x) if isinstance(x, np.floating) else str(x)))


def _first_words(message, words=12):
    text = message.replace("integration failed: ", "").replace("integration failed ", "")
    return " ".join(text.split()[:words])


# ------------------------------------------------------------------- the matrix
def run_child(args, timeout):
    """(row dict or None, seconds) of a child process; None on timeout."""
    command = [sys.executable, __file__, "--child", *args]
    started = time.perf_counter()
    process = subprocess.Popen(command, cwd=ROOT, stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True, start_new_session=True,
                               env=dict(os.environ, PYTHONPATH=os.pathsep.join(
                                   [str(ROOT)] + os.environ.get("PYTHONPATH", "").split(
                                       os.pathsep)).rstrip(os.pathsep)))
    try:
        out, err = process.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(process.pid, signal.SIGKILL)
        process.communicate()
        return None, time.perf_counter() - started
    lines = out.strip().splitlines()
    if process.returncode or not lines:
        last = (err.strip().splitlines() or ["no output"])[-1]
        return {"outcome": "crashed: " + last[:100]}, time.perf_counter() - started
    return json.loads(lines[-1]), time.perf_counter() - started


def plan(case_names, method_labels):
    for case in case_names:
        methods, rtols = LIMITED.get(case, (None, RTOLS))
        for rtol in rtols:
            for label, method, backend in METHODS:
                if label in method_labels and (methods is None or label in methods):
                    yield case, label, method, backend, rtol


def run_matrix(case_names, method_labels, timeout, log=print):
    rows = []
    for case in case_names:                       # compile once into the disk cache
        done, seconds = run_child([case, "auto", "auto", "default", "--prepare"],
                                  max(timeout, 600))
        log(f"prepared {case} ({seconds:.0f} s)" + ("" if done else ": timeout"))
    for case, label, method, backend, rtol in plan(case_names, method_labels):
        row, seconds = run_child([case, method, backend,
                                  "default" if rtol is None else repr(rtol)], timeout + 30)
        if row is None:
            row = {"outcome": "timeout"}
        elif row.get("time", 0) > timeout:          # finished, but after the limit
            row["outcome"] += " (over the limit)"
        row.update(key=case, label=label, rtol=rtol, process=seconds)
        rows.append(row)
        log(line(row))
    return rows


def _tol(rtol):
    return "default" if rtol is None else f"{rtol:.0e}"


def _num(value, fmt):
    return "-" if value is None or (isinstance(value, float) and math.isnan(value)) \
        else format(value, fmt)


def _seconds(row):
    if row["outcome"] == "timeout":
        return "> limit"
    text = _num(row.get("time"), ".3g")
    if row.get("again") is not None:
        text += f" / {row['again']:.3g}"
    return text


def _used(row):
    backends = row.get("backends") or {}
    where = ", ".join(f"{k} {v}" for k, v in backends.items())
    used = row.get("used", "")
    return f"{used} ({where})" if where else used


def line(row):
    return (f"{row.get('case', row['key']):30} {row['label']:17} {_tol(row['rtol']):>7} "
            f"{row['outcome'][:40]:40} {_seconds(row):>15} {_num(row.get('steps'), 'd'):>8} "
            f"{_num(row.get('error'), '.1e'):>8} {_used(row)}")


# ------------------------------------------------------------------- report
def headline(rows):
    out = ["| case | error measured (bound) | outcome | time s (first / again) | steps | "
           "error | methods used (steps per backend) | switches |",
           "|---|---|---|---|---|---|---|---|"]
    for row in rows:
        if row["label"] != "auto" or row["rtol"] is not None:
            continue
        out.append(f"| {row.get('case', row['key'])} | {row.get('what', '')} "
                   f"({row.get('bound', 0):.0e}) | {row['outcome']} | {_seconds(row)} | "
                   f"{_num(row.get('steps'), ',d')} | {_num(row.get('error'), '.1e')} | "
                   f"{_used(row)} | {row.get('switches', '-')} |")
    return "\n".join(out)


def matrix(rows):
    out = ["| case | method | rtol | outcome | time s | steps | error | used |",
           "|---|---|---|---|---|---|---|---|"]
    for row in rows:
        out.append(f"| {row.get('case', row['key'])} | {row['label']} | {_tol(row['rtol'])} "
                   f"| {row['outcome']} | {_seconds(row)} | {_num(row.get('steps'), ',d')} | "
                   f"{_num(row.get('error'), '.1e')} | {_used(row)} |")
    return "\n".join(out)


def switches(rows):
    out = []
    for row in rows:
        if row["label"] == "auto" and row.get("switch_list"):
            items = "; ".join(f"t = {s['t']:.6g}: {s['from']} -> {s['to']} ({s['why']})"
                              for s in row["switch_list"][:6])
            more = row["switches"] - min(6, len(row["switch_list"]))
            out.append(f"- {row.get('case', row['key'])}, rtol {_tol(row['rtol'])}: {items}"
                       + (f"; and {more} more" if more > 0 else ""))
    return "\n".join(out)


def header(timeout):
    import numpy
    import scipy
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    return (f"Python {platform.python_version()}, scipy {scipy.__version__}, numpy "
            f"{numpy.__version__}; {os.cpu_count()} CPU cores, load average {load:.1f} at "
            f"the start; limit {timeout:.0f} s per run; {time.strftime('%Y-%m-%d %H:%M')}")


def write(rows, timeout, load_note, path):
    text = "\n".join([
        "# Hard cases x methods x tolerances", "",
        "Written by `python benchmarks/hard_case_matrix.py`. " + load_note, "",
        __doc__.split("\n\n", 2)[2].strip(), "",
        "## Headline: `method=\"auto\"` at the default tolerances", "", headline(rows), "",
        "## The matrix", "", matrix(rows), "",
        "## Method switches of the auto runs (the first six of each)", "", switches(rows),
        ""])
    path.write_text(text)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--timeout", type=float, default=60.0)
    parser.add_argument("--cases", help="comma-separated hard_cases function names")
    parser.add_argument("--methods", help="comma-separated method labels")
    parser.add_argument("--no-write", action="store_true")
    parser.add_argument("--out", default=str(HERE / "HARD_CASES.md"))
    parser.add_argument("--json", help="also save the rows to this file")
    parser.add_argument("--from-json", help="write the report from saved rows, run nothing")
    parser.add_argument("--child", nargs=4, help=argparse.SUPPRESS)
    parser.add_argument("--prepare", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.child:
        case, method, backend, rtol = args.child
        child(case, method, backend, None if rtol == "default" else float(rtol),
              args.prepare)
        return None
    if args.from_json:
        saved = json.loads(Path(args.from_json).read_text())
        write(saved["rows"], saved["timeout"], saved["note"], Path(args.out))
        print(headline(saved["rows"]))
        return saved["rows"]
    sys.path[:0] = [str(ROOT), str(HERE)]
    import hard_cases
    cases = args.cases.split(",") if args.cases else [f.__name__ for f in hard_cases.CASES]
    labels = args.methods.split(",") if args.methods else [m[0] for m in METHODS]
    note = header(args.timeout)
    print(note, flush=True)
    rows = run_matrix(cases, labels, args.timeout, log=lambda s: print(s, flush=True))
    if args.json:
        Path(args.json).write_text(json.dumps({"rows": rows, "timeout": args.timeout,
                                               "note": note}))
    print()
    print(headline(rows))
    if not args.no_write:
        write(rows, args.timeout, note, Path(args.out))
        print(f"wrote {args.out}")
    return rows


if __name__ == "__main__":
    main()

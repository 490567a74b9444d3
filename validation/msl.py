"""Validation against the Modelica Standard Library's reference results.

Every example ``<Package>.<Example>`` has a reference excerpt ``msl/reference/<name>.csv``
(provenance: ``msl/README.md``) and a mechdyn model ``msl/models/<name>.py``: a model file
as in ``models/`` (``mechanism``, ``params``, ``scenes``) with a scene ``"reference"``
(the example's stop time, default tolerances and method) and ``signals``, the mechdyn
expression of each reference column. A model may set ``needs = "..."`` (the elements
mechdyn lacks for it; the example is reported as not yet expressible and never run) and
``slow = True`` (kept out of the fast test subset). Both are read from the file's text,
so a model written against an API that does not exist yet is never executed. A model of
a part of an example (``msl/models/parts/``) is compared on the signals it defines.

Every reference signal is compared at every reference time. The error of a signal is
``max |mechdyn - reference| / base`` where ``base`` is the range of the reference signal,
or, as CSV Compare does, ``|max|`` when the range is zero, or ``ABSOLUTE_FLOOR`` when the
signal is zero throughout. An example passes when every error is within ``TOLERANCE``
(2e-3, the MSL regression tolerance). At a mechdyn event the state after the event is
used (the excerpts keep the last row of repeated time stamps, the state after an event).

    python validation/msl.py                  # fast examples: a table, one row each
    python validation/msl.py --all            # every example, slow ones too
    python validation/msl.py Rotational.First --worst   # chosen examples, each signal

>>> round(signal_error([0.0, 1.002, 2.0], [0.0, 1.0, 2.0]), 12)  # mechdyn, reference
0.001
>>> round(signal_error([4.5, 4.509], [4.5, 4.5]), 12)    # zero range: relative to |max|
0.002
"""
from __future__ import annotations

import argparse
import ast
import csv
import runpy
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import sympy as sp

import mechdyn as md

HERE = Path(__file__).resolve().parent / "msl"
REFERENCE_DIR = HERE / "reference"
MODELS_DIR = HERE / "models"
TOLERANCE = 2e-3
ABSOLUTE_FLOOR = 1e-6      # base of a signal that is zero throughout (its own units)
EVENT_WINDOW = 1e-9        # reference times this close (x run length) to an event: after it


@dataclass
class Outcome:
    """How one example compared: ``status`` is "pass", "FAIL", "needs" (not yet
    expressible), "no model" or "error"; ``errors`` maps each signal to its error."""
    name: str
    status: str
    errors: dict = field(default_factory=dict)
    worst: str = ""
    worst_time: float = float("nan")
    detail: str = ""
    total_time: float = float("nan")
    simulation_time: float = float("nan")

    @property
    def worst_error(self) -> float:
        return self.errors.get(self.worst, float("nan"))


# ------------------------------------------------------------------ the files
def example_names() -> list:
    """Every example with a reference excerpt, sorted."""
    return sorted(p.stem for p in REFERENCE_DIR.glob("*.csv"))


def model_path(name: str) -> Path:
    return MODELS_DIR / f"{name}.py"


def read_reference(name: str):
    """``(times, {signal: values})`` of an example's reference excerpt."""
    with open(REFERENCE_DIR / f"{name}.csv", newline="") as handle:
        rows = list(csv.reader(handle))
    header, data = rows[0], np.array(rows[1:], dtype=float)
    return data[:, 0], {column: data[:, i] for i, column in enumerate(header) if i}


def declared(path: Path, variable: str, default=None):
    """A literal module-level assignment in a model file, read without running it."""
    for node in ast.parse(path.read_text()).body:
        if isinstance(node, ast.Assign) and any(
                isinstance(target, ast.Name) and target.id == variable
                for target in node.targets):
            return ast.literal_eval(node.value)
    return default


def is_slow(name: str) -> bool:
    path = model_path(name)
    return path.exists() and bool(declared(path, "slow", False))


# ----------------------------------------------------------------- comparison
def signal_error(mechdyn, reference) -> float:
    """``max |mechdyn - reference|`` over the reference's base (see the module text)."""
    mechdyn, reference = np.asarray(mechdyn, float), np.asarray(reference, float)
    base = float(np.ptp(reference)) or float(np.max(np.abs(reference))) or ABSOLUTE_FLOOR
    return float(np.max(np.abs(mechdyn - reference)) / base)


def states_at(result, times) -> np.ndarray:
    """States ``(2n, len(times))`` from the dense output; a time at a mechdyn event takes
    the state recorded after it (the right limit)."""
    times = np.asarray(times, dtype=float)
    dense = result.at(times)
    states = np.array([np.atleast_1d(dense[name]) for name in result.state_names])
    window = EVENT_WINDOW * max(1.0, float(times[-1] - times[0]))
    for event_time in sorted({event.time for event in result.events}):
        after = np.flatnonzero(result.t == event_time)
        if not len(after):
            continue
        near = np.abs(times - event_time) <= window
        states[:, near] = result.y[:, after[-1]][:, None]
    return states


def signal_values(model, result, states, times) -> dict:
    """Each reference signal's mechdyn values, from the model's ``signals`` expressions
    (of the coordinates, their speeds, ``md.t`` and the model's parameters)."""
    symbols, rows = [md.t], [np.asarray(times, dtype=float)]
    for q in model["mechanism"].coordinates:
        for key in (q, md.speed(q)):
            symbols.append(md.plain(key))
            rows.append(states[result.state_names.index(str(md.plain(key)))])
    known = {sp.sympify(key): value for key, value in model["params"].items()}
    values = {}
    for signal, expression in model["signals"].items():
        plain = sp.sympify(expression).xreplace(
            {key: md.plain(key) for q in model["mechanism"].coordinates
             for key in (md.speed(q), q)}).xreplace(known)
        function = sp.lambdify(symbols, plain, "numpy")
        values[signal] = np.broadcast_to(function(*rows), np.shape(times)).astype(float)
    return values


# ------------------------------------------------------------------- running
def run_example(name: str, try_awaiting: bool = False, model_file=None) -> Outcome:
    """Simulate one example at default settings and compare every reference signal.

    ``model_file`` replaces the example's model by one of a part of it (a subsystem):
    then only the reference signals that model defines are compared."""
    path = Path(model_file) if model_file else model_path(name)
    if not path.exists():
        return Outcome(name, "no model", detail=f"no model file {path.name}")
    needs = declared(path, "needs")
    if needs and not try_awaiting:
        return Outcome(name, "needs", detail=f"not yet expressible: needs {needs}")
    started = time.perf_counter()
    try:
        model = runpy.run_path(str(path), run_name="mechdyn_model")
        times, reference = read_reference(name)
        unknown = sorted(set(model["signals"]) - set(reference))
        missing = sorted(set(reference) - set(model["signals"]))
        if unknown or (missing and not model_file):
            return Outcome(name, "error", detail=f"signals not in the reference: {unknown}; "
                           f"reference signals not modelled: {missing}")
        reference = {signal: reference[signal] for signal in model["signals"]}
        result = model["mechanism"].simulate(model["scenes"]["reference"], model["params"])
        states = states_at(result, times)
        values = signal_values(model, result, states, times)
    except Exception as error:   # a failing example is a row of the table, not a crash
        text = f"{type(error).__name__}: {error}"[:300]
        if needs:
            return Outcome(name, "needs", detail=f"tried although it needs {needs}: {text}")
        return Outcome(name, "error", detail=text, total_time=time.perf_counter() - started)
    outcome = Outcome(name, "pass", total_time=time.perf_counter() - started,
                      simulation_time=result.stats.get("wall_time", float("nan")))
    for signal, ref in reference.items():
        outcome.errors[signal] = signal_error(values[signal], ref)
    outcome.worst = max(outcome.errors, key=outcome.errors.get)
    deviation = np.abs(values[outcome.worst] - reference[outcome.worst])
    outcome.worst_time = float(times[int(np.argmax(deviation))])
    if outcome.worst_error > TOLERANCE:
        outcome.status = "FAIL"
    if needs:
        outcome.detail = f"tried although it needs {needs}: {outcome.status}"
        outcome.status = "needs"
    return outcome


def table(outcomes, skipped=()) -> str:
    """The printed summary: one row per example, then the counts (``skipped``: the slow
    examples left out)."""
    lines = [f"{'example':46} {'signals':>7} {'worst signal':24} {'error':>9} "
             f"{'at t':>8} {'result':8} {'total s':>7} {'sim s':>6}"]
    for o in outcomes:
        if o.errors:
            lines.append(f"{o.name:46} {len(o.errors):7d} {o.worst:24} {o.worst_error:9.2e} "
                         f"{o.worst_time:8.4g} {o.status:8} {o.total_time:7.2f} "
                         f"{o.simulation_time:6.2f} {o.detail}".rstrip())
        else:
            lines.append(f"{o.name:46} {'':7} {'':24} {'':9} {'':8} {o.status:8} "
                         f"{'':7} {'':6} {o.detail}".rstrip())
    counts = {s: sum(o.status == s for o in outcomes) for s in
              ("pass", "FAIL", "error", "needs", "no model")}
    modelled = counts["pass"] + counts["FAIL"] + counts["error"]
    lines.append(f"\n{counts['pass']} of {modelled} modelled examples within {TOLERANCE:g} of "
                 f"each signal's range; {counts['needs']} not yet expressible, "
                 f"{counts['no model']} without a model ({len(outcomes)} shown).")
    if skipped:
        lines.append(f"Slow, not run (--all runs them): {', '.join(skipped)}.")
    return "\n".join(lines)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description="Compare mechdyn with the MSL reference "
                                     "results (validation/msl/README.md).")
    parser.add_argument("examples", nargs="*", help="example names (default: all)")
    parser.add_argument("--all", action="store_true", help="include the slow examples")
    parser.add_argument("--try-awaiting", action="store_true",
                        help="run examples marked `needs` too (they are not counted)")
    parser.add_argument("--worst", action="store_true", help="list every signal's error")
    args = parser.parse_args(argv)
    names = args.examples or [n for n in example_names() if args.all or not is_slow(n)]
    skipped = [] if args.examples or args.all else [n for n in example_names() if is_slow(n)]
    unknown = sorted(set(names) - set(example_names()))
    if unknown:
        parser.error(f"no reference for {', '.join(unknown)}")
    outcomes = []
    for name in names:
        outcomes.append(run_example(name, args.try_awaiting))
        if args.worst:
            for signal, error in outcomes[-1].errors.items():
                print(f"  {name}: {signal:28} {error:9.2e}")
    print(table(outcomes, skipped))
    return 0 if all(o.status in ("pass", "needs", "no model") for o in outcomes) else 1


if __name__ == "__main__":
    sys.exit(main())

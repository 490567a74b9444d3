"""Whole-process times: ``mechdyn simulate`` cold and warm against a yardstick process.

    python benchmarks/process.py [--runs 10] [--model models/shoe_brake.py --scene braking]

Each command is a fresh Python process timed from outside (wall clock from start to
exit; user + system CPU and peak memory from the operating system's accounting of the
child, ``os.wait4``). A command and the yardstick ``python -c "import numpy,
scipy.integrate"`` run in turn, A B A B ..., after one unrecorded warm-up each, and the
ratio is taken pair by pair, so a drift of the machine's speed during the measurement
moves both sides of a ratio. Figures are medians (min and max show the spread).

* cold: ``python -m mechdyn.cli.command simulate MODEL --scene NAME`` with an empty cache
  (``MECHDYN_CACHE`` a fresh directory for every run): model file, sympy derivation,
  code generation, simulation.
* warm: the same command with the cache filled by an earlier run (issue 15: the warm
  start skips the model file and sympy; target within 1.3x of the yardstick).
"""
from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
YARDSTICK = ("python -c \"import numpy, scipy.integrate\"",
             [sys.executable, "-c", "import numpy, scipy.integrate"])
WARM_TARGET = 1.3


def run_once(command, env=None):
    """(wall s, cpu s, peak MiB, exit status) of one process running ``command``."""
    started = time.perf_counter()
    process = subprocess.Popen(command, cwd=ROOT, env=env, stdin=subprocess.DEVNULL,
                               stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    _, status, usage = os.wait4(process.pid, 0)
    wall = time.perf_counter() - started
    process.returncode = os.waitstatus_to_exitcode(status)
    return wall, usage.ru_utime + usage.ru_stime, usage.ru_maxrss / 1024, process.returncode


def paired(command, runs, env_of=lambda k: None, warmup=1):
    """Figures of ``command`` (env from ``env_of(run index)``) run in turn with the
    yardstick: dict of wall/cpu/peak lists per side and the pairwise wall ratios."""
    for k in range(warmup):
        run_once(command, env_of(-1 - k))
        run_once(YARDSTICK[1])
    a, b = [], []
    for k in range(runs):
        a.append(run_once(command, env_of(k)))
        b.append(run_once(YARDSTICK[1]))
    failed = [r[3] for r in a if r[3]]
    return {"a": a, "b": b, "ratios": [x[0] / y[0] for x, y in zip(a, b)],
            "failed": failed}


def spread(values, fmt):
    return (f"{format(statistics.median(values), fmt)} "
            f"({format(min(values), fmt)}-{format(max(values), fmt)})")


def cli_command(model, scene):
    return [sys.executable, "-m", "mechdyn.cli.command", "simulate", str(model), "--scene", scene]


def measure(model, scene, runs):
    """{"cold": paired(...), "warm": paired(...)} for one scene."""
    command = cli_command(model, scene)
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(
        [str(ROOT)] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]))
    with tempfile.TemporaryDirectory() as base:
        def fresh(k):
            return dict(env, MECHDYN_CACHE=str(Path(base) / f"cold{k + 10}"))
        cold = paired(command, runs, fresh)
        warm_env = dict(env, MECHDYN_CACHE=str(Path(base) / "warm"))
        run_once(command, warm_env)                       # fills the cache
        warm = paired(command, runs, lambda k: warm_env)
    return {"cold": cold, "warm": warm}


def whole_process(model, scene, repeats=3):
    """(cold, warm) median wall seconds of ``mechdyn simulate`` (each cold run with an
    empty cache of its own), unpaired: for a table of many scenes."""
    command = cli_command(model, scene)
    with tempfile.TemporaryDirectory() as base:
        colds = [run_once(command, dict(os.environ, MECHDYN_CACHE=str(Path(base) / str(k))))
                 for k in range(repeats)]
        env = dict(os.environ, MECHDYN_CACHE=str(Path(base) / "0"))
        warms = [run_once(command, env) for _ in range(repeats)]
    if any(r[3] for r in colds + warms):
        return float("nan"), float("nan")
    return (statistics.median(r[0] for r in colds), statistics.median(r[0] for r in warms))


def yardstick(repeats=5):
    """Median wall seconds of the yardstick process."""
    return statistics.median(run_once(YARDSTICK[1])[0] for _ in range(repeats))


def report(rows, runs) -> str:
    """rows: [(label, model, scene, measure(...))]"""
    lines = [f"{runs} runs of each, paired with `{YARDSTICK[0]}`; median (min-max):", "",
             "| command | wall s | cpu s | peak MiB | yardstick wall s | ratio to the "
             "yardstick |", "|---|---|---|---|---|---|"]
    for label, model, scene, m in rows:
        for kind in ("cold", "warm"):
            r = m[kind]
            note = f" ({len(r['failed'])} runs failed)" if r["failed"] else ""
            lines.append(f"| `mechdyn simulate {Path(model).name} --scene {scene}`, {kind}"
                         f"{note} | {spread([x[0] for x in r['a']], '.2f')} | "
                         f"{spread([x[1] for x in r['a']], '.2f')} | "
                         f"{spread([x[2] for x in r['a']], '.0f')} | "
                         f"{spread([x[0] for x in r['b']], '.2f')} | "
                         f"{spread(r['ratios'], '.2f')} |")
    return "\n".join(lines)


def verdict(m) -> str:
    ratio = statistics.median(m["warm"]["ratios"])
    return (f"warm within {WARM_TARGET}x of the yardstick: {ratio:.2f}x "
            f"({'met' if ratio <= WARM_TARGET else '**missed**'})")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--runs", type=int, default=10)
    parser.add_argument("--model", default="models/shoe_brake.py")
    parser.add_argument("--scene", default="braking")
    args = parser.parse_args(argv)
    m = measure(ROOT / args.model, args.scene, args.runs)
    print(report([(args.model, args.model, args.scene, m)], args.runs))
    print(verdict(m))
    return m


if __name__ == "__main__":
    main()

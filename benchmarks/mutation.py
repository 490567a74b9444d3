"""Mutation testing of mechdyn's core with mutmut 3: how many deliberately broken
versions of the code the test suite catches, per module.

    python benchmarks/mutation.py --fast              # reduction, codegen: minutes
    python benchmarks/mutation.py --full              # every core module: hours on 2 cores
    python benchmarks/mutation.py --modules derive analytic
    python benchmarks/mutation.py --report            # the table of the last run, no run
    python benchmarks/mutation.py --fast --survivors  # rerun only the last survivors
    python benchmarks/mutation.py --modules friction --functions decide _holdable

mutmut copies the package to ``mutants/`` with every mutant built in, runs the suite once
to learn which tests reach which function, then runs for each mutant only those tests
(``-x``: the first failure kills it) in a fresh forked process. Configuration:
``[tool.mutmut]`` in pyproject.toml. Results accumulate in ``mutants/``; a mutant already
decided is not rerun: after adding tests, ``--survivors`` retries the survivors, and
deleting ``mutants/`` starts over.
``mutmut show NAME`` prints a mutant's diff, ``mutmut browse`` lists them interactively.
Scores and the account of every survivor: docs/mutation.md.
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from collections import Counter
from datetime import date
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
CORE = ["derive", "codegen", "compile", "simulate", "stepping", "analytic", "periodic",
        "fluctuation", "modal", "reduction", "driver", "segments", "events", "friction",
        "constrained"]
FAST = ["reduction", "codegen"]
STATUS = {1: "killed", 3: "killed", 0: "survived", 5: "no tests", 33: "no tests",
          36: "timeout", -24: "timeout", 24: "timeout", 152: "timeout", 255: "timeout",
          None: "not run"}


def run(modules, workers, survivors=False, functions=None):
    """``mutmut run`` on the mutants of ``modules`` (only those of ``functions``, names
    of functions or methods, if given; with ``survivors``: on the mutants that survived
    the last run, to try new tests on them); mutmut's own exit status."""
    # mutants/ must exist before Python starts: a PYTHONPATH entry missing at start-up is
    # remembered as empty, and mechdyn would be imported from elsewhere.
    (ROOT / "mutants").mkdir(exist_ok=True)
    env = dict(os.environ, MECHDYN_CACHE="off", PYTHONPATH=str(ROOT / "mutants"))
    names = [f"mechdyn.{module}.*" for module in modules]
    if functions:
        names = [f"mechdyn.{module}.*{function}__mutmut_*" for module in modules
                 for function in functions]
    if survivors:
        names = sorted(name for module in modules for name, outcome in
                       outcomes(module, functions).items()
                       if outcome in ("survived", "no tests"))
        if not names:
            return 0
    command = ["mutmut", "run", "--max-children", str(workers), *names]
    print("$", " ".join(command), flush=True)
    return subprocess.run(command, cwd=ROOT, env=env).returncode


def outcomes(module, functions=None) -> dict:
    """Mutant name -> outcome, from mutmut's record of ``module`` (of its
    ``functions`` only, if given)."""
    meta = ROOT / "mutants" / "mechdyn" / f"{module}.py.meta"
    if not meta.is_file():
        return {}
    codes = json.loads(meta.read_text())["exit_code_by_key"]
    return {name: STATUS.get(code, f"exit {code}") for name, code in codes.items()
            if not functions or _function(name) in functions}


def _function(name) -> str:
    """The function or method a mutant belongs to: ``mechdyn.friction.xǁFrictionModesǁ
    decide__mutmut_7`` -> ``decide``."""
    mangled = name.rsplit("__mutmut_", 1)[0].rsplit(".", 1)[-1]
    return mangled.split("\u01c1")[-1] if "\u01c1" in mangled else mangled[2:]


def table(modules, functions=None) -> str:
    """Per module: mutants, killed, survived, other outcomes, score = killed / decided."""
    lines = [f"mutation score, {date.today().isoformat()} (mutmut, tests/ without slow)", "",
             "| module | mutants | killed | survived | no tests | timeout | not run | score |",
             "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"]
    survivors = []
    for module in modules:
        results = outcomes(module, functions)
        count = Counter(results.values())
        decided = count["killed"] + count["survived"] + count["no tests"]
        score = f"{100 * count['killed'] / decided:.1f} %" if decided else "-"
        other = sum(v for k, v in count.items() if k not in
                    ("killed", "survived", "no tests", "timeout", "not run"))
        lines.append(f"| {module}.py | {len(results)} | {count['killed'] + count['timeout']} "
                     f"| {count['survived']} | {count['no tests']} | {count['timeout']} "
                     f"| {count['not run'] + other} | {score} |")
        survivors += [n for n, outcome in results.items() if outcome in ("survived", "no tests")]
    lines += ["", "(timeouts count as killed: an infinite loop is caught; the score is killed "
              "over killed + survived + no tests)", "", f"{len(survivors)} survivors:"]
    lines += [f"  {name}" for name in sorted(survivors)]
    return "\n".join(lines)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    which = parser.add_mutually_exclusive_group(required=True)
    which.add_argument("--fast", action="store_true", help=f"modules {', '.join(FAST)}")
    which.add_argument("--full", action="store_true", help="every core module")
    which.add_argument("--modules", nargs="+", choices=CORE, metavar="MODULE",
                       help=f"some of {', '.join(CORE)}")
    which.add_argument("--report", action="store_true", help="print the last results only")
    parser.add_argument("--survivors", action="store_true",
                        help="rerun only the mutants that survived the last run")
    parser.add_argument("--functions", nargs="+", metavar="NAME",
                        help="only the mutants of these functions or methods")
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 2)
    args = parser.parse_args(argv)
    modules = FAST if args.fast else CORE if args.full or args.report else args.modules
    status = 0 if args.report else run(modules, args.workers, args.survivors,
                                       args.functions)
    print(table(modules, args.functions))
    return status


if __name__ == "__main__":
    sys.exit(main())

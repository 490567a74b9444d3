"""Mutation testing of mechdyn's core: per module of mechdyn/simulate, compile, derive and
kernels, a seeded random sample of mutants, each run against the tests that reach it.

    python benchmarks/mutation.py --sample 100 --seed 1                # the whole table
    python benchmarks/mutation.py --sample 5 --seed 1 --modules compile/codegen simulate/events
    python benchmarks/mutation.py --sample 100 --seed 1 --budget-minutes 120 --workers 2
    python benchmarks/mutation.py --report --sample 100 --seed 1       # recorded results only
    python benchmarks/mutation.py --show compile/codegen:17            # a mutant's diff
    python benchmarks/mutation.py --sample 100 --seed 1 --survivors    # rerun the survivors
    python benchmarks/mutation.py --map                                # build the test map only

A mutant is one small textual edit found on the module's syntax tree (:func:`mutants`);
the sample is drawn from all of a module's mutants with ``random.Random(f"{seed}:{module}")``
(a smaller sample is the beginning of a larger one). The tests that reach a mutant come
from a map by lines, built once by running the quick suite under coverage.py, one context a
test (``mutation_probe.py``). Each worker runs a fork server in a copy of the repository
(``mutation_server.py``: pytest, mechdyn and the tests imported once); each mutant runs in
a forked child that changes the imported code in memory and runs the reaching tests,
fastest first, stopping at the first failure; a kill counts where the unmutated package
passes the same tests up to the failing one. Results are kept per mutant under
``mutants/results/``: a decided mutant is not run again (``--survivors`` reruns the
survivors after tests were added). Everything else: docs/mutation.md.
"""
from __future__ import annotations

import argparse
import ast
import bisect
import contextlib
import difflib
import functools
import hashlib
import io
import json
import math
import os
import random
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
import tokenize
from dataclasses import dataclass
from datetime import date
from itertools import accumulate
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
WORK = ROOT / "mutants"
PROBE = Path(__file__).with_name("mutation_probe.py")
SERVER = Path(__file__).with_name("mutation_server.py")
PACKAGES = ("simulate", "compile", "derive", "kernels")
COPIED = ("mechdyn", "tests", "benchmarks", "models", "validation", "docs", "examples", ".ci",
          "README.md", "pyproject.toml")
# Not marked slow, but six minutes long: left out of the map, so no mutant runs it.
DESELECTED = ["tests/test_drive_trains.py::"
              "test_stiff_coupling_runs_implicit_and_matches_the_rigid_drive"]
HARNESS_TESTS = "tests/test_mutation_harness.py"      # test this file, not mechdyn: no map
PYTEST = ["-m", "pytest", "-q", "-p", "no:cacheprovider", "-o", "addopts=", "-m", "not slow",
          "-p", "mutation_probe", "--hypothesis-profile=mutation"]
# Where Python hands work to mechdyn's numba-compiled code: the integration loop, and every
# scene function and numerical routine compiled into it, run below Integration
# (kernels/api.py); compile/numba_model.py loads and calls a scene's numba functions. A
# compiled function called from Python is in the map itself (numba reports such calls to
# the profiler), one called from compiled code is not.
COMPILED_ENTRIES = ["mechdyn/kernels/api.py", "mechdyn/compile/numba_model.py"]
MAP_FORMAT = 3            # raise it when the map's recording (mutation_probe.py) changes
JIT_DECORATORS = {"njit", "jit", "intrinsic", "cfunc", "overload", "vectorize", "guvectorize"}
STARTUP = 2.0             # s: a forked child's pytest start-up and collection
KERNEL_COMPILE = 30.0     # s: numba compiling the kernels afresh (12-15 s on a quiet core)
CAP = 60.0                # s of a mutant's tests after which it counts as not killed (capped)
CAPPED = 6                # the exit status of a run the probe stopped at the cap
NOT_LOADED = 7            # ... of a child whose mutated module did not execute (mutation_server)
DECIDED = {"killed", "timeout", "import error", "survived", "capped", "no tests"}
CAUGHT = {"killed", "timeout", "import error"}
UNCAUGHT = DECIDED - CAUGHT   # the survivors of the table, rerun by --survivors


# ---------------------------------------------------------------- mutation operators

@dataclass(frozen=True)
class Mutant:
    start: tuple          # (line, column): 1-based line, column in characters
    end: tuple
    text: str             # replaces the source from start to end
    kind: str


SYMBOLS = {ast.Add: "+", ast.Sub: "-", ast.Mult: "*", ast.Div: "/", ast.FloorDiv: "//",
           ast.Pow: "**", ast.Lt: "<", ast.LtE: "<=", ast.Gt: ">", ast.GtE: ">=",
           ast.Eq: "==", ast.NotEq: "!=", ast.Is: "is", ast.IsNot: "is not", ast.In: "in",
           ast.NotIn: "not in", ast.And: "and", ast.Or: "or"}
SWAPS = {ast.Add: "-", ast.Sub: "+", ast.Mult: "/", ast.Div: "*", ast.FloorDiv: "/",
         ast.Pow: "*", ast.Lt: "<=", ast.LtE: "<", ast.Gt: ">=", ast.GtE: ">", ast.Eq: "!=",
         ast.NotEq: "==", ast.Is: "is not", ast.IsNot: "is", ast.In: "not in",
         ast.NotIn: "in", ast.And: "or", ast.Or: "and"}
MESSAGES = {"print", "warn", "_warn", "_warnings", "announce"}    # calls not mutated
_SKIPPED_TOKENS = {tokenize.COMMENT, tokenize.NL, tokenize.NEWLINE, tokenize.INDENT,
                   tokenize.DEDENT, tokenize.ENCODING, tokenize.ENDMARKER}


class _Sites(ast.NodeVisitor):
    """Collects the mutants of a module (:func:`mutants`)."""

    def __init__(self, source):
        self.lines = source.splitlines(keepends=True)
        self.tokens = [(t.start, t.end, t.string) for t in
                       tokenize.generate_tokens(io.StringIO(source).readline)
                       if t.type not in _SKIPPED_TOKENS]
        self.starts = [t[0] for t in self.tokens]
        self.found = []

    def start(self, node):          # ast's columns count UTF-8 bytes; ours characters
        return node.lineno, len(self.lines[node.lineno - 1].encode()[:node.col_offset].decode())

    def end(self, node):
        line = self.lines[node.end_lineno - 1].encode()
        return node.end_lineno, len(line[:node.end_col_offset].decode())

    def add(self, start, end, text, kind):
        self.found.append(Mutant(start, end, text, kind))

    def operator(self, words, low, high):
        """The index of the first token of ``words`` (e.g. "is not") in [low, high)."""
        words = words.split()
        i = bisect.bisect_left(self.starts, low)
        while i < len(self.tokens) and self.tokens[i][0] < high:
            if [t[2] for t in self.tokens[i:i + len(words)]] == words:
                return i, i + len(words) - 1
            i += 1
        return None

    def swap(self, op, low, high, kind, suffix=""):
        found = self.operator(SYMBOLS[type(op)] + suffix, low, high)
        if found:
            self.add(self.tokens[found[0]][0], self.tokens[found[1]][1],
                     SWAPS[type(op)] + suffix, kind)

    def visit_BinOp(self, node):
        if type(node.op) in SWAPS:
            self.swap(node.op, self.end(node.left), self.start(node.right), "arithmetic")
        self.generic_visit(node)

    def visit_AugAssign(self, node):
        if type(node.op) in SWAPS:
            self.swap(node.op, self.end(node.target), self.start(node.value), "arithmetic",
                      suffix="=")
        self.generic_visit(node)

    def visit_Compare(self, node):
        left = node.left
        for op, right in zip(node.ops, node.comparators):
            self.swap(op, self.end(left), self.start(right), "comparison")
            left = right
        self.generic_visit(node)

    def visit_BoolOp(self, node):
        for left, right in zip(node.values, node.values[1:]):
            self.swap(node.op, self.end(left), self.start(right), "boolean")
        self.generic_visit(node)

    def visit_UnaryOp(self, node):
        if isinstance(node.op, (ast.Not, ast.USub)):       # the operator and its spaces go
            i = bisect.bisect_left(self.starts, self.start(node))
            self.add(self.tokens[i][0], self.tokens[i + 1][0], "",
                     "not x -> x" if isinstance(node.op, ast.Not) else "-x -> x")
        self.generic_visit(node)

    def visit_Constant(self, node):
        value = node.value
        if isinstance(value, bool):
            self.add(self.start(node), self.end(node), repr(not value), "True/False")
        elif isinstance(value, int):
            new = "1" if value == 0 else "0" if value == 1 else repr(value + 1)
            self.add(self.start(node), self.end(node), new, "constant")
        elif isinstance(value, float) and math.isfinite(2 * value):
            new = "1.0" if value == 0 else "0.0" if value == 1 else repr(2 * value)
            self.add(self.start(node), self.end(node), new, "constant")

    def visit_Return(self, node):
        if node.value is not None and not isinstance(node.value, ast.Constant):
            self.add(self.start(node.value), self.end(node.value), "None", "return None")
        self.generic_visit(node)

    def visit_If(self, node):
        for word in ("True", "False"):
            self.add(self.start(node.test), self.end(node.test), word, f"if {word}")
        self.generic_visit(node)

    def visit_Break(self, node):
        self.add(self.start(node), self.end(node), "continue", "break/continue")

    def visit_Continue(self, node):
        self.add(self.start(node), self.end(node), "break", "break/continue")

    # Not mutated: what is raised, messages (f-strings, printed or warned), annotations,
    # decorators (numba's compile options: cache, inline, error model).
    def visit_Raise(self, node):
        pass

    def visit_JoinedStr(self, node):
        pass

    def visit_Call(self, node):
        func = node.func
        name = func.id if isinstance(func, ast.Name) else func.attr \
            if isinstance(func, ast.Attribute) else None
        if name not in MESSAGES:
            self.generic_visit(node)

    def visit_FunctionDef(self, node):
        for default in node.args.defaults + [d for d in node.args.kw_defaults if d]:
            self.visit(default)
        for statement in node.body:
            self.visit(statement)

    visit_AsyncFunctionDef = visit_FunctionDef

    def visit_ClassDef(self, node):
        for statement in node.body:
            self.visit(statement)

    def visit_AnnAssign(self, node):
        if node.value is not None:
            self.visit(node.value)


def mutants(source: str) -> list:
    """Every mutant of a module's source, in source order: arithmetic swaps (+ -, * /,
    // -> /, ** -> *, also in += and the like), comparison swaps (< <=, > >=, == !=,
    is / is not, in / not in), and / or, ``not x`` -> ``x``, ``-x`` -> ``x``, numbers
    (0 -> 1, 1 -> 0, an integer c -> c + 1, a float c -> 2c), True / False, ``return
    expr`` -> ``return None`` (expr not a constant), an ``if`` condition -> True and ->
    False, break / continue; nothing inside ``raise``, f-strings, messages, annotations
    or decorators, and no edit that leaves the text as it was."""
    sites = _Sites(source)
    sites.visit(ast.parse(source))
    unique = {m: None for m in sites.found if _span(source, m) != m.text}
    return sorted(unique, key=lambda m: (m.start, m.end, m.text))


def _offsets(source):
    return [0, *accumulate(len(line) for line in source.splitlines(keepends=True))]


def _span(source, mutant) -> str:
    offsets = _offsets(source)
    return source[offsets[mutant.start[0] - 1] + mutant.start[1]:
                  offsets[mutant.end[0] - 1] + mutant.end[1]]


def apply(source: str, mutant: Mutant) -> str:
    """The source with the mutant's edit made."""
    offsets = _offsets(source)
    start = offsets[mutant.start[0] - 1] + mutant.start[1]
    return source[:start] + mutant.text + source[offsets[mutant.end[0] - 1] + mutant.end[1]:]


def one_line(source: str, mutant: Mutant) -> str:
    """``line: old  ->  new`` (the lines the edit touches, stripped)."""
    first, last = mutant.start[0], mutant.end[0]
    old = " ".join(line.strip() for line in source.splitlines()[first - 1:last])
    new = apply(source, mutant).splitlines()[first - 1].strip()   # the edit has no newline
    return f"{first}: {old}  ->  {new}"


def diff(source: str, mutant: Mutant, name: str) -> str:
    return "".join(difflib.unified_diff(source.splitlines(keepends=True),
                                        apply(source, mutant).splitlines(keepends=True),
                                        name, name + " (mutant)", n=2))


def sample(population: int, size: int, seed, module: str) -> list:
    """``size`` indices of ``population`` mutants drawn with a generator seeded by
    ``seed`` and the module (all when fewer), in the order drawn (a run cut short by its
    time box has decided a random part of the sample): a smaller sample is the beginning
    of a larger one."""
    order = list(range(population))
    random.Random(f"{seed}:{module}").shuffle(order)
    return order[:size]


def wilson(successes: int, n: int, z: float = 1.959964) -> tuple:
    """The 95 % Wilson score interval of a proportion."""
    if n == 0:
        return (0.0, 1.0)
    p = successes / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z / (1 + z * z / n) * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n))
    return (max(0.0, centre - half), min(1.0, centre + half))


# ---------------------------------------------------------------- which tests reach a line

@dataclass(frozen=True)
class Scope:
    first: int            # the code object's first line (its first decorator's, if any)
    last: int
    name: str             # qualified name
    jitted: bool          # compiled by numba (or inside such a function)


def scopes(source: str) -> list:
    """The functions of a module, outermost first. Compiled (``jitted``): a function
    decorated by numba, one inside it, and in a module that calls numba's decorators
    as functions (``cfunc(signature)(implementation)``, as compile/mode_entry.py does),
    every module-level function named outside its own body."""
    found = []
    tree = ast.parse(source)
    by_call = _compiled_by_call(tree)

    def walk(node, prefix, jitted):
        for child in ast.iter_child_nodes(node):
            if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef)):
                first = min([d.lineno for d in child.decorator_list] + [child.lineno])
                inner = jitted or child.name in by_call and not prefix or any(
                    _decorator_name(d) in JIT_DECORATORS for d in child.decorator_list)
                found.append(Scope(first, child.end_lineno, prefix + child.name, inner))
                walk(child, prefix + child.name + ".", inner)
            elif isinstance(child, ast.ClassDef):
                walk(child, prefix + child.name + ".", jitted)
            else:
                walk(child, prefix, jitted)
    walk(tree, "", False)
    return found


def _compiled_by_call(tree) -> set:
    """Names of module-level functions that may be handed to a numba decorator called
    as a function: every one named outside its own body, where the module makes such a
    call (none otherwise)."""
    decorators = {id(d) for node in ast.walk(tree)
                  if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef))
                  for d in node.decorator_list}
    from_numba = {alias.asname or alias.name for node in ast.walk(tree)
                  if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("numba")
                  for alias in node.names if alias.name in JIT_DECORATORS}

    def numba_call(node):
        function = node.func
        if isinstance(function, ast.Attribute):         # numba.cfunc(...)
            return function.attr in JIT_DECORATORS and getattr(function.value, "id", "") == "numba"
        return getattr(function, "id", None) in from_numba
    if not any(isinstance(node, ast.Call) and id(node) not in decorators and numba_call(node)
               for node in ast.walk(tree)):
        return set()
    functions = {node.name: node for node in tree.body
                 if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef))}
    named = set()
    for name, function in functions.items():
        inside = {id(n) for n in ast.walk(function)}
        named |= {name for n in ast.walk(tree) if isinstance(n, ast.Name) and n.id == name
                  and id(n) not in inside}
    return named


def _decorator_name(node):
    node = node.func if isinstance(node, ast.Call) else node
    return node.attr if isinstance(node, ast.Attribute) else getattr(node, "id", None)


def innermost(found: list, line: int):
    """The innermost function whose lines hold ``line``, or None (module or class body)."""
    holding = [s for s in found if s.first <= line <= s.last]
    return max(holding, key=lambda s: s.first) if holding else None


def _module_file(dotted):
    """mechdyn/a/b.py or mechdyn/a/b/__init__.py for ``mechdyn.a.b``, relative to ROOT
    (None for a name that is not one of mechdyn's modules)."""
    if dotted.split(".")[0] != "mechdyn":
        return None
    path = ROOT.joinpath(*dotted.split("."))
    for candidate in (path.with_suffix(".py"), path / "__init__.py"):
        if candidate.is_file():
            return candidate.relative_to(ROOT).as_posix()
    return None


def _imports(path: Path, package: str) -> set:
    """The files of the mechdyn modules a module imports (``package``: its own)."""
    files = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            files.update(_module_file(alias.name) for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parts = package.split(".")[:len(package.split(".")) - node.level + 1]
                base = ".".join(parts + ([base] if base else []))
            submodules = {_module_file(f"{base}.{alias.name}") for alias in node.names}
            submodules.discard(None)      # names, not modules: the module itself
            files.update(submodules or {_module_file(base)})
    files.discard(None)
    return files


def _dotted(rel):
    return rel[:-3].replace("/", ".").removesuffix(".__init__")


@functools.cache
def importers(rel: str) -> frozenset:
    """The files of the mechdyn modules that import ``rel`` directly."""
    found = set()
    for path in (ROOT / "mechdyn").rglob("*.py"):
        other = path.relative_to(ROOT).as_posix()
        package = _dotted(other) if other.endswith("__init__.py") else \
            _dotted(other).rpartition(".")[0]
        if rel in _imports(path, package):
            found.add(other)
    return frozenset(found)


@functools.cache
def testing(rel: str) -> frozenset:
    """The test files (tests/..., relative to ROOT) that import ``rel`` directly."""
    return frozenset(path.relative_to(ROOT).as_posix()
                     for path in (ROOT / "tests").rglob("test_*.py")
                     if rel in _imports(path, "tests"))


@functools.cache
def compiled_files() -> frozenset:
    """mechdyn's files whose code numba compiles, and the mechdyn modules they import
    (their globals are frozen into the machine code): a mutant of one of them must not
    meet numba's cache of the unmutated code."""
    todo = []
    for path in sorted((ROOT / "mechdyn").rglob("*.py")):
        rel = path.relative_to(ROOT).as_posix()
        if any(s.jitted for s in scopes(path.read_text())):
            todo.append(rel)
    found = set()
    while todo:
        rel = todo.pop()
        if rel not in found:
            found.add(rel)
            package = _dotted(rel) if rel.endswith("__init__.py") else _dotted(rel).rpartition(".")[0]
            todo.extend(_imports(ROOT / rel, package))
    return frozenset(found)


def statement_lines(source: str, line: int) -> range:
    """The lines of the innermost statement holding ``line`` (of a compound statement,
    its header only: ``if``, ``for``, ``def`` ... up to its body), where the tests that
    ran the edited code ran some line of."""
    best = None
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.stmt) and node.lineno <= line <= node.end_lineno:
            body = [n for field in ("body", "orelse", "finalbody", "handlers")
                    for n in getattr(node, field, []) if isinstance(n, ast.AST)]
            last = min([n.lineno for n in body if n.lineno > node.lineno] or
                       [node.end_lineno + 1]) - 1 if body else node.end_lineno
            if node.lineno <= line <= max(last, node.lineno):
                span = range(node.lineno, max(last, node.lineno) + 1)
                if best is None or len(span) < len(best):
                    best = span
    return best or range(line, line + 1)


class ReachMap:
    """Which tests ran which lines of mechdyn, how long each took (map mode of
    mutation_probe.py, one run of the quick suite under coverage.py)."""

    def __init__(self, data):
        self.data = data
        self.tests = data["tests"]       # [[node id, seconds, outcome], ...] as collected
        self.lines = {f: {int(k): set(v) for k, v in lines.items()}
                      for f, lines in data["lines"].items()}
        self.usable = {i for i, (_, _, outcome) in enumerate(self.tests) if outcome == "passed"}
        self.compiled = compiled_files()           # of the sources now: cheap, and a
                                                   # change of the rule needs no new map
        self.outside = {rel: set(lines) for rel, lines in data["outside"].items()}
        self.compiled_runs = set().union(*(self.touching(rel) for rel in COMPILED_ENTRIES))

    def touching(self, rel):
        return set().union(*self.lines.get(rel, {}).values())

    def reaching(self, rel: str, line: int, found: list, source: str) -> list:
        """The usable tests that reach ``line`` of ``rel``, fastest first: those that ran
        a line of the statement holding it (:func:`statement_lines`); where that statement
        ran outside any test (a module or class body, a default argument, a function run
        while a module is imported), also every test that ran a line of the file; for
        numba-compiled code (and the bodies of the modules whose globals it reads), whose
        lines run as machine code, every test that ran a line of the file or ran
        compiled code: first those that ran a line of it or of a module importing it (the
        Python that calls it: a stuck friction's mode entries for the mode numerics), and
        those of test files importing it (that call its compiled functions from Python),
        then the others, each part fastest first."""
        scope = innermost(found, line)
        if scope is not None and scope.jitted or scope is None and rel in self.compiled:
            files = testing(rel)
            near = self.touching(rel).union(
                *(self.touching(f) for f in importers(rel) if f not in COMPILED_ENTRIES),
                {i for i, (node, _, _) in enumerate(self.tests)
                 if node.split("::")[0] in files}) & self.usable
            rest = (self.compiled_runs & self.usable) - near
            return [i for part in (near, rest)
                    for i in sorted(part, key=lambda i: (self.tests[i][1], i))]
        else:
            span = statement_lines(source, line)
            ran = self.lines.get(rel, {})
            reached = set().union(*(ran.get(n, ()) for n in span))
            if scope is None or any(n in self.outside.get(rel, ()) for n in span):
                reached |= self.touching(rel)
        return sorted(reached & self.usable, key=lambda i: (self.tests[i][1], i))

    def expected(self, tests: list, cap=math.inf) -> float:
        """Seconds the unmutated run of these tests takes (as measured in the map); with
        a ``cap``, the run stopped by it (the cap and the test running when it passes)."""
        durations = [self.tests[i][1] for i in tests]
        return STARTUP + min(sum(durations), cap + max(durations, default=0.0))


MAPPED = ("mechdyn", "tests", "models", "validation", "README.md", "docs/guide",
          "pyproject.toml")


def digest() -> str:
    """A hash of what the map depends on (MAPPED: mechdyn, the tests and the files that
    name tests, as models/ and the code blocks of README.md and docs/guide/ do; not their
    prose, the rest of docs/, .ci/, benchmarks/ or the harness's own tests) and of the
    map's format (MAP_FORMAT)."""
    h = hashlib.blake2b(f"map format {MAP_FORMAT}".encode(), digest_size=8)
    for name in MAPPED:
        path = ROOT / name
        for file in sorted(path.rglob("*")) if path.is_dir() else [path]:
            rel = file.relative_to(ROOT).as_posix()
            if file.is_file() and "__pycache__" not in file.parts and rel != HARNESS_TESTS:
                content = file.read_bytes()
                if rel == "README.md" or rel.startswith("docs/guide/"):
                    content = b"".join(re.findall(rb"```.*?```", content, re.S))
                h.update(rel.encode() + b"\0" + content)
    return h.hexdigest()


def load_map(workers: int = 1) -> ReachMap:
    """The test map of the current sources, built (the quick suite, once) if missing."""
    path = WORK / f"map-{digest()}.json"
    if not path.is_file():
        build_map(path, workers)
    return ReachMap(json.loads(path.read_text()))


def build_map(path: Path, workers: int, paths=("tests",)):
    mirror = copy_repository(WORK / "slots" / "map")
    parts = mirror / "map-parts"
    parts.mkdir()
    cache = Path(tempfile.mkdtemp(prefix="cache-", dir=WORK))   # cold, as every mutant's
    env = dict(os.environ, MECHDYN_MUTATION_MAP=str(parts), PYTHONPATH=str(mirror),
               MECHDYN_TESTS_CACHE_FOLDER=str(cache), MECHDYN_CACHE=str(cache))
    command = [sys.executable, *PYTEST, *[a for t in DESELECTED for a in ("--deselect", t)],
               f"--ignore={HARNESS_TESTS}",
               *(["-n", str(workers)] if workers > 1 else []), *paths]
    print(f"building the test map (the quick suite under a profiler, {workers} "
          f"process{'es' * (workers > 1)}): mutants/{path.name}", flush=True)
    start = time.perf_counter()
    status = subprocess.run(command, cwd=mirror, env=env, stdin=subprocess.DEVNULL).returncode
    seconds = time.perf_counter() - start
    shutil.rmtree(cache, ignore_errors=True)
    if status not in (0, 1):
        sys.exit(f"the map's test run stopped with status {status}")
    path.write_text(json.dumps(merge_parts(parts, seconds)))
    shutil.rmtree(mirror)


def merge_parts(parts: Path, seconds: float) -> dict:
    """The probe's files (one a process, one a test's child process) as one map."""
    tests, collect, lines, outside = {}, {}, {}, {}
    children = [_json(p) for p in sorted(parts.glob("child-*.json"))]
    if None in children:       # a child killed or held to a file size limit by its test
        print(f"{children.count(None)} child processes left an unfinished record: ignored")
        children = [c for c in children if c is not None]
    processes = [json.loads(p.read_text()) for p in sorted(parts.glob("part-*.json"))]
    for data in processes:            # not what xdist's controller saw of its workers' tests
        tests.update({n: t for n, t in data["tests"].items() if "seconds" in t})
        collect.update(data["collect"])
    collected = processes[0]["order"] if processes else []     # the same in xdist's workers
    order = [n for n in collected if n in tests] + sorted(set(tests) - set(collected))
    index = {nodeid: i for i, nodeid in enumerate(order)}
    for data in children + processes:
        for rel, ran in data["lines"].items():
            for line, contexts in ran.items():
                for context in contexts:
                    if context == "":
                        outside.setdefault(rel, set()).add(int(line))
                    elif context in index:
                        lines.setdefault(rel, {}).setdefault(line, set()).add(index[context])
    failing = [n for n in order if tests[n].get("outcome") == "failed"]
    if failing:
        print(f"{len(failing)} tests failed unmutated (never used to judge a mutant):",
              *failing, sep="\n  ")
    return {"date": date.today().isoformat(), "commit": commit(), "seconds": round(seconds),
            "tests": [[n, tests[n].get("seconds", 0.0), tests[n].get("outcome", "passed")]
                      for n in order],
            "collect": collect,
            "outside": {rel: sorted(found) for rel, found in outside.items()},
            "lines": {rel: {line: sorted(ids) for line, ids in ran.items()}
                      for rel, ran in lines.items()}}


def _json(path):
    try:
        return json.loads(path.read_text())
    except ValueError:
        return None


# ---------------------------------------------------------------- running mutants

def copy_repository(target: Path) -> Path:
    """A copy of the files the tests read (modification times kept), with the probe, the
    fork server and a ``sitecustomize.py`` (:data:`SITE`) at the top."""
    shutil.rmtree(target, ignore_errors=True)
    target.mkdir(parents=True)
    ignore = shutil.ignore_patterns("__pycache__", "*.pyc", ".hypothesis")
    for name in COPIED:
        source = ROOT / name
        if source.is_dir():
            shutil.copytree(source, target / name, ignore=ignore)
        else:
            shutil.copy2(source, target / name)
    for helper in (PROBE, SERVER):
        shutil.copy2(helper, target / helper.name)
    (target / "sitecustomize.py").write_text(SITE)
    return target


# Run by every process started with the copy on PYTHONPATH: a process a test starts while
# the map is built records its lines; one a mutant's test starts with the cache folder it
# inherited uses the mutant's own, and keys its scenes by the digest of the sources the
# mutant's process took before the edit (else a test that fills a cache in a process of
# its own and reads it in its own process finds other keys: a kill that is no kill).
SITE = """import os
if os.environ.get('MECHDYN_MUTATION_MAP') and os.environ.get('MECHDYN_MUTATION_TEST'):
    import mutation_probe
    mutation_probe.child()
_sub = os.environ.get('MECHDYN_MUTATION_SUBCACHE')
if _sub and os.environ.get('MECHDYN_CACHE') == os.environ.get('MECHDYN_MUTATION_INHERITED'):
    os.environ['MECHDYN_CACHE'] = os.environ['MECHDYN_TESTS_CACHE_FOLDER'] = _sub
_digest = os.environ.get('MECHDYN_MUTATION_DIGEST')
if _digest:                  # key scenes as the mutant's own process does (mutation_server)
    import importlib.abc, importlib.util, sys

    class _SameDigest(importlib.abc.MetaPathFinder):
        def find_spec(self, name, path, target=None):
            if name != 'mechdyn.keys':
                return None
            sys.meta_path.remove(self)
            spec = importlib.util.find_spec(name)
            run = spec.loader.exec_module

            def exec_module(module):
                run(module)
                module._SOURCES = _digest
            spec.loader.exec_module = exec_module
            return spec
    sys.meta_path.insert(0, _SameDigest())
"""


@dataclass
class Job:
    module: str           # e.g. "simulate/driver"
    index: int            # in the module's mutants
    mutant: Mutant
    source: str           # the module's source
    tests: list           # node ids, fastest first
    timeout: float        # s: the time box of the (capped) run
    how: str              # "function", "module" or "compiled" (mutation_server.mutate)
    cap: float = CAP      # s of tests, after which a mutant not killed counts as capped
    control_timeout: float = None   # the uncapped control's time box (None: ``timeout``)
    scope: Scope = None   # the outermost function holding the edit (None: module level)

    @property
    def rel(self):
        return f"mechdyn/{self.module}.py"

    @property
    def key(self):
        return key(self.source, self.mutant)

    @property
    def scenes(self) -> str:
        """Where the mutant's scenes come from: "warm" (the shared cache: a mutant that
        cannot change generated code), "fresh" (an empty folder: derive/ and compile/),
        "private" (also mechdyn's kernels compiled afresh: a mutant of compiled code)."""
        if self.how == "compiled":
            return "private"
        return "fresh" if self.module.split("/")[0] in ("derive", "compile") else "warm"

    def record(self) -> dict:
        return {"module": self.module, "index": self.index, "key": self.key,
                "kind": self.mutant.kind, "line": self.mutant.start[0],
                "diff": one_line(self.source, self.mutant), "tests": len(self.tests),
                "timeout": round(self.timeout), "how": self.how}


def key(source, mutant) -> str:
    """Names a mutant's result: a hash of the mutated module."""
    return hashlib.blake2b(apply(source, mutant).encode(), digest_size=6).hexdigest()


def result_path(module, index, name) -> Path:
    return WORK / "results" / module.replace("/", ".") / f"{index}-{name}.json"


def how_to_mutate(rel, line, found, test_map) -> tuple:
    """("compiled" | "function" | "module", the outermost function holding the line)."""
    holding = [s for s in found if s.first <= line <= s.last]
    outermost = min(holding, key=lambda s: s.first) if holding else None
    scope = innermost(found, line)
    if scope is not None and scope.jitted or scope is None and rel in test_map.compiled:
        return "compiled", outermost
    return ("function" if outermost else "module"), outermost


def compiled_order(compiled: set) -> dict:
    """{dotted name: the mechdyn modules it imports, directly or not} of the compiled set's
    modules that numba compiles code in, dependencies first: a compiled mutant executes
    again its own module and those of them that import it
    (:func:`executed_again`)."""
    chosen = {rel for rel in compiled if rel.split("/")[1] in PACKAGES + ("analyse",)
              and any(s.jitted for s in scopes((ROOT / rel).read_text()))}
    order = {}

    def visit(rel):
        if _dotted(rel) in order:
            return order[_dotted(rel)]
        order[_dotted(rel)] = None                    # an import cycle ends here
        package = _dotted(rel) if rel.endswith("__init__.py") else _dotted(rel).rpartition(".")[0]
        found = set()
        for dependency in sorted(_imports(ROOT / rel, package)):
            found |= {_dotted(dependency)} | (visit(dependency) or set())
        del order[_dotted(rel)]
        order[_dotted(rel)] = found
        return found
    for rel in sorted(chosen):
        visit(rel)
    return {name: deps for name, deps in order.items()
            if _module_file(name) in chosen}


def executed_again(module: str, compiled: dict) -> list:
    """The modules a compiled mutant of ``module`` (dotted) executes again, in order: its
    own, then those of the compiled set that import it."""
    return [module] + [name for name, deps in compiled.items()
                       if module in deps and name != module]


class Server:
    """A fork server (mutation_server.py) in a copy of the repository: mechdyn, pytest and
    the tests imported once; each run a forked child."""

    def __init__(self, slot: Path, warm: Path):
        self.slot, self.warm = slot, warm
        warm.mkdir(mode=0o700, parents=True, exist_ok=True)
        env = dict(os.environ, PYTHONPATH=str(slot), MECHDYN_CACHE=str(warm),
                   MECHDYN_TESTS_CACHE_FOLDER=str(warm), MECHDYN_MUTATION_INHERITED=str(warm))
        for name in ("MECHDYN_MUTATION_MAP", "MECHDYN_MUTATION_TEST", "MECHDYN_TEST_CACHE"):
            env.pop(name, None)
        self.process = subprocess.Popen(
            [sys.executable, SERVER.name, "tests", f"--ignore={HARNESS_TESTS}"], cwd=slot,
            env=env, stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True,
            stderr=open(slot.with_name(slot.name + "-server.log"), "w"),
            start_new_session=True)
        ready = self.process.stdout.readline()
        if not ready:
            raise RuntimeError(f"the fork server in {slot} did not start: see "
                               f"{slot.name}-server.log")

    def ask(self, request: dict) -> dict:
        self.process.stdin.write(json.dumps(request) + "\n")
        self.process.stdin.flush()
        reply = self.process.stdout.readline()
        if not reply:
            raise RuntimeError(f"the fork server in {self.slot} stopped")
        return json.loads(reply)

    def close(self):
        with contextlib.suppress(ProcessLookupError):
            os.killpg(self.process.pid, signal.SIGKILL)
        self.process.wait()


def run_mutant(job: Job, server: Server, compiled=None) -> dict:
    """Runs ``job`` (a control, unmutated, where its index is -1) in a forked child of
    ``server``; its record with the outcome."""
    record = dict(job.record(), commit=commit(), date=date.today().isoformat())
    if not job.tests:
        return dict(record, outcome="no tests", seconds=0.0)
    slot = server.slot
    cache = slot.with_name(slot.name + "-cache")
    shutil.rmtree(cache, ignore_errors=True)
    cache.mkdir(mode=0o700)
    scenes = job.scenes
    if scenes != "private":        # processes the tests start load the unmutated kernels
        (cache / "kernels").symlink_to(server.warm / "kernels", target_is_directory=True)
    log = cache.with_name(cache.name + ".log")
    request = {"file": job.rel, "module": _dotted(job.rel), "tests": job.tests,
               "cap": job.cap, "timeout": job.timeout, "log": str(log),
               "cache": str(server.warm if scenes == "warm" else cache),
               "subcache": str(cache),
               "source": apply(job.source, job.mutant) if job.index >= 0 else None,
               "how": job.how,
               "compiled": executed_again(_dotted(job.rel), compiled) if compiled else [],
               "qualname": job.scope.name if job.scope else None,
               "first": job.scope.first if job.scope else None}
    reply = server.ask(request)
    outcome, detail = classify(reply["status"], log.read_text(errors="replace"))
    shutil.rmtree(cache, ignore_errors=True)
    return dict(record, outcome=outcome, detail=detail, seconds=reply["seconds"])


class LeftOut:
    """Tests that failed with the unmutated package after other tests of a mutant's run
    (a control, :func:`decide`): left out of every later run, kept in
    ``mutants/left-out-<map digest>.json`` and listed under the table."""

    def __init__(self, path: Path):
        self.path, self.lock = path, threading.Lock()
        self.tests = set(json.loads(path.read_text())) if path.is_file() else set()

    def add(self, test: str):
        with self.lock:
            self.tests.add(test)
            self.path.write_text(json.dumps(sorted(self.tests), indent=1))


def decide(job: Job, server: Server, left_out: LeftOut, controls: Path,
           compiled=None) -> dict:
    """Runs a mutant. A kill (or a timeout) stands where the unmutated package passes the
    same tests in the same order up to the one that failed (:func:`control`); where it
    fails too, that test is left out and the mutant run again."""
    start = time.perf_counter()
    for _ in range(5):
        job.tests = [t for t in job.tests if t not in left_out.tests]
        result = run_mutant(job, server, compiled)
        if result["outcome"] not in ("killed", "timeout"):
            break
        failing = control(job, result, server, controls)
        if failing is None:
            result["controlled"] = True
            break
        if not failing.startswith("tests/"):
            result.update(outcome="error", detail=f"unmutated too: {failing}")
            break
        left_out.add(failing)
    else:
        result.update(outcome="error", detail="tests kept failing unmutated")
    return dict(result, total_seconds=round(time.perf_counter() - start, 1))


_CONTROL_LOCKS: dict = {}      # a control's file -> the lock its first runner holds
_CONTROL_LOCKS_LOCK = threading.Lock()


def control(job: Job, result: dict, server: Server, controls: Path):
    """The unmutated package's run of the mutant's tests up to the one that failed (all
    of them after a crash or a timeout), uncapped, in the time box of those tests' whole
    run, with the mutant's caches (:attr:`Job.scenes`): None where it passes, else the test
    that failed or what happened. Kept by the list of tests and the caches: kills at the
    same place are checked once."""
    failed = _node(result["detail"])
    tests = job.tests[:job.tests.index(failed) + 1] if failed in job.tests else job.tests
    name = "\n".join([job.scenes, *tests])
    path = controls / (hashlib.blake2b(name.encode(), digest_size=8).hexdigest() + ".json")
    with _CONTROL_LOCKS_LOCK:
        lock = _CONTROL_LOCKS.setdefault(path, threading.Lock())
    with lock:                                 # one run per list of tests, whoever asks
        if not path.is_file():
            plain = Job(job.module, -1, Mutant((1, 0), (1, 0), "", "none"), job.source,
                        tests, job.control_timeout or job.timeout, job.how, math.inf)
            outcome = run_mutant(plain, server)
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(json.dumps({k: outcome[k]
                                        for k in ("outcome", "detail", "seconds")}))
    outcome = json.loads(path.read_text())
    if outcome["outcome"] == "survived":
        return None
    return _node(outcome["detail"]) or f"{outcome['outcome']} {outcome['detail']}".strip()


def _node(detail: str):
    """The node id in pytest's ``FAILED <id> - <message>`` (or ERROR) line, or None."""
    if detail.startswith(("FAILED ", "ERROR ")):
        return detail.split(" ", 1)[1].split(" - ")[0]
    return None


def classify(status, output: str) -> tuple:
    """(outcome, detail) of a mutant's pytest run from its exit status and output."""
    lines = output.splitlines()
    failed = [l for l in lines if l.startswith(("FAILED ", "ERROR "))]
    if status is None:
        return "timeout", ""
    if status == 0:
        return "survived", ""
    if status == CAPPED:
        said = next((l for l in lines if "mutation cap" in l), "")
        return "capped", said[said.find("mutation cap"):].strip(" !")
    if status == 1:
        return "killed", failed[0] if failed else ""
    if status == NOT_LOADED:
        return "import error", next((l for l in lines if l.startswith("mutant does not load")), "")
    if status in (2, 4) and any(("during collection" in l or "ERROR collecting" in l or
                                 "found no collectors" in l) for l in lines):
        return "import error", next((l for l in lines if "ERROR collecting" in l), "").strip(" _")
    if status < 0:
        return "killed", f"crashed: signal {-status}"
    return "error", f"pytest status {status}: " + " | ".join(lines[-5:])


@functools.cache
def commit() -> str:
    return subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, text=True,
                          capture_output=True).stdout.strip() or "?"


# ---------------------------------------------------------------- the table

def modules_of(names=None) -> list:
    if names:
        return names
    return sorted(p.relative_to(ROOT / "mechdyn").with_suffix("").as_posix()
                  for package in PACKAGES for p in (ROOT / "mechdyn" / package).glob("*.py"))


def selection(modules, size, seed) -> list:
    """(module, source, mutants, sampled indices) for each module."""
    chosen = []
    for module in modules:
        path = ROOT / "mechdyn" / f"{module}.py"
        if not path.is_file():
            sys.exit(f"no module mechdyn/{module}.py")
        source = path.read_text()
        found = mutants(source)
        chosen.append((module, source, found, sample(len(found), size, seed, module)))
    return chosen


def recorded(module, index, source, mutant):
    path = result_path(module, index, key(source, mutant))
    return json.loads(path.read_text()) if path.is_file() else None


def table(chosen, wall=None, left_out=()) -> str:
    """The scores of the sampled mutants' recorded results, and the survivors."""
    head = ["| module | mutants | sampled | decided | killed | timeout | import error | "
            "survived | capped | no tests | score (95 % interval) |",
            "|" + " --- |" + " ---: |" * 10]
    rows, survivors, seconds, commits = [], [], [], set()
    total = dict.fromkeys(("population", "sampled", *DECIDED), 0)
    packages = {}
    for module, source, found, indices in chosen:
        count = dict.fromkeys(DECIDED, 0)
        for index in indices:
            result = recorded(module, index, source, found[index])
            if result and result["outcome"] in DECIDED:
                count[result["outcome"]] += 1
                seconds.append(result.get("total_seconds", result["seconds"]))
                commits.add(result["commit"])
                if result["outcome"] in UNCAUGHT:
                    survivors.append(f"{module}:{index} ({result['outcome']}, "
                                     f"{result['kind']}) {result['diff']}")
        package = packages.setdefault(module.split("/")[0], dict.fromkeys(total, 0))
        for k, v in [("population", len(found)), ("sampled", len(indices)), *count.items()]:
            total[k] += v
            package[k] += v
        rows.append(_row(module, len(found), len(indices), count))
    for name, package in sorted(packages.items()):
        rows.append(_row(f"**{name}/**", package["population"], package["sampled"], package))
    rows.append(_row("**all**", total["population"], total["sampled"], total))
    run = (f"wall time {wall / 60:.1f} min, " if wall is not None else "") + (
        f"{len(seconds)} mutants decided, {sum(seconds) / 60:.1f} min of runs "
        f"(median {sorted(seconds)[len(seconds) // 2]:.0f} s a mutant)" if seconds else "nothing decided")
    lines = [f"Mutation scores, {date.today().isoformat()}, commit {commit()} (results of "
             f"commits {', '.join(sorted(commits)) or '-'}); {run}", "", *head, *rows, "",
             "score = (killed + timeout + import error) / decided; decided = killed + "
             "timeout + import error + survived + capped + no tests (capped: no test failed "
             "in the first CAP seconds of its tests, counted as not killed)", "",
             f"{len(survivors)} survivors (`--show MODULE:INDEX` for the diff):",
             *[f"- {s}" for s in sorted(survivors)]]
    if left_out:
        lines += ["", f"{len(left_out)} tests left out (they fail unmutated after other "
                      "tests of a mutant's run):", *[f"- {t}" for t in sorted(left_out)]]
    return "\n".join(lines)


def _row(module, population, sampled, count) -> str:
    decided = sum(count[k] for k in DECIDED)
    caught = sum(count[k] for k in CAUGHT)
    low, high = wilson(caught, decided)
    score = f"{100 * caught / decided:.0f} % ({100 * low:.0f}-{100 * high:.0f} %)" \
        if decided else "-"
    return (f"| {module} | {population} | {sampled} | {decided} | {count['killed']} | "
            f"{count['timeout']} | {count['import error']} | {count['survived']} | "
            f"{count['capped']} | {count['no tests']} | {score} |")


# ---------------------------------------------------------------- the run

def jobs(chosen, test_map: ReachMap, survivors_only=False, cap=CAP) -> list:
    """The sampled mutants still to run (or, with ``survivors_only``, those that
    survived or were capped), round robin over the modules: a time box leaves every module
    a share. Each stops as capped after ``cap`` seconds of tests without a failure."""
    queues = []
    for module, source, found, indices in chosen:
        rel = f"mechdyn/{module}.py"
        found_scopes = scopes(source)
        queue = []
        for index in indices:
            result = recorded(module, index, source, found[index])
            wanted = result is None or result["outcome"] not in DECIDED
            if survivors_only:
                wanted = result is not None and result["outcome"] in UNCAUGHT
            if not wanted:
                continue
            mutant = found[index]
            tests = test_map.reaching(rel, mutant.start[0], found_scopes, source)
            how, scope = how_to_mutate(rel, mutant.start[0], found_scopes, test_map)
            compile_ = KERNEL_COMPILE if how == "compiled" else 0.0
            queue.append(Job(module, index, mutant, source,
                             [test_map.tests[i][0] for i in tests],
                             time_box(test_map.expected(tests, cap) + compile_), how, cap,
                             time_box(test_map.expected(tests) + compile_), scope))
        queues.append(queue)
    return [job for round_ in _round_robin(queues) for job in round_]


def time_box(expected: float) -> float:
    """Seconds a mutant's run may take, from the unmutated run's ``expected`` seconds in
    the map: 10 times that, at least 120 s (a test that found its scenes compiled by an
    earlier test in the map's run compiles them afresh in a mutant's empty cache) and at
    most 300 s, or twice that where longer (the map's times were taken under the
    profiler, which doubles them): a surviving mutant is never cut off as a timeout."""
    return max(120.0, min(10 * expected, max(300.0, 2 * expected)))


def _round_robin(queues):
    for i in range(max((len(q) for q in queues), default=0)):
        yield [q[i] for q in queues if i < len(q)]


def run(todo: list, workers: int, budget_minutes=None, left_out=None) -> float:
    """Runs the jobs on ``workers`` copies of the repository; stops starting new ones
    once the budget is spent. The wall time."""
    controls = WORK / "controls" / digest()
    left_out = left_out or LeftOut(WORK / f"left-out-{digest()}.json")
    start = time.perf_counter()
    deadline = math.inf if budget_minutes is None else start + 60 * budget_minutes
    lock, queue, done, stop = threading.Lock(), list(todo), [0], threading.Event()

    compiled = compiled_order(compiled_files())
    servers = []

    def work(number):
        server = Server(copy_repository(WORK / "slots" / f"w{number}"), WORK / f"warm-w{number}")
        servers.append(server)
        while True:
            with lock:
                if not queue or time.perf_counter() > deadline:
                    server.close()
                    return
                job = queue.pop(0)
            result = decide(job, server, left_out, controls, compiled)
            if stop.is_set():                  # interrupted: killed by us, not by a test
                return
            path = result_path(job.module, job.index, job.key)
            if result["outcome"] != "error":
                path.parent.mkdir(parents=True, exist_ok=True)
                path.write_text(json.dumps(result, indent=1))
            with lock:
                done[0] += 1
                print(f"[{done[0]}/{len(todo)}] {job.module}:{job.index} {result['outcome']} "
                      f"in {result['total_seconds']:.0f} s ({len(job.tests)} tests, box "
                      f"{job.timeout:.0f} s{', controlled' * bool(result.get('controlled'))})"
                      f" {result.get('detail', '')[:100]}", flush=True)

    threads = [threading.Thread(target=work, args=(i,)) for i in range(workers)]
    for thread in threads:
        thread.start()
    try:
        for thread in threads:
            thread.join()
    except KeyboardInterrupt:
        stop.set()
        with lock:
            queue.clear()
        for server in servers:
            server.close()
        for thread in threads:
            thread.join()
        raise
    if queue:
        print(f"budget spent: {len(queue)} mutants not started")
    return time.perf_counter() - start


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--sample", type=int, default=100, metavar="N",
                        help="mutants a module (all where fewer; default 100)")
    parser.add_argument("--seed", default="1", metavar="S", help="of the sample (default 1)")
    parser.add_argument("--modules", nargs="+", metavar="MODULE",
                        help="e.g. simulate/driver compile/codegen (default: every module "
                             f"of {', '.join(PACKAGES)})")
    parser.add_argument("--workers", type=int, default=2, help="mutants run at once")
    parser.add_argument("--budget-minutes", type=float, metavar="M",
                        help="start no mutant after M minutes")
    parser.add_argument("--cap-seconds", type=float, default=CAP, metavar="C",
                        help="a mutant no test killed in C s of its tests counts as capped, "
                             f"not killed (default {CAP:.0f}; inf for none)")
    parser.add_argument("--map-workers", type=int, default=1,
                        help="pytest-xdist processes of the map's test run (default 1)")
    action = parser.add_mutually_exclusive_group()
    action.add_argument("--report", action="store_true", help="the table of recorded results")
    action.add_argument("--show", metavar="MODULE:INDEX", help="a mutant's diff")
    action.add_argument("--survivors", action="store_true", help="rerun only the survivors")
    action.add_argument("--map", action="store_true", help="build the test map only")
    args = parser.parse_args(argv)
    if args.show:
        module, _, index = args.show.rpartition(":")
        source = (ROOT / "mechdyn" / f"{module}.py").read_text()
        mutant = mutants(source)[int(index)]
        print(f"{args.show}: {mutant.kind}\n" + diff(source, mutant, f"mechdyn/{module}.py"))
        return 0
    WORK.mkdir(exist_ok=True)
    if args.map:
        load_map(args.map_workers)
        return 0
    chosen = selection(modules_of(args.modules), args.sample, args.seed)
    wall, left_out = None, LeftOut(WORK / f"left-out-{digest()}.json")
    if not args.report:
        todo = jobs(chosen, load_map(args.map_workers), args.survivors, args.cap_seconds)
        print(f"{len(todo)} mutants to run on {args.workers} workers", flush=True)
        wall = run(todo, args.workers, args.budget_minutes, left_out)
    print(table(chosen, wall, left_out.tests))
    return 0


if __name__ == "__main__":
    sys.exit(main())

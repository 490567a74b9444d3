"""The pure parts of benchmarks/mutation.py: which mutants a source has, the seeded
sample, the Wilson interval, and which function holds a line."""
import importlib.util
import sys
import time
from pathlib import Path

import pytest

_PATH = Path(__file__).resolve().parents[1] / "benchmarks" / "mutation.py"
_SPEC = importlib.util.spec_from_file_location("mutation_harness", _PATH)
mutation = importlib.util.module_from_spec(_SPEC)
sys.modules[_SPEC.name] = mutation          # dataclasses look their module up
_SPEC.loader.exec_module(mutation)

SOURCE = '''"""A docstring: 1 + 2 is not mutated."""
import numba


def f(a: int = 1, b=2.5) -> float:
    """Neither is this one < 3."""
    if a < b and not a:
        raise ValueError(f"a {a + 1} is too small")
    while a:
        a -= 1
        break
    print("message", 1 + 1)
    return -a ** 2 / b


@numba.njit(cache=True)
def g(x):
    def h():
        return x is None
    return x in (0, True)


class C:
    k = 3
'''


def _edits(source):
    return [(m.kind, mutation.one_line(source, m)) for m in mutation.mutants(source)]


def test_every_operator_once_and_nothing_in_docstrings_raise_messages_or_annotations():
    assert _edits(SOURCE) == [
        ("constant", "5: def f(a: int = 1, b=2.5) -> float:  ->  def f(a: int = 0, b=2.5) -> float:"),
        ("constant", "5: def f(a: int = 1, b=2.5) -> float:  ->  def f(a: int = 1, b=5.0) -> float:"),
        ("if False", "7: if a < b and not a:  ->  if False:"),
        ("if True", "7: if a < b and not a:  ->  if True:"),
        ("comparison", "7: if a < b and not a:  ->  if a <= b and not a:"),
        ("boolean", "7: if a < b and not a:  ->  if a < b or not a:"),
        ("not x -> x", "7: if a < b and not a:  ->  if a < b and a:"),
        ("arithmetic", "10: a -= 1  ->  a += 1"),
        ("constant", "10: a -= 1  ->  a -= 0"),
        ("break/continue", "11: break  ->  continue"),
        ("-x -> x", "13: return -a ** 2 / b  ->  return a ** 2 / b"),
        ("return None", "13: return -a ** 2 / b  ->  return None"),
        ("arithmetic", "13: return -a ** 2 / b  ->  return -a * 2 / b"),
        ("constant", "13: return -a ** 2 / b  ->  return -a ** 3 / b"),
        ("arithmetic", "13: return -a ** 2 / b  ->  return -a ** 2 * b"),
        ("return None", "19: return x is None  ->  return None"),
        ("comparison", "19: return x is None  ->  return x is not None"),
        ("return None", "20: return x in (0, True)  ->  return None"),
        ("comparison", "20: return x in (0, True)  ->  return x not in (0, True)"),
        ("constant", "20: return x in (0, True)  ->  return x in (1, True)"),
        ("True/False", "20: return x in (0, True)  ->  return x in (0, False)"),
        ("constant", "24: k = 3  ->  k = 4"),
    ]


def test_every_mutant_compiles_and_edits_one_place():
    for mutant in mutation.mutants(SOURCE):
        changed = mutation.apply(SOURCE, mutant)
        compile(changed, "mutant", "exec")
        assert changed.replace(mutant.text, "", 1) != SOURCE or mutant.text == ""
        assert len(changed.splitlines()) == len(SOURCE.splitlines())


def test_multi_word_operators_and_columns_after_non_ascii_text():
    source = 'x = "µ" if a is not b else c\ny = a not in b\n'
    assert [mutation.one_line(source, m) for m in mutation.mutants(source)] == [
        '1: x = "µ" if a is not b else c  ->  x = "µ" if a is b else c',
        "2: y = a not in b  ->  y = a in b"]


def test_the_sample_depends_on_seed_and_module_only_and_grows_by_extension():
    first = mutation.sample(500, 20, 1, "simulate/driver")
    assert first == mutation.sample(500, 20, 1, "simulate/driver")
    assert len(set(first)) == 20 and set(first) <= set(range(500))
    assert first != mutation.sample(500, 20, 2, "simulate/driver")
    assert first != mutation.sample(500, 20, 1, "simulate/events")
    assert mutation.sample(500, 5, 1, "simulate/driver") == first[:5]
    assert sorted(mutation.sample(7, 100, 1, "kernels/layout")) == list(range(7))


def test_wilson_interval_against_a_hand_computed_value():
    # 8 of 10, z = 1.96: centre (0.8 + 0.19208) / 1.38416 = 0.716737; half-width
    # 1.96 / 1.38416 * sqrt(0.016 + 0.009604) = 0.226582
    low, high = mutation.wilson(8, 10, z=1.96)
    assert (low, high) == (pytest.approx(0.490155, abs=2e-6), pytest.approx(0.943319, abs=2e-6))
    assert mutation.wilson(8, 10) == pytest.approx((0.4902, 0.9433), abs=1e-4)
    assert mutation.wilson(0, 0) == (0.0, 1.0)
    assert mutation.wilson(5, 5)[1] == 1.0


def test_a_line_belongs_to_its_innermost_function():
    found = mutation.scopes(SOURCE)
    assert [(s.name, s.first, s.jitted) for s in found] == [
        ("f", 5, False), ("g", 16, True), ("g.h", 18, True)]
    assert mutation.innermost(found, 10).name == "f"
    assert mutation.innermost(found, 16).name == "g"       # the decorator's line
    assert mutation.innermost(found, 19).name == "g.h"
    assert mutation.innermost(found, 20).name == "g"
    assert mutation.innermost(found, 2) is None             # module level
    assert mutation.innermost(found, 24) is None            # class body


def test_a_function_compiled_by_calling_numba_counts_as_compiled():
    """compile/mode_entry.py's way: ``cfunc(signature)(implementation)`` in a function;
    numpy's ``vectorize`` called the same way is not numba."""
    by_call = ("from numba import cfunc\n\n\ndef impl(x):\n    return x\n\n\n"
               "def build(sig):\n    return cfunc(sig)(impl)\n\n\ndef unused():\n"
               "    return 1\n")
    assert [(s.name, s.jitted) for s in mutation.scopes(by_call)] == [
        ("impl", True), ("build", False), ("unused", False)]
    by_numpy = by_call.replace("from numba import cfunc", "from numpy import vectorize as cfunc")
    assert not any(s.jitted for s in mutation.scopes(by_numpy))


def test_time_box():
    assert [mutation.time_box(e) for e in (1, 20, 100, 400)] == [120, 200, 300, 800]


def test_outcomes_from_pytest_status():
    assert mutation.classify(1, "x\nFAILED tests/a.py::t - boom\n") == (
        "killed", "FAILED tests/a.py::t - boom")
    assert mutation.classify(0, "") == ("survived", "")
    assert mutation.classify(None, "") == ("timeout", "")
    assert mutation.classify(2, "1 error during collection")[0] == "import error"
    assert mutation.classify(4, "__ ERROR collecting tests/a.py __\nERROR: found no collectors "
                                "for tests/a.py::t") == ("import error", "ERROR collecting tests/a.py")
    assert mutation.classify(-11, "")[0] == "killed"
    assert mutation.classify(7, "Traceback\nmutant does not load: TypingError: x\n") == (
        "import error", "mutant does not load: TypingError: x")
    assert mutation.classify(4, "usage")[0] == "error"


def test_workers_share_the_queue_and_a_spent_budget_starts_nothing(tmp_path, monkeypatch):
    """run() with the fork servers left out: each worker has its own server, every job
    runs once, two workers' kills at the same test share one control run, results land
    in mutants/results/, and a spent budget starts no job."""
    monkeypatch.setattr(mutation, "WORK", tmp_path)
    monkeypatch.setattr(mutation, "copy_repository", lambda target: target)

    class Server:
        def __init__(self, slot, warm):
            self.slot = slot

        def close(self):
            pass
    monkeypatch.setattr(mutation, "Server", Server)
    ran = []

    def fake(job, server, compiled=None):  # killed; its control (index -1) passes
        ran.append((job.index, server.slot.name))
        if job.index < 0:
            time.sleep(0.2)             # the other worker asks for the same control meanwhile
        outcome = "survived" if job.index < 0 else "killed"
        return dict(job.record(), outcome=outcome, detail=f"FAILED {job.tests[0]} - x",
                    seconds=0.0, commit="c", date="d")
    monkeypatch.setattr(mutation, "run_mutant", fake)
    found = mutation.mutants(SOURCE)
    todo = [mutation.Job("x/y", i, m, SOURCE, ["t"], 60.0, "function")
            for i, m in enumerate(found)]
    mutation.run(todo, workers=2)
    assert sorted(i for i, _ in ran) == [-1] + list(range(len(found)))   # one control
    assert {slot for _, slot in ran} <= {"w0", "w1"}
    assert len(list((tmp_path / "results" / "x.y").glob("*.json"))) == len(found)
    ran.clear()
    mutation.run(todo, workers=2, budget_minutes=0)
    assert ran == []


def _pytest_with_probe(folder, order, cap):
    import subprocess
    code = ("import sys, pytest, mutation_probe\n"
            f"sys.exit(pytest.main(['-q', '-x', '-p', 'no:cacheprovider', '-o', 'addopts=', "
            f"'tests'], plugins=[mutation_probe.Ordered({order!r}, float({str(cap)!r}))]))")
    done = subprocess.run([sys.executable, "-c", code], cwd=folder, capture_output=True,
                          text=True, env={**__import__("os").environ, "PYTHONPATH": str(folder)})
    return done.returncode, done.stdout + done.stderr


def test_a_run_past_the_cap_stops_between_tests_and_counts_as_not_killed(tmp_path):
    """The probe in mutant mode: after ``cap`` seconds of tests no further test starts,
    the run exits with the capped status and classify() calls it capped (not killed, not
    survived); without a cap the same tests all run and pass, in the order given."""
    import shutil
    shutil.copy(_PATH.with_name("mutation_probe.py"), tmp_path)
    (tmp_path / "tests").mkdir()
    (tmp_path / "tests" / "test_a.py").write_text(
        "import time\nSEEN = []\n" + "".join(
            f"def test_{i}():\n    time.sleep(0.1)\n    SEEN.append({i})\n"
            f"    assert SEEN[0] == 3\n" for i in range(4)))
    order = [f"tests/test_a.py::test_{i}" for i in (3, 0, 1, 2)]
    status, output = _pytest_with_probe(tmp_path, order, 0.05)    # passed after the first
    assert status == mutation.CAPPED
    outcome, detail = mutation.classify(status, output)
    assert outcome == "capped" and detail.startswith("mutation cap: 1 tests passed")
    status, output = _pytest_with_probe(tmp_path, order, float("inf"))
    assert status == 0 and "4 passed" in output


def test_a_capped_run_is_expected_to_end_after_the_cap_and_the_test_then_running():
    """The time box of a mutant's run follows the cap: start-up, the cap and the longest
    test (the one running when the cap passes); uncapped, all."""
    data = {"tests": [["tests/a.py::t1", 30.0, "passed"], ["tests/a.py::t2", 50.0, "passed"],
                      ["tests/b.py::t3", 40.0, "passed"]], "lines": {}, "outside": {}}
    reach = mutation.ReachMap(data)
    assert reach.expected([0, 1, 2]) == mutation.STARTUP + 120.0
    assert reach.expected([0, 1, 2], cap=60.0) == mutation.STARTUP + 60.0 + 50.0
    assert reach.expected([0], cap=60.0) == mutation.STARTUP + 30.0


LINES = '''import math

LIMIT = 3


def f(a, b=2):
    if (a > LIMIT
            and b):
        return math.sqrt(a)
    return -a


def g(a):
    return [a + k for k in range(2)]
'''


def test_the_statement_holding_a_line_is_its_header_for_compound_statements():
    assert list(mutation.statement_lines(LINES, 7)) == [7, 8]     # the if's two lines
    assert list(mutation.statement_lines(LINES, 8)) == [7, 8]
    assert list(mutation.statement_lines(LINES, 9)) == [9]
    assert list(mutation.statement_lines(LINES, 6)) == [6]        # a default argument
    assert list(mutation.statement_lines(LINES, 3)) == [3]


def test_a_mutant_is_reached_by_the_tests_that_ran_its_statement():
    """Line-level: a test that ran f without reaching its last line does not judge a
    mutant there; a line run outside any test (module level, def's default) is reached
    by every test that ran the file; a line no test ran has no tests."""
    rel = "mechdyn/toy.py"
    data = {"tests": [["t::a", 1.0, "passed"], ["t::b", 2.0, "passed"],
                      ["t::c", 0.5, "passed"], ["t::d", 0.1, "failed"]],
            "lines": {rel: {"7": [0, 1, 3], "8": [1], "9": [0], "10": [1], "14": [2]}},
            "outside": {rel: [1, 3, 6, 13]}}
    reach = mutation.ReachMap(data)
    reach.compiled = set()
    found = mutation.scopes(LINES)
    assert reach.reaching(rel, 9, found, LINES) == [0]
    assert reach.reaching(rel, 10, found, LINES) == [1]
    assert reach.reaching(rel, 7, found, LINES) == [0, 1]          # not the failing one
    assert reach.reaching(rel, 3, found, LINES) == [2, 0, 1]       # fastest first
    assert reach.reaching(rel, 6, found, LINES) == [2, 0, 1]
    assert reach.reaching("mechdyn/other.py", 9, found, LINES) == []


def test_a_compiled_mutant_runs_first_the_tests_that_ran_its_file_then_every_compiled_run():
    """numba-compiled lines are unseen by coverage: every test that ran compiled code
    reaches them, those that ran Python of the file (or of its importers) first."""
    rel = "mechdyn/toy.py"
    data = {"tests": [["t::a", 1.0, "passed"], ["t::b", 2.0, "passed"], ["t::c", 0.5, "passed"]],
            "lines": {rel: {"9": [1]}, "mechdyn/kernels/api.py": {"1": [0, 1, 2]}},
            "outside": {}}
    reach = mutation.ReachMap(data)
    reach.compiled = {rel}
    assert reach.reaching(rel, 3, mutation.scopes(LINES), LINES) == [1, 2, 0]
    assert "mechdyn/compile/mode_entry.py" in mutation.importers("mechdyn/compile/mode_numerics.py")
    assert "tests/test_band_linalg.py" in mutation.testing("mechdyn/compile/band_linalg.py")
    assert "tests/test_sparse_kernel.py" in mutation.testing("mechdyn/kernels/iteration.py")


def test_how_a_mutant_is_made_in_memory():
    class Map:
        compiled = {"mechdyn/kernels/x.py"}
    found = mutation.scopes(SOURCE)
    assert mutation.how_to_mutate("mechdyn/a.py", 10, found, Map)[0] == "function"
    assert mutation.how_to_mutate("mechdyn/a.py", 10, found, Map)[1].name == "f"
    assert mutation.how_to_mutate("mechdyn/a.py", 19, found, Map)[0] == "compiled"
    assert mutation.how_to_mutate("mechdyn/a.py", 24, found, Map)[0] == "module"
    assert mutation.how_to_mutate("mechdyn/kernels/x.py", 24, found, Map)[0] == "compiled"


def test_a_compiled_mutant_executes_again_its_module_and_those_that_import_it():
    compiled = mutation.compiled_order(mutation.compiled_files())
    names = list(compiled)
    again = mutation.executed_again("mechdyn.kernels.linalg", compiled)
    assert again[0] == "mechdyn.kernels.linalg"
    assert {"mechdyn.kernels.loop", "mechdyn.compile.mode_numerics"} <= set(again)
    assert names.index("mechdyn.kernels.iteration") < names.index("mechdyn.kernels.loop")
    assert "mechdyn.kernels.loop" not in mutation.executed_again(
        "mechdyn.compile.mode_numerics", compiled)


def _server():
    spec = importlib.util.spec_from_file_location("mutation_server_under_test",
                                                  _PATH.with_name("mutation_server.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_fork_server_swaps_a_function_and_executes_a_module_again(tmp_path, monkeypatch):
    """mutate(): a function's code is swapped where every reference sees it (a method,
    a decorated function); a module-level edit executes the module again and points the
    references other modules took (``from x import y``) at the new objects, a number only
    under its own name."""
    server = _server()
    toy = tmp_path / "mechdyn_toy_a.py"
    toy.write_text("LIMIT = 3\n\n\nclass C:\n    def m(self):\n        return LIMIT + 1\n"
                   "\n\n@__import__('functools').cache\ndef twice(x):\n    return 2 * x\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.delitem(sys.modules, "mechdyn_toy_a", raising=False)
    monkeypatch.delitem(sys.modules, "mechdyn_toy_b", raising=False)
    (tmp_path / "mechdyn_toy_b.py").write_text(
        "from mechdyn_toy_a import LIMIT, C, twice\nTHREE = 3\n")
    import mechdyn_toy_a
    import mechdyn_toy_b
    source = toy.read_text()
    held = mechdyn_toy_b.C()
    assert (held.m(), mechdyn_toy_b.twice(5)) == (4, 10)
    how = server.mutate({"module": "mechdyn_toy_a", "how": "function", "qualname": "C.m",
                         "first": 5, "source": source.replace("LIMIT + 1", "LIMIT - 1")})
    assert how == "function" and held.m() == 2                     # the same object
    how = server.mutate({"module": "mechdyn_toy_a", "how": "function", "qualname": "twice",
                         "first": 9, "source": source.replace("2 * x", "2 + x")})
    assert how == "function" and mechdyn_toy_b.twice(5) == 7        # its cache emptied
    how = server.mutate({"module": "mechdyn_toy_a", "how": "module", "qualname": None,
                         "first": None, "source": source.replace("LIMIT = 3", "LIMIT = 4")})
    assert how == "module"
    assert (mechdyn_toy_a.LIMIT, mechdyn_toy_b.LIMIT, mechdyn_toy_b.THREE) == (4, 4, 3)
    assert mechdyn_toy_b.C is mechdyn_toy_a.C and mechdyn_toy_b.C().m() == 5


def test_a_process_a_mutant_s_test_starts_keys_scenes_by_the_mutant_s_digest(tmp_path):
    """The copy's sitecustomize.py makes a process started by a test key its scenes by
    the digest the mutant's own process took before the edit: a cache one fills, the
    other reads (a test filling the cache in a process of its own failed on every
    mutant: a kill that was no kill)."""
    import os
    import subprocess
    (tmp_path / "sitecustomize.py").write_text(mutation.SITE)
    env = dict(os.environ, PYTHONPATH=f"{tmp_path}{os.pathsep}{_PATH.parents[1]}",
               MECHDYN_MUTATION_DIGEST="0123456789abcdef")
    code = "import mechdyn.keys as k; print(k.source_digest())"
    done = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                          text=True, check=True)
    assert done.stdout.strip() == "0123456789abcdef"
    env.pop("MECHDYN_MUTATION_DIGEST")
    done = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                          text=True, check=True)
    assert len(done.stdout.strip()) == 16 and done.stdout.strip() != "0123456789abcdef"

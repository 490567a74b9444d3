"""The fork server of benchmarks/mutation.py: one process that has imported pytest,
mechdyn and every test module once, and runs each mutant in a forked child.

Started by the harness in a copy of the repository (``python mutation_server.py``, the
copy first on ``sys.path``), it reads one request a line on stdin and answers one line
on stdout (JSON). A request names the module, its mutated source (none for a control
run of the unmutated package), the line of the edit, how to mutate, the tests in their
order, the cap and the time box. The child

- writes the mutated source into the copy, so that processes a test starts import the
  mutant (the server puts the original back after the child ends);
- changes its own, already imported mechdyn (:func:`mutate`):
  - ``function``: the edited function's code object is swapped for the mutant's
    (``function.__code__``), found by its qualified name in the compiled mutated module;
  - ``module``: the module is executed again from the mutated source, in its own
    namespace, and every reference other modules hold to a replaced object is pointed
    at the new one (module-level constants, class bodies, functions not found);
  - ``compiled``: numba's disk cache is switched off and every module of the compiled
    set (in the request, dependencies first) is executed again: numba compiles the
    kernels afresh in the child, with the mutant;
- runs the tests with pytest in-process, stopping at the first failure, and exits with
  pytest's status (7 where the mutated module does not execute or compile: an import
  error); the server answers with it (``None`` for a child killed at its time
  box) and the seconds taken.

A mutant's scenes: the digest of mechdyn's sources (``mechdyn.keys.source_digest``) is
taken once in the server, before any mutant, so a child's scenes are keyed as the
unmutated ones; a request names the cache folder the child uses (a warm one shared by the
mutants that cannot change generated code, an empty one for the others) and the one for
processes its tests start (``MECHDYN_MUTATION_SUBCACHE``: they import the mutated file and
compile their scenes there, keyed by the same digest, ``MECHDYN_MUTATION_DIGEST``, so that a
cache one process fills is read by the other as it is in the unmutated suite).
"""
import importlib
import json
import os
import pkgutil
import signal
import sys
import time
import traceback
from pathlib import Path

ROOT = Path(__file__).resolve().parent
MUTATED = ("simulate", "compile", "derive", "kernels")    # the harness's PACKAGES
NOT_LOADED, NOT_LOADED_STATUS = "mutant does not load:", 7     # its module fails to execute
PYTEST_ARGS = ["-q", "-x", "-p", "no:cacheprovider", "-o", "addopts=", "-m", "not slow",
               "--hypothesis-profile=mutation"]


def _mechdyn_modules():
    """Imports every module of mechdyn but the command line's ``__main__``. A module of
    the mutated packages that fails to import stops the server: each of its mutants would
    otherwise count as killed (an import error) though the unmutated module fails too."""
    import mechdyn
    for info in pkgutil.walk_packages(mechdyn.__path__, "mechdyn."):
        if info.name == "mechdyn.cli.__main__":
            continue
        try:
            importlib.import_module(info.name)
        except ImportError:              # an optional dependency missing (report/, cli/)
            if info.name.split(".")[1] in MUTATED:
                raise


def prepare(test_paths):
    """Imports mechdyn's modules and the test modules (a collection), and fixes the
    digest of the sources before any mutant is written."""
    import pytest
    import mechdyn.keys
    mechdyn.keys.source_digest()
    _mechdyn_modules()
    status = pytest.main(["--collect-only", "-q", "-p", "no:cacheprovider", "-o", "addopts=",
                          *test_paths])
    if status not in (0, 5):
        raise SystemExit(f"the tests could not be collected unmutated (status {status})")


# ---------------------------------------------------------------- mutating in memory

def _named(code, qualname, first) -> bool:
    """Whether ``code`` is the function ``qualname`` defined at line ``first`` (Python
    3.10's code objects have no qualified name: their own name then)."""
    if code.co_firstlineno != first:
        return False
    if hasattr(code, "co_qualname"):
        return code.co_qualname == qualname
    return code.co_name == qualname.rsplit(".", 1)[-1]


def _find_code(code, qualname, first):
    if _named(code, qualname, first):
        return code
    for constant in code.co_consts:
        if hasattr(constant, "co_code"):
            found = _find_code(constant, qualname, first)
            if found is not None:
                return found
    return None


def _unwrap(value) -> list:
    """The objects behind a class attribute or module global, outermost first: wrappers
    (``functools.cache``, a numba dispatcher, a property) and the plain functions."""
    if isinstance(value, (staticmethod, classmethod)):
        return _unwrap(value.__func__)
    if isinstance(value, property):
        return [f for part in (value.fget, value.fset, value.fdel) if part
                for f in _unwrap(part)]
    if hasattr(value, "py_func"):                          # a numba dispatcher
        return [value] + _unwrap(value.py_func)
    wrapped = getattr(value, "__wrapped__", None)
    return [value] + (_unwrap(wrapped) if wrapped is not None else [])


def _live_function(module, qualname, first) -> tuple:
    """(the function object of ``qualname`` defined at line ``first``, the wrappers
    around it), or (None, [])."""
    owner = module
    parts = qualname.split(".")
    for part in parts[:-1]:
        owner = vars(owner).get(part) if hasattr(owner, "__dict__") else None
        if owner is None:
            return None, []
    value = vars(owner).get(parts[-1]) if hasattr(owner, "__dict__") else None
    chain = _unwrap(value) if value is not None else []
    for function in chain:
        code = getattr(function, "__code__", None)
        if code is not None and _named(code, qualname, first):
            return function, chain
    return None, []


def _swap_function(module, code, qualname, first):
    """Swaps the live function's code for the mutant's and empties the caches wrapped
    around it (a value cached unmutated would hide the mutant); False where it is not
    found."""
    new = _find_code(code, qualname, first)
    live, chain = _live_function(module, qualname, first)
    if new is None or live is None or len(new.co_freevars) != len(live.__code__.co_freevars):
        return False
    live.__code__ = new
    for wrapper in chain:
        if hasattr(wrapper, "cache_clear"):
            wrapper.cache_clear()
    return True


def _ours(module_name, module):
    path = getattr(module, "__file__", None) or ""
    return module_name.startswith("mechdyn") or path.startswith(str(ROOT))


def _execute_again(module, code):
    """Runs the module's (mutated) code again in its namespace and points every reference
    that mechdyn's and the tests' modules hold to an object it replaced at the new one
    (a number or a string only where it is held under the same name: they are shared)."""
    old = dict(vars(module))
    exec(code, vars(module))
    replaced = {id(value): (name, vars(module)[name]) for name, value in old.items()
                if not name.startswith("__") and name in vars(module)
                and vars(module)[name] is not value}
    for module_name, other in list(sys.modules.items()):
        if other is module or other is None or not _ours(module_name, other):
            continue
        for key, value in list(vars(other).items()):
            name, new = replaced.get(id(value), (None, None))
            if name is not None and (key == name or not isinstance(value, _SHARED)):
                setattr(other, key, new)


_SHARED = (int, float, complex, str, bytes, bool, type(None), tuple, frozenset)


def _compiled_again(modules):
    """numba's disk cache off (in mechdyn's modules executed from here on), then the
    compiled set executed again, dependencies first, from the files (the mutant's
    written): every kernel compiles afresh with the mutant."""
    import mechdyn.numba_cache
    mechdyn.numba_cache.CACHED = False
    for name in modules:
        module = importlib.import_module(name)
        path = Path(module.__file__)
        _execute_again(module, compile(path.read_text(), str(path), "exec"))


def mutate(request):
    """Changes the imported mechdyn as the request says (see the module's docstring)."""
    name = request["module"]
    module = importlib.import_module(name)
    code = compile(request["source"], module.__file__, "exec")
    how = request["how"]
    if how == "function" and _swap_function(module, code, request["qualname"],
                                            request["first"]):
        return "function"
    if how == "compiled":
        _compiled_again(request["compiled"])
        return "compiled"
    _execute_again(module, code)
    return "module"


# ---------------------------------------------------------------- the child

def _run_child(request):
    import pytest
    from mutation_probe import Ordered
    os.environ["MECHDYN_CACHE"] = os.environ["MECHDYN_TESTS_CACHE_FOLDER"] = request["cache"]
    os.environ["MECHDYN_MUTATION_SUBCACHE"] = request["subcache"]
    import mechdyn.keys
    os.environ["MECHDYN_MUTATION_DIGEST"] = mechdyn.keys.source_digest()    # taken unmutated
    os.environ["PYTHONDONTWRITEBYTECODE"] = "1"
    if request.get("source") is not None:
        Path(ROOT, request["file"]).write_text(request["source"])
        try:
            print(f"mutated in memory: {mutate(request)}", flush=True)
        except Exception as error:              # noqa: BLE001 (the mutant's import fails)
            traceback.print_exc()
            print(f"{NOT_LOADED} {type(error).__name__}: {str(error).splitlines()[0][:200]}"
                  if str(error) else f"{NOT_LOADED} {type(error).__name__}", flush=True)
            return NOT_LOADED_STATUS
    return pytest.main([*PYTEST_ARGS, *request["tests"]],
                       plugins=[Ordered(request["tests"], request["cap"])])


def run(request, answer):
    path = Path(ROOT, request["file"])
    original = path.read_bytes()
    start = time.perf_counter()
    pid = os.fork()
    if pid == 0:                                            # the child
        os.setpgid(0, 0)
        log = os.open(request["log"], os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
        os.dup2(log, 1)
        os.dup2(log, 2)
        status = 3
        try:
            status = int(_run_child(request))
        except BaseException:                               # noqa: BLE001 (reported)
            traceback.print_exc()
        finally:
            sys.stdout.flush()
            sys.stderr.flush()
            os._exit(status)
    deadline = start + request["timeout"]
    status = None
    while True:
        done, code = os.waitpid(pid, os.WNOHANG)
        if done:
            status = os.waitstatus_to_exitcode(code)
            break
        if time.perf_counter() > deadline:
            _kill(pid)
            os.waitpid(pid, 0)
            break
        time.sleep(0.02)
    _kill(pid)                                  # what the tests started and left behind
    if path.read_bytes() != original:
        path.write_bytes(original)
    answer({"status": status, "seconds": round(time.perf_counter() - start, 2)})


def _kill(group):
    try:
        os.killpg(group, signal.SIGKILL)
    except ProcessLookupError:
        pass


def main():
    protocol = os.fdopen(os.dup(1), "w")
    os.dup2(2, 1)                  # whatever imports print goes to stderr, not the answers
    sys.path.insert(0, str(ROOT))
    prepare(sys.argv[1:] or ["tests"])

    def answer(reply):
        protocol.write(json.dumps(reply) + "\n")
        protocol.flush()
    answer({"ready": True, "pid": os.getpid()})
    for line in sys.stdin:
        if line.strip():
            run(json.loads(line), answer)


if __name__ == "__main__":
    main()

"""Nothing kept is stale (``docs/caching.md``): each layer that keeps something — the
compiled code in memory and on disk, the derived equations, a sweep's parameter
template, a run's kept start — gives the fresh result when any input changes: an
element's attribute, a module constant, a closure's cell or a class attribute its
``work()`` reads, a parameter given as an expression of a swept one, an initial value
using it; in the same process and in a new one sharing the disk cache, whose result is
the one ``MECHDYN_CACHE=off`` gives.

The reference values are closed forms: a disc ``J = 1`` from ``phi = 1`` at rest under
the moment ``-g k phi`` swings as ``cos(sqrt(g k) t)``; under ``-k phi^3`` as the Jacobi
function ``cn(t, 1/2)``; a shoe brake ``f (P + Q) R`` with ``Q = 3 P`` stops a disc of
``I`` from ``omega_0`` after ``omega_0 I / (f (P + Q) R)``."""
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import sympy as sp
from scipy.special import ellipj

import mechdyn as md

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "mechdyn"

ELEMENT = '''
from dataclasses import dataclass
import numpy as np
import sympy as sp
import mechdyn as md

GAIN = {gain}


@dataclass(frozen=True)
class Spring(md.Element):
    """The moment -GAIN * LIST[0] * ARRAY[0] * FACTOR * scale * k * along**n."""
    k: object = 0
    along: object = None
    n: int = 1
    LIST = [{listed}]
    ARRAY = np.array([{array}])
    FACTOR = sp.Integer({factor})

    def __post_init__(self):
        super().__post_init__()
        self.convert("k")
        self.convert("along")

    def expressions(self):
        return {{"k": self.k, "along": self.along}}

    def scale(self):
        return 1

    def work(self, motion):
        angle = motion.position(self.along, self.name)
        gain = GAIN * self.LIST[0] * float(self.ARRAY[0]) * self.FACTOR * self.scale()
        return md.Work(forces=((-gain * motion.plain(self.k) * angle ** self.n, angle),))


def make_spring(scale):
    """A Spring class of its own scale (a closure)."""
    @dataclass(frozen=True)
    class Scaled(Spring):
        def scale(self):
            return scale
    return Scaled
'''

SCRIPT = '''
import sys
import sympy as sp
import mechdyn as md
import spring_module

n, scale, backend = int(sys.argv[1]), float(sys.argv[2]), sys.argv[3]
phi = md.coordinate("phi")
k = sp.Symbol("k", positive=True)
disc = md.Mechanism("disc", [phi])
disc.link("disc", J=1, angle=phi)
disc.add(spring_module.make_spring(scale)("spring", k=k, along=phi, n=n))
scene = md.Scene("swing", initial={phi: 1, md.speed(phi): 0}, t_end=1, rtol=1e-10,
                 backend=backend)
print(repr(disc.simulate(scene, {k: 1.0}).final(phi)))
'''


def write_module(folder, gain=1.0, listed=1.0, array=1.0, factor=1):
    (folder / "spring_module.py").write_text(ELEMENT.format(
        gain=gain, listed=listed, array=array, factor=factor))
    (folder / "swing.py").write_text(SCRIPT)


def run_script(folder, n=1, scale=1.0, backend="scipy", cache=None) -> float:
    """``phi(1)`` from a new process (the disk cache of these tests, or ``cache``)."""
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(folder), str(ROOT)])}
    if cache is not None:
        env["MECHDYN_CACHE"] = cache
    done = subprocess.run([sys.executable, str(folder / "swing.py"), str(n), str(scale),
                           backend], capture_output=True, text=True, env=env, timeout=600)
    assert done.returncode == 0, done.stderr
    return float(done.stdout.strip().splitlines()[-1])


def fresh_and_off(folder, **options) -> float:
    """A new process's ``phi(1)``, checked equal to ``MECHDYN_CACHE=off``'s."""
    value = run_script(folder, **options)
    assert value == run_script(folder, cache="off", **options)
    return value


# ------------------------------------------------- compiled code, new processes
@pytest.mark.parametrize("edit, gain", [   # a new process each (5-7 s): one in the quick
    ({"gain": 4.0}, 4.0),              # a module constant          loop, all in CI's suite
    pytest.param({"listed": 4.0}, 4.0, marks=pytest.mark.slow),   # a list class attribute
    pytest.param({"array": 9.0}, 9.0, marks=pytest.mark.slow),    # a numpy class attribute
    pytest.param({"factor": 4}, 4.0, marks=pytest.mark.slow),     # a sympy class attribute
])
def test_an_edited_module_is_compiled_again_in_a_new_process(tmp_path, edit, gain):
    write_module(tmp_path)
    assert fresh_and_off(tmp_path) == pytest.approx(np.cos(1.0), abs=1e-8)
    write_module(tmp_path, **edit)
    assert fresh_and_off(tmp_path) == pytest.approx(np.cos(np.sqrt(gain)), abs=1e-8)


def test_a_closure_and_an_attribute_outside_expressions_key_the_compiled_code(tmp_path):
    write_module(tmp_path)
    assert fresh_and_off(tmp_path) == pytest.approx(np.cos(1.0), abs=1e-8)
    assert fresh_and_off(tmp_path, scale=4.0) == pytest.approx(np.cos(2.0), abs=1e-8)
    cn = ellipj(1.0, 0.5)[1]                    # phi'' = -phi^3, phi(0) = 1
    assert fresh_and_off(tmp_path, n=3) == pytest.approx(cn, abs=1e-8)
    assert run_script(tmp_path) == pytest.approx(np.cos(1.0), abs=1e-8)


def test_the_compiled_backend_follows_an_edit_in_a_new_process(tmp_path):
    write_module(tmp_path)
    assert run_script(tmp_path, backend="compiled") == pytest.approx(np.cos(1.0), abs=1e-7)
    write_module(tmp_path, gain=4.0)
    assert run_script(tmp_path, backend="compiled") == pytest.approx(np.cos(2.0), abs=1e-7)


MODEL = """import sympy as sp
import mechdyn as md
from spring_module import Spring

phi = md.coordinate("phi")
k = sp.Symbol("k", positive=True)
mechanism = md.Mechanism("disc", [phi])
mechanism.link("disc", J=1, angle=phi)
mechanism.add(Spring("spring", k=k, along=phi))
params = {k: 1.0}
scenes = {"swing": md.Scene("swing", initial={phi: 1, md.speed(phi): 0}, t_end=1,
                            rtol=1e-10, backend="scipy")}
"""


def command_line(folder, cache=None) -> str:
    """The ``phi:`` line of ``mechdyn simulate model.py --scene swing`` (a new process)."""
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(folder), str(ROOT)])}
    if cache is not None:
        env["MECHDYN_CACHE"] = cache
    done = subprocess.run([sys.executable, "-m", "mechdyn.cli", "simulate",
                           str(folder / "model.py"), "--scene", "swing"],
                          capture_output=True, text=True, env=env, timeout=600, cwd=folder)
    assert done.returncode == 0, done.stderr
    return next(line for line in done.stdout.splitlines() if line.strip().startswith("phi:"))


def test_the_command_line_follows_an_edited_module_constant(tmp_path):
    """Case 2 of issue 37: ``mechdyn simulate`` in a new process printed 0.540302."""
    write_module(tmp_path)
    (tmp_path / "model.py").write_text(MODEL)
    assert "final 0.540302 rad" in command_line(tmp_path)            # cos 1
    write_module(tmp_path, gain=4.0)
    line = command_line(tmp_path)
    assert "final -0.416147 rad" in line                               # cos 2
    assert line == command_line(tmp_path, cache="off")


# ----------------------------------------------- memory and derivation, this process
@pytest.fixture
def module(tmp_path, monkeypatch):
    write_module(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    sys.modules.pop("spring_module", None)
    import spring_module
    yield spring_module
    sys.modules.pop("spring_module", None)


phi = md.coordinate("phi")
k = sp.Symbol("k", positive=True)
SWING = md.Scene("swing", initial={phi: 1, md.speed(phi): 0}, t_end=1, rtol=1e-10,
                 backend="scipy")


def disc_with(spring):
    disc = md.Mechanism("disc", [phi])
    disc.link("disc", J=1, angle=phi)
    disc.add(spring)
    return disc


def swing(disc) -> float:
    return disc.simulate(SWING, {k: 1.0}).final(phi)


def test_an_attribute_read_only_by_work_is_part_of_the_key(module):
    """Case 1 of issue 37: n = 3 ran the code compiled for n = 1."""
    assert swing(disc_with(module.Spring("s", k=k, along=phi))) == \
        pytest.approx(np.cos(1.0), abs=1e-8)
    cubic = disc_with(module.Spring("s", k=k, along=phi, n=3))
    assert md.same(cubic.reduced_moment(), -k * sp.Symbol("phi") ** 3)
    assert swing(cubic) == pytest.approx(ellipj(1.0, 0.5)[1], abs=1e-8)


@pytest.mark.parametrize("change", ["constant", "list", "array", "sympy"])
def test_what_work_reads_changed_in_place_gives_the_fresh_result(module, change):
    """The same mechanism, run again after its element's code reads another value:
    the derivation and the compiled code are made again."""
    disc = disc_with(module.Spring("s", k=k, along=phi))
    assert swing(disc) == pytest.approx(np.cos(1.0), abs=1e-8)
    if change == "constant":
        module.GAIN = 4.0
    elif change == "list":
        module.Spring.LIST[0] = 4.0
    elif change == "array":
        module.Spring.ARRAY[0] = 4.0
    else:
        module.Spring.FACTOR = sp.Integer(4)
    assert swing(disc) == pytest.approx(np.cos(2.0), abs=1e-8)
    assert md.same(disc.reduced_moment(), -4 * k * sp.Symbol("phi"))


def test_a_worker_that_would_run_other_code_says_so(module):
    """A module constant changed in the calling process is not a spawned worker's (it
    imports the module afresh): its rows fail by name instead of holding cos(1)."""
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor
    disc = disc_with(module.Spring("s", k=k, along=phi))
    module.GAIN = 4.0
    here = md.sweep(disc, SWING, {k: 1.0}, {"k": [1.0, 2.0]}, progress=False)
    assert here["final:phi"] == pytest.approx([np.cos(2.0), np.cos(np.sqrt(8.0))], abs=1e-8)
    with ProcessPoolExecutor(1, mp_context=multiprocessing.get_context("spawn")) as pool:
        there = md.sweep(disc, SWING, {k: 1.0}, {"k": [1.0, 2.0]}, progress=False,
                         executor=pool)
    assert all("other equations in this worker process" in row["error"]
               for row in there.rows), there.rows


def test_a_closure_gives_its_own_code(module):
    for scale in (1.0, 4.0, 1.0):
        spring = module.make_spring(scale)("s", k=k, along=phi)
        assert swing(disc_with(spring)) == pytest.approx(np.cos(np.sqrt(scale)), abs=1e-8)


# ------------------------------------------- derived parameters: template, kept start
I, f, P, Q, R = sp.symbols("I f P Q R", positive=True)
PARAMS = {I: 0.4, f: 0.2, P: 20, Q: 3 * P, R: 0.1}     # f (P + Q) R / I = P / 5


def brake():
    mechanism = md.Mechanism("brake", [phi])
    mechanism.link("disc", J=I, angle=phi)
    mechanism.friction("shoe", f * (P + Q) * R, along=phi)
    return mechanism


STOP = md.Scene("stop", initial={phi: 0, md.speed(phi): 100}, until=md.stopped(phi))
STOP_FROM_Q = md.Scene("stop from Q", initial={phi: 0, md.speed(phi): Q},
                       until=md.stopped(phi))


@pytest.mark.parametrize("workers", [None, 2])
def test_a_sweep_evaluates_parameters_given_as_expressions_of_a_swept_one(workers):
    """Case 3 of issue 37: the template kept Q = 3 * 20; t_end = 100 / (P / 5)."""
    table = md.sweep(brake(), STOP, PARAMS, {"P": [10.0, 40.0]}, progress=False,
                     workers=workers)
    assert table["t_end"] == pytest.approx([50.0, 12.5], rel=1e-9)


@pytest.mark.parametrize("workers", [None, 2])
def test_a_sweep_evaluates_initial_values_using_such_a_parameter(workers):
    """omega_0 = Q = 3 P and P / 5 of deceleration: 15 s at every P."""
    table = md.sweep(brake(), STOP_FROM_Q, PARAMS, {"P": [10.0, 40.0]}, progress=False,
                     workers=workers)
    assert table["t_end"] == pytest.approx([15.0, 15.0], rel=1e-9)


def test_a_sweep_refuses_a_point_whose_derived_value_breaks_a_rule():
    """Q = P - 30 is declared positive: at P = 20 it is not; the row keeps the error."""
    table = md.sweep(brake(), STOP, {**PARAMS, P: 50, Q: P - 30}, {"P": [20.0, 50.0]},
                     progress=False)
    assert "Q" in table.rows[0]["error"] and table.rows[1]["error"] == ""
    assert table["t_end"][1] == pytest.approx(100 * 0.4 / (0.2 * 70 * 0.1), rel=1e-9)


def test_the_kept_start_and_parameter_vector_follow_a_derived_parameter():
    mechanism = brake()
    for force in (10.0, 40.0, 10.0):
        params = {**PARAMS, P: force}
        assert mechanism.simulate(STOP, params).t_end == pytest.approx(500 / force, rel=1e-9)
        assert mechanism.simulate(STOP_FROM_Q, params).t_end == pytest.approx(15.0, rel=1e-9)


# ------------------------------------------------------------ numba's own cache
def test_numba_writes_nothing_beside_the_package(tmp_path):
    """Item 7 of issue 37: a compiled run in a new process leaves no numba index or data
    file under the package; the kernels' files are in the cache folder."""
    def numba_files():
        return {p for pattern in ("*.nbi", "*.nbc") for p in PACKAGE.rglob(pattern)}
    before = numba_files()
    write_module(tmp_path)
    assert run_script(tmp_path, backend="compiled") == pytest.approx(np.cos(1.0), abs=1e-7)
    assert numba_files() == before
    from mechdyn import numba_cache
    from mechdyn.compile import band_linalg, mode_numerics
    from mechdyn.kernels import integrate
    for function in (integrate, band_linalg.band_factor, mode_numerics.constrained):
        folder = getattr(function._cache, "_cache_path", None)   # None: in memory
        if folder is not None:     # in the cache folder of the process's first import
            assert PACKAGE not in Path(folder).parents
            source = Path(function.py_func.__code__.co_filename)
            assert Path(folder) == numba_cache.folder_for(source)
            assert Path(folder).parent.name == "kernels"


# ------------------------------------------------------------ announcements
def test_a_compilation_over_the_delay_is_announced(monkeypatch, capsys):
    """Item 6 of issue 37: the scene's derivation (and its numba compilation) print the
    kernels' line once they take longer than COMPILE_DELAY."""
    import time
    from mechdyn.compile import compiler, numba_model

    class Slow(md.Element):
        def work(self, motion):
            time.sleep(0.3)
            angle = motion.position(phi, self.name)
            return md.Work(forces=((-angle, angle),))

    monkeypatch.setenv("MECHDYN_CACHE", "off")
    monkeypatch.setattr(compiler, "COMPILE_DELAY", 0.05)
    monkeypatch.setattr(numba_model, "COMPILE_DELAY", 0.05)
    disc = disc_with(Slow("slow"))
    scene = md.Scene("announced", initial={phi: 1, md.speed(phi): 0}, t_end=1)
    assert disc.simulate(scene, {}).final(phi) == pytest.approx(np.cos(1.0), abs=1e-6)
    err = capsys.readouterr().err
    assert ("mechdyn: deriving and generating the code of scene 'announced' (once; kept "
            "for this process) ...") in err
    assert "mechdyn: deriving and generating the code of scene 'announced': done in " in err
    if numba_model.available():
        assert "mechdyn: compiling a scene's functions for the compiled kernels (once; " \
            "kept for this process) ..." in err



def test_a_scene_stored_on_disk_is_read_not_derived_again(tmp_path, monkeypatch):
    """A new process (an empty memory cache) with the scene on disk loads its code: the
    derivation is not run, and the code is the stored one."""
    from mechdyn.compile import compiler

    monkeypatch.setenv("MECHDYN_CACHE", str(tmp_path))
    monkeypatch.setattr(compiler, "_memory_cache", {})
    disc = md.Mechanism("stored disc", [phi])
    disc.link("disc", J=1, angle=phi)
    disc.spring("spring", 3, stretch=phi)
    scene = md.Scene("stored", initial={phi: 1, md.speed(phi): 0}, t_end=1)
    first = compiler.compile_scene(disc, scene)

    def derive_again(*args, **kwargs):
        raise AssertionError("derived again although the scene is on disk")
    monkeypatch.setattr(compiler, "_memory_cache", {})            # as a new process
    monkeypatch.setattr(compiler, "equations", derive_again)
    second = compiler.compile_scene(disc, scene)
    assert second is not first and second.source == first.source


@pytest.mark.skipif(not __import__("mechdyn.compile.numba_model",
                                   fromlist=["available"]).available(), reason="no numba")
def test_compiled_functions_on_disk_are_imported_by_a_new_process(tmp_path, monkeypatch):
    """The second load (an empty memory, as a new process) imports the numba folder the
    first one wrote and keeps it: no compilation in memory, no folder wiped."""
    from mechdyn.cache import cache_dir
    from mechdyn.compile import compiler, numba_model

    kernels = cache_dir() / "kernels"               # the kernels' own, already compiled
    if kernels.is_dir():
        (tmp_path / "kernels").symlink_to(kernels, target_is_directory=True)
    monkeypatch.setenv("MECHDYN_CACHE", str(tmp_path))
    monkeypatch.setattr(compiler, "_memory_cache", {})
    monkeypatch.setattr(numba_model, "_loaded", {})
    disc = md.Mechanism("imported disc", [phi])
    disc.link("disc", J=1, angle=phi)
    disc.spring("spring", 3, stretch=phi)
    compiled = compiler.compile_scene(disc, md.Scene("imported", initial={phi: 1},
                                                     t_end=1))
    assert numba_model.numba_functions(compiled) is not None
    folder = tmp_path / "numba" / compiled.key
    written = sorted(path.name for path in folder.rglob("*"))

    def compile_in_memory(*args):
        raise AssertionError("compiled in memory although the folder is on disk")
    monkeypatch.setattr(numba_model, "_loaded", {})                # as a new process
    monkeypatch.setattr(numba_model, "_in_memory", compile_in_memory)
    assert numba_model.numba_functions(compiled) is not None
    assert sorted(path.name for path in folder.rglob("*")) == written


def test_the_mode_entries_are_keyed_on_the_numerics_they_are_compiled_from(tmp_path,
                                                                            monkeypatch):
    """numba keys a cached cfunc on its own file, but the mode entries' machine code holds
    the numerics they call: edited numerics loaded the old code from a warm cache (a held
    coordinate's fix in mode_numerics.py had no effect until the cache was emptied). Each
    entry closes over a fingerprint of those sources, as the kernels do."""
    from mechdyn.compile import mode_entry, mode_numerics

    compiled_from = {Path(sys.modules[value.py_func.__module__].__file__)
                     for value in vars(mode_numerics).values() if hasattr(value, "py_func")}
    assert compiled_from == set(mode_entry.SOURCES)
    for implementation, _, _ in mode_entry._ENTRIES.values():
        assert [cell.cell_contents for cell in implementation.__closure__] == \
            [mode_entry._fingerprint()]
    copies = []
    for source in mode_entry.SOURCES:
        copies.append(tmp_path / source.name)
        copies[-1].write_bytes(source.read_bytes())
    monkeypatch.setattr(mode_entry, "SOURCES", tuple(copies))
    before = mode_entry._fingerprint()
    copies[0].write_text(copies[0].read_text().replace("out[n + i] = 0.0", "out[n - i] = 0.0"))
    assert mode_entry._fingerprint() != before


def _geared_pair(independent):
    """A slider x (1 kg) on a spring (10 N/m) geared to a wheel y (2 kg m^2) by a rack of
    pitch radius 2 (x = 2 y): one degree of freedom, m_red = 1 + 2 / 2^2 = 1.5 kg along x."""
    x, y = md.coordinate("x"), md.coordinate("y")
    mech = md.Mechanism("geared pair", [x, y], independent=independent(x, y))
    mech.link("slider", m=1, x=x)
    mech.link("wheel", J=2, angle=y)
    mech.constraint("rack", x - 2 * y)
    mech.spring("spring", 10, stretch=x)
    return mech, x, y


def test_the_choice_of_independent_coordinate_keys_the_compiled_code(tmp_path, monkeypatch,
                                                                      share_kernels):
    """The same elements with the other coordinate independent integrate another state
    vector: each choice gets its own code, and both swing as x = 0.2 cos(sqrt(10 / 1.5) t)
    (a stale key served the first choice's code to the second: "missing xdot")."""
    monkeypatch.setenv("MECHDYN_CACHE", str(share_kernels(tmp_path / "cache")))
    for independent in (lambda x, y: x, lambda x, y: y):
        mech, x, y = _geared_pair(independent)
        free = independent(x, y)
        start = {x: 0.2, y: 0.1, md.speed(free): 0}
        res = mech.simulate(md.Scene("swing", initial=start, t_end=1), {})
        assert res.final(x) == pytest.approx(0.2 * np.cos(np.sqrt(10 / 1.5)), rel=1e-6)
        assert res.final(y) == pytest.approx(res.final(x) / 2, rel=1e-9)

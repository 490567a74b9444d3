"""Nothing silently wrong, nothing lost (issue 28): a warm start that would answer other
than a cold run does not happen; name clashes, extreme scales and outputs leaving their
domain are named errors; files are written whole or not at all; the cache cannot hang;
long tables are one lookup.

References are worked by hand: the shoe brake (I omega_0 = 2 f P R t_stop) stops after
t = I * 100 / (0.04 P) s; a disc J = 1 under a moment 1 turns phi = t^2 / 2; a rotor J
driven by M = 10 - 0.04 w spins up as w = 250 (1 - exp(-0.4 t / J)).
"""
import errno
import math
import os
import re
import shutil
import subprocess
import sys
import threading
from pathlib import Path

import numpy as np
import pytest
from announcements import said
import sympy as sp

import mechdyn as md
from mechdyn import cache
from mechdyn.cli import main

ROOT = Path(__file__).resolve().parent.parent
BRAKE = ROOT / "models" / "shoe_brake.py"
phi = md.coordinate("phi")
START = {phi: 0, md.speed(phi): 0}

DATA_BRAKE = '''"""Shoe brake whose shoe force P, a measured value, comes from brake.json."""
import json
import os
from pathlib import Path

import sympy as sp

import mechdyn as md

phi = md.coordinate("phi")
I, f, P, R = sp.symbols("I f P R", positive=True)
mechanism = md.Mechanism("Shoe brake", coordinates=[phi])
mechanism.link("disc", J=I, angle=phi)
mechanism.friction("shoe", f * 2 * P * R, along=phi)
force = json.loads((Path(__file__).parent / "brake.json").read_text())["P"]
force *= float(os.environ.get("BRAKE_TEST_FACTOR", "1"))
params = {I: 0.4, f: 0.2, P: force, R: 0.1}
scenes = {"braking": md.Scene("braking", initial={phi: 0, md.speed(phi): 100},
                              until=md.stopped(phi))}
'''


# ------------------------------------------------------------ 1. the warm start
@pytest.fixture
def brake_folder(tmp_path, monkeypatch, share_kernels):
    monkeypatch.setenv("MECHDYN_CACHE", str(share_kernels(tmp_path / "cache")))
    monkeypatch.delenv("BRAKE_TEST_FACTOR", raising=False)
    (tmp_path / "brake.py").write_text(DATA_BRAKE)
    (tmp_path / "brake.json").write_text('{"P": 20}')
    return tmp_path


def stop_time(capsys, model):
    assert main(["simulate", str(model), "--scene", "braking"]) == 0
    out = capsys.readouterr().out
    return out.split("ended at t = ")[1].split(" s")[0]


def test_a_warm_start_sees_the_data_file_the_model_read(brake_folder, capsys, monkeypatch):
    model = brake_folder / "brake.py"
    assert stop_time(capsys, model) == "50"                 # 0.4 * 100 / (0.04 * 20)
    loads = []
    from mechdyn.declare import model_file
    original = model_file.load_model
    monkeypatch.setattr(model_file, "load_model", lambda p: loads.append(p) or original(p))
    assert stop_time(capsys, model) == "50" and loads == []  # unchanged: warm
    (brake_folder / "brake.json").write_text('{"P": 10}')
    assert stop_time(capsys, model) == "100" and len(loads) == 1   # edited: cold
    assert stop_time(capsys, model) == "100" and len(loads) == 1   # and warm again


def test_a_warm_start_sees_the_environment_variables_the_model_read(brake_folder, capsys,
                                                                     monkeypatch):
    model = brake_folder / "brake.py"
    assert stop_time(capsys, model) == "50"
    monkeypatch.setenv("BRAKE_TEST_FACTOR", "4")
    assert stop_time(capsys, model) == "12.5"               # P = 80
    monkeypatch.delenv("BRAKE_TEST_FACTOR")
    assert stop_time(capsys, model) == "50"


def test_a_warm_start_sees_a_helper_module_outside_the_model_folder(tmp_path, share_kernels):
    """A separate process per run, as on the command line (imports are per process)."""
    share_kernels(tmp_path / "cache")
    helpers, models = tmp_path / "lib", tmp_path / "models"
    helpers.mkdir()
    models.mkdir()
    (helpers / "brake_data.py").write_text("P = 20\n")
    (models / "brake.py").write_text(DATA_BRAKE.replace(
        'force = json.loads((Path(__file__).parent / "brake.json").read_text())["P"]',
        "from brake_data import P as force"))
    env = {**os.environ, "MECHDYN_CACHE": str(tmp_path / "cache"),
           "PYTHONPATH": os.pathsep.join([str(ROOT), str(helpers)])}
    env.pop("BRAKE_TEST_FACTOR", None)

    def run():
        done = subprocess.run([sys.executable, "-m", "mechdyn.cli.command", "simulate",
                               str(models / "brake.py"), "--scene", "braking"],
                              capture_output=True, text=True, env=env, timeout=120)
        assert done.returncode == 0, done.stderr
        return done.stdout.split("ended at t = ")[1].split(" s")[0]
    assert run() == "50"
    (helpers / "brake_data.py").write_text("P = 40\n")
    assert run() == "25"


def test_a_model_file_that_runs_a_program_is_never_skipped(brake_folder, capsys,
                                                          monkeypatch):
    model = brake_folder / "brake.py"
    model.write_text(DATA_BRAKE + "import subprocess\nsubprocess.run(['true'])\n")
    assert stop_time(capsys, model) == "50"
    assert not [p for p in (brake_folder / "cache").iterdir() if p.name.startswith("warm")]


# ------------------------------------------------------------ 2. name clashes
def spring_on(q, stiffness):
    mech = md.Mechanism("oscillator", [q])
    mech.link("mass", m=1, x=q)
    mech.spring("spring", stiffness, stretch=q)
    return mech


@pytest.mark.parametrize("make, culprit", [
    (lambda: md.coordinate("t"), "coordinate name 't' is the time"),
    (lambda: spring_on(md.coordinate("q"), sp.Symbol("q", real=True)),
     "spring 'spring': k: the parameter q has the name of the coordinate q"),
    (lambda: spring_on(md.coordinate("q"), sp.Symbol("qdot")),
     "the parameter qdot has the name of the speed of the coordinate q"),
    (lambda: spring_on(md.coordinate("q"), sp.Symbol("qddot", positive=True)),
     "the parameter qddot has the name of the acceleration of the coordinate q"),
    (lambda: spring_on(md.coordinate("q"), sp.Symbol("t", positive=True)),
     "the parameter t has the name of the time t"),
    (lambda: md.Mechanism("m", [md.coordinate("x"), md.coordinate("xdot")]),
     "the coordinate xdot is named xdot, the name of the speed of the coordinate x"),
])
def test_a_name_clash_is_refused_naming_both(make, culprit):
    with pytest.raises(md.DeclarationError, match=culprit):
        make()


def test_two_parameter_symbols_of_one_name_are_refused_naming_both():
    q = md.coordinate("q")
    mech = spring_on(q, sp.Symbol("k", positive=True))
    with pytest.raises(md.DeclarationError) as raised:
        mech.damper("oil", sp.Symbol("k"), stretch=q)
    assert "damper 'oil': c: the parameter k (declared without assumptions)" in \
        str(raised.value)
    assert "spring 'spring': k (declared positive=True)" in str(raised.value)


def test_a_coordinate_not_named_t_oscillates_as_cos_t():
    x = md.coordinate("x")
    res = spring_on(x, 1).simulate(md.Scene("s", initial={x: 1, md.speed(x): 0}, t_end=1),
                                   {})
    assert res.final(x) == pytest.approx(math.cos(1), rel=1e-8)


# ------------------------------------------------------------ 3. extreme scales
def brake(capsys, inertia=None, force=None):
    argv = ["simulate", str(BRAKE), "--scene", "braking"]
    argv += ["--param", f"I={inertia}"] if inertia else []
    argv += ["--param", f"P={force}"] if force else []
    status = main(argv)
    return status, capsys.readouterr()


@pytest.mark.parametrize("inertia", [1e-30, 1e-150])
def test_a_tiny_inertia_stops_at_the_right_time_and_at_rest(inertia, capsys, monkeypatch):
    monkeypatch.setenv("MECHDYN_CACHE", "off")
    model = md.load_model(BRAKE)
    scene = model.scene("braking")
    params = {str(symbol): value for symbol, value in model.params.items()}
    res = model.mechanism.simulate(scene, {**params, "I": inertia})
    assert res.t_end == pytest.approx(inertia * 100 / 0.8, rel=1e-9)
    assert res.final(md.speed(phi)) == 0.0            # at rest, not spinning backwards
    assert res.final(phi) == pytest.approx(100 * res.t_end / 2, rel=1e-9)


def test_caching_off_compiles_in_memory_and_writes_no_files(tmp_path, monkeypatch):
    """MECHDYN_CACHE=off: the compiled run writes nothing, not even a temporary folder."""
    import tempfile
    monkeypatch.setenv("MECHDYN_CACHE", "off")
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    model = md.load_model(BRAKE)
    res = model.mechanism.simulate(model.scene("braking"), model.params)
    assert set(res.stats["backends"]) == {"compiled"}
    assert res.t_end == pytest.approx(50.0, rel=1e-9)           # worked example 1: 50 s
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("value, culprit", [("P=1e200", "a friction magnitude"),
                                             ("I=1e250", "the mass matrix"),
                                             ("I=1e-170", "the mass matrix")])
def test_scales_beyond_floating_point_comfort_are_a_named_error(value, culprit, capsys,
                                                                 monkeypatch):
    monkeypatch.setenv("MECHDYN_CACHE", "off")
    status = main(["simulate", str(BRAKE), "--scene", "braking", "--param", value])
    err = capsys.readouterr().err
    assert status == 1 and len(said(err)) == 1
    assert culprit in err and "far outside the range floating-point arithmetic" in err


# ------------------------------------------------------------ 4. atomic writes
def disc_result(outputs=None):
    mech = md.Mechanism("disc", [phi])
    mech.link("disc", J=1, angle=phi)
    mech.load("drive", 1, along=phi)
    scene = md.Scene("spin", initial=START, t_end=2, outputs=outputs or [])
    return mech.simulate(scene, {})


def only_file(folder):
    return sorted(p.name for p in folder.iterdir())


def test_a_csv_that_cannot_be_written_whole_keeps_the_old_file(tmp_path, monkeypatch):
    import csv
    path = tmp_path / "run.csv"
    path.write_text("the good old file\n")
    result = disc_result()
    real = csv.writer

    class FullDisk:
        """Three rows, then half a row and the disk is full."""
        def __init__(self, handle):
            self.handle, self.writer, self.rows = handle, real(handle), 0

        def writerow(self, row):
            self.rows += 1
            if self.rows > 3:
                self.handle.write("0.5,0.12")
                raise OSError(errno.ENOSPC, "No space left on device")
            self.writer.writerow(row)
    monkeypatch.setattr(csv, "writer", FullDisk)
    with pytest.raises(md.OutputError) as raised:
        result.to_csv(path)
    monkeypatch.undo()
    assert f"cannot write {path}: the disk is full; the old file is kept" in str(raised.value)
    assert path.read_text() == "the good old file\n" and only_file(tmp_path) == ["run.csv"]
    result.to_csv(path)                                      # and written whole later
    last = [float(v) for v in path.read_text().splitlines()[-1].split(",")[:3]]
    assert last == pytest.approx([2.0, 2.0, 2.0], rel=1e-12)     # t, phi = t^2/2, omega


def test_a_figure_that_cannot_be_written_whole_leaves_no_partial_file(tmp_path, monkeypatch):
    pytest.importorskip("matplotlib")
    from matplotlib.figure import Figure
    result = disc_result()
    save = Figure.savefig

    def broken(self, target, **options):
        save(self, target, **options)
        raise OSError(errno.ENOSPC, "No space left on device")
    monkeypatch.setattr(Figure, "savefig", broken)
    with pytest.raises(md.OutputError, match="nothing written"):
        result.plot(tmp_path / "run.png")
    assert only_file(tmp_path) == []


def test_a_report_and_the_command_line_keep_the_old_file(tmp_path, monkeypatch, capsys):
    page, table = tmp_path / "page.html", tmp_path / "run.csv"
    page.write_text("old page")
    table.write_text("old table")

    def refused(source, target):
        raise PermissionError(errno.EACCES, "Permission denied")
    monkeypatch.setattr(os, "replace", refused)
    from mechdyn.report.document import Report
    with pytest.raises(md.OutputError, match=f"cannot write {page}: Permission denied"):
        Report("<html>new</html>", None, "").write(page)
    monkeypatch.setenv("MECHDYN_CACHE", "off")
    status = main(["simulate", str(BRAKE), "--scene", "braking", "--csv", str(table)])
    err = capsys.readouterr().err
    assert status == 2 and len(said(err)) == 1 and f"cannot write {table}" in err
    assert page.read_text() == "old page" and table.read_text() == "old table"
    assert only_file(tmp_path) == ["page.html", "run.csv"]


# ------------------------------------------------------------ 5. outputs out of domain
def test_an_output_leaving_its_domain_is_a_named_error_with_the_partial_result():
    with pytest.raises(md.SimulationError) as raised:
        disc_result(outputs={"o": sp.sqrt(sp.Rational(1, 2) - phi)})
    message = str(raised.value)
    assert "t = 1 s: output 'o' = sqrt(1/2 - phi) has no real value" in message
    partial = raised.value.partial
    assert partial.t[-1] == pytest.approx(1.0, rel=1e-9)      # phi = t^2/2 = 1/2
    early = partial.t < 0.99
    assert np.allclose(partial.outputs["o"][early], np.sqrt(0.5 - partial.t[early] ** 2 / 2))
    assert partial.peak("o") == pytest.approx((0.0, math.sqrt(0.5)))     # at the start


def test_the_command_line_writes_the_partial_result_of_an_output_out_of_domain(
        tmp_path, capsys, monkeypatch):
    monkeypatch.setenv("MECHDYN_CACHE", "off")
    model = tmp_path / "domain.py"
    model.write_text(BRAKE.read_text().replace(
        'until=md.stopped(phi))', 'until=md.stopped(phi), outputs={"o": sp.sqrt(1000 - phi)})'))
    table = tmp_path / "partial.csv"
    status = main(["simulate", str(model), "--scene", "braking", "--csv", str(table)])
    err = capsys.readouterr().err
    assert status == 1 and "output 'o' = sqrt(1000 - phi)" in err
    # phi = 100 t - t^2 (the deceleration is 2 rad/s^2) reaches 1000 at t = 50 - sqrt(1500)
    last = table.read_text().splitlines()[-1].split(",")
    assert float(last[0]) == pytest.approx(50 - math.sqrt(1500), rel=1e-8)


# ------------------------------------------------------------ 6. the cache cannot hang
@pytest.fixture
def private_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("MECHDYN_CACHE", str(tmp_path / "cache"))
    assert cache.store("entry.json", {"answer": 42})
    return tmp_path / "cache"


def load_within(seconds, name, fifo=None):
    """``cache.load(name)`` in a thread; a FIFO it blocks on is opened to release it."""
    answer = []
    reader = threading.Thread(target=lambda: answer.append(cache.load(name)), daemon=True)
    reader.start()
    reader.join(seconds)
    if reader.is_alive() and fifo is not None:
        os.close(os.open(fifo, os.O_WRONLY | os.O_NONBLOCK))
        reader.join(seconds)
        pytest.fail(f"cache.load blocked on the FIFO {fifo}")
    return answer


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs here")
@pytest.mark.filterwarnings("ignore:mechdyn cache")      # a FIFO key: replaced, one warning
@pytest.mark.parametrize("victim", ["entry.json", "key"])
def test_a_fifo_in_the_cache_neither_hangs_nor_stays(private_cache, victim):
    (private_cache / victim).unlink()
    os.mkfifo(private_cache / victim, 0o600)
    assert load_within(10, "entry.json", private_cache / victim) == [None]
    assert cache.store("entry.json", {"answer": 43})          # rebuilt
    assert cache.load("entry.json") == {"answer": 43}


def test_a_huge_sparse_entry_is_discarded_and_rebuilt(private_cache):
    with open(private_cache / "entry.json", "wb") as handle:
        handle.truncate(cache.MAX_ENTRY_BYTES + 1)
    assert cache.load("entry.json") is None
    assert not (private_cache / "entry.json").exists()
    assert cache.store("entry.json", {"answer": 44}) and cache.load("entry.json") == \
        {"answer": 44}


def test_a_folder_in_an_entrys_place_is_discarded_without_a_warning(private_cache, recwarn):
    (private_cache / "entry.json").unlink()
    (private_cache / "entry.json").mkdir()
    (private_cache / "entry.json" / "inside").write_text("x")
    assert cache.load("entry.json") is None
    assert cache.store("entry.json", {"answer": 45})
    assert cache.load("entry.json") == {"answer": 45}
    assert not [w for w in recwarn if issubclass(w.category, md.MechdynWarning)]


# ------------------------------------------------------------ 7. long tables
def motor(points, backend="auto"):
    speeds = np.linspace(0, 400, points)
    curve = md.table(speeds, 10 - 0.04 * speeds, name="motor curve")
    mech = md.Mechanism("motor", [phi])
    mech.link("rotor", J=0.1, angle=phi)
    mech.load("motor", curve(md.speed(phi)), along=phi)
    return mech, md.Scene("startup", initial=START, t_end=5, backend=backend)


def test_a_long_table_is_one_lookup_and_runs_right():
    mech, scene = motor(5000)
    moment = mech.elements["motor"].value
    assert type(moment).__name__ == "Lookup" and not moment.has(sp.Piecewise)
    res = mech.simulate(scene, {})
    assert res.final(md.speed(phi)) == pytest.approx(250 * (1 - math.exp(-2)), rel=1e-8)


def test_a_long_table_interpolates_and_extrapolates_as_the_short_one():
    xs = np.linspace(-1, 2, 40) ** 3                     # uneven spacing
    ys = np.cos(3 * xs)
    long, w = md.table(xs, ys), sp.Symbol("w")
    for value in (-5.0, -1.0, -0.3, 0.0, 0.123, 1.999, 8.0, 30.0):
        inside = np.interp(value, xs, ys)
        i = min(max(np.searchsorted(xs, value, side="right") - 1, 0), len(xs) - 2)
        beyond = ys[i] + (ys[i + 1] - ys[i]) / (xs[i + 1] - xs[i]) * (value - xs[i])
        expected = inside if xs[0] <= value <= xs[-1] else beyond
        assert float(long(w).subs(w, value)) == pytest.approx(expected, abs=1e-12)
    fast = sp.lambdify(w, long(w), "numpy")
    assert np.allclose(fast(np.array([0.5, 1.5])), np.interp([0.5, 1.5], xs, ys))


@pytest.mark.slow
def test_a_long_table_compiles_with_numba():
    pytest.importorskip("numba")
    mech, scene = motor(2000, backend="compiled")
    res = mech.simulate(scene, {})
    assert res.final(md.speed(phi)) == pytest.approx(250 * (1 - math.exp(-2)), rel=1e-8)


# ------------------------------------------------------------ 8. smaller ones
@pytest.mark.parametrize("make, culprit", [
    (lambda: md.Mechanism("m", [phi]).link("disc", J=1 + sp.I, angle=phi),
     "link 'disc': J: 1 + I is complex"),
    (lambda: md.Mechanism("m", [phi]).load("drive", 1 + 2 * sp.I, along=phi),
     "load 'drive': value: 1 + 2*I is complex"),
    (lambda: md.coordinate(""), "coordinate name must be an identifier"),
    (lambda: md.coordinate("a b"), "got 'a b'"),
])
def test_complex_values_and_bad_coordinate_names_are_declaration_errors(make, culprit):
    with pytest.raises(md.DeclarationError, match=re.escape(culprit)):
        make()


def test_a_figure_with_an_unknown_suffix_is_a_named_error(tmp_path):
    pytest.importorskip("matplotlib")
    with pytest.raises(md.MechdynError, match=r"x.xyz: cannot write a figure with the "
                                              r"suffix .xyz; use one of .*\.png"):
        disc_result().plot(tmp_path / "x.xyz")
    assert only_file(tmp_path) == []


def test_a_period_beyond_the_budget_is_refused_before_any_integration(capsys, monkeypatch):
    from mechdyn.analyse import shooting
    monkeypatch.setattr(shooting, "_integrate", lambda *a: pytest.fail("integrated"))
    status = main(["periodic", str(ROOT / "models" / "loom_sley.py"), "--scene", "run",
                   "--period", "1e300"])
    err = capsys.readouterr().err
    assert status == 2 and len(said(err)) == 1 and "period = 1e+300 s" in err
    assert "step budget max_steps = 1,000,000" in err


def test_models_lists_every_file_even_after_one_that_ends_the_process(tmp_path, capsys):
    shutil.copy(BRAKE, tmp_path / "a_brake.py")
    (tmp_path / "b_exits.py").write_text("import os\nos._exit(0)\n")
    shutil.copy(BRAKE, tmp_path / "c_brake.py")
    assert main(["models", str(tmp_path)]) == 2
    out = capsys.readouterr().out
    assert f"{tmp_path / 'b_exits.py'}  cannot be loaded: the model file ended its process " \
           "(exit status 0)" in out
    assert f"{tmp_path / 'c_brake.py'}  Shoe brake" in out
    with pytest.raises(SystemExit):
        main(["models", "--help"])
    assert "Each file is run" in capsys.readouterr().out

"""Bad input of every kind, as a hostile or careless user gives it: each is a named
MechdynError (exit status 2 with one line on the command line, 1 for a failed run) or
the right value, and none leaves a partial file.

Families: declarations, parameter values, scenes, model files, output files and the
disk cache. (The older catalogue is tests/hard/test_bad_input_catalogue.py; the issue's
own cases are in tests/test_nothing_lost.py.)
"""
import re
import os
import shutil
import uuid
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
J, M = sp.symbols("J M", positive=True)
START = {phi: 0, md.speed(phi): 0}


def disc():
    mech = md.Mechanism("disc", [phi])
    mech.link("disc", J=J, angle=phi)
    mech.load("drive", M, along=phi)
    return mech


def run(values, **scene):
    initial = scene.pop("initial", START)
    return lambda: disc().simulate(md.Scene("s", initial=initial, **{"t_end": 1, **scene}),
                                   values)


def declare(method, *args, **kwargs):
    return lambda: getattr(disc(), method)(*args, **kwargs)


def numbers(count, last=None, start=0.0):
    values = [start + i for i in range(count)]
    if last is not None:
        values[-1] = last
    return values


CASES = [
    # declarations
    (lambda: md.coordinate(3), md.DeclarationError, "got 3"),
    (lambda: md.coordinate("1x"), md.DeclarationError, "got '1x'"),
    (lambda: md.coordinate("a-b"), md.DeclarationError, "got 'a-b'"),
    (lambda: md.coordinate(None), md.DeclarationError, "got None"),
    (lambda: md.Mechanism("m", [md.coordinate("x"), md.coordinate("xddot")]),
     md.DeclarationError, "the acceleration of the coordinate x"),
    (lambda: md.Mechanism("m", []), md.DeclarationError, "give at least one coordinate"),
    (declare("load", "brake", sp.I * M, along=phi), md.DeclarationError,
     "load 'brake': value: I*M is complex"),
    (declare("link", "rim", m=sp.nan, x=phi), md.DeclarationError, "link 'rim': m: nan"),
    (declare("load", "brake", "5", along=phi), md.DeclarationError, "got the string '5'"),
    (declare("link", "rim", J=[1], angle=phi), md.DeclarationError, "link 'rim': J: [1]"),
    (declare("link", "disc", J=1, angle=phi), md.DeclarationError,
     "an element named 'disc' exists already"),
    (declare("spring", "shaft", sp.Symbol("phidot", positive=True), stretch=phi),
     md.DeclarationError, "the parameter phidot has the name of the speed"),
    (declare("friction", "shoe", sp.Symbol("s0", real=True), along=phi),
     md.DeclarationError, "the parameter s0 declared real=True is one of the symbols"),
    (declare("damper", "oil", sp.Symbol("J"), stretch=phi), md.DeclarationError,
     "is another symbol than the parameter J of link 'disc': J"),
    (declare("load", "drag", sp.Symbol("phi", real=True) * M, along=phi),
     md.DeclarationError, "the parameter phi has the name of the coordinate phi"),
    # tables
    (lambda: md.table(numbers(20)[::-1], numbers(20)), md.DeclarationError,
     "x values must increase strictly, but x[0] = 19.0 and x[1] = 18.0"),
    (lambda: md.table(numbers(20, float("inf")), numbers(20)), md.DeclarationError,
     "table: x[19]: inf is not a finite real number"),
    (lambda: md.table(numbers(20), numbers(20, float("nan")), name="mu"),
     md.DeclarationError, "mu: y[19]: nan is not a finite real number"),
    (lambda: md.table(numbers(20), numbers(19, 1j) + [0]), md.DeclarationError,
     "y[18]: 1j is complex"),
    (lambda: md.table([0], [1]), md.DeclarationError, "at least two points"),
    (lambda: md.table(["0", "1"], [1, 2]), md.DeclarationError, "got the string '0'"),
    (lambda: md.table(numbers(30), numbers(30))(sp.Symbol("w") + 2j), md.DeclarationError,
     "table: argument"),
    # parameter values
    (run({J: [1], M: 1}), md.ParameterError, "parameter J = [1] is not a number"),
    (run({J: np.array([1.0, 2.0]), M: 1}), md.ParameterError, "parameter J = [1. 2.]"),
    (run({J: sp.oo, M: 1}), md.ParameterError, "J = inf"),
    (run({J: sp.zoo, M: 1}), md.ParameterError, "J = zoo"),
    (run({J: 1, M: 1, "phi": 1}), md.ParameterError, "unknown parameter 'phi'"),
    (run({J: 0, M: 1}), md.ParameterError, "parameter J = 0 is zero"),
    (run({J: sp.Symbol("x"), M: 1}), md.ParameterError, "give values for x"),
    (run({J: 1, M: "1/0"}), md.ParameterError, "parameter M: '1/0'"),
    (run({J: 1e-200, M: 1}), md.SimulationError, "magnitude 1e-200 in the mass matrix"),
    (run({J: 1, M: 1e300}), md.SimulationError, "magnitude 1e+300 in the generalized forces"),
    # scenes
    (lambda: md.Scene("s", initial=START, t_end=-1), md.SceneError, "t_end = -1.0 must be"),
    (lambda: md.Scene("s", initial=START, t_start=5, t_end=1), md.SceneError,
     "must be later than the start 5.0"),
    (run({J: 1, M: 1}, initial={phi: 1j, md.speed(phi): 0}), md.SceneError,
     "initial value of phi(t) = 1j is not a number"),
    (run({J: 1, M: 1}, initial={phi: "abc", md.speed(phi): 0}), md.SceneError,
     "initial value of phi: 'abc'"),
    (run({J: 1, M: 1}, initial={phi: float("nan"), md.speed(phi): 0}), md.SceneError,
     "initial value of phi(t) is not finite"),
    (lambda: md.Scene("s", initial=START, t_end=1, max_steps=0), md.SceneError,
     "max_steps must be a positive number, got 0"),
    (lambda: md.Scene("s", initial=START, t_end=1, max_wall_time=-1), md.SceneError,
     "max_wall_time must be a positive number, got -1"),
    (run({J: 1, M: 1}, outputs={"o": sp.log(phi - 1)}), md.SimulationError,
     "t = 0 s: output 'o' = log(phi - 1) has no real value"),
    (run({J: 1, M: 1}, t_end=3, outputs={"o": sp.asin(phi)}), md.SimulationError,
     "t = 1.41421 s: output 'o' = asin(phi) has no real value"),    # phi = t^2 / 2 = 1
    (run({J: 1, M: 1}, outputs=["nothing"]), md.SceneError, "output 'nothing' is not"),
    (lambda: md.Scene("s", initial=START, until=md.reaches(phi, float("inf"))),
     md.DeclarationError, "reaches(): value: inf is not finite"),
    (lambda: md.Scene("s", initial=START, until=md.reaches(phi, 1j)), md.DeclarationError,
     "reaches(): value: 1j is complex"),
    (lambda: md.Scene("s", initial=START), md.SceneError, "give t_end or a stop condition"),
    (run({J: 1, M: 1}, initial={**START, md.speed(md.coordinate("psi")): 1}), md.SceneError,
     "Derivative(psi(t), t), which is not a declared coordinate"),
    (lambda: run({J: 1, M: 1})().to_csv("unused.csv", sample=float("nan")), md.MechdynError,
     "sample = nan: give a positive time step"),
    (lambda: run({J: 1, M: 1})().at(5.0), md.MechdynError,
     "t = 5.0 lies outside the simulated interval [0.0, 1.0]"),
]


@pytest.mark.parametrize("make, error, culprit", CASES,
                         ids=[f"{i}-{culprit[:40]}" for i, (_, _, culprit) in
                              enumerate(CASES)])
def test_bad_input_is_a_named_error(make, error, culprit, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(error) as raised:
        make()
    assert culprit in str(raised.value)
    assert list(tmp_path.iterdir()) == []                     # nothing written


def test_a_parameter_of_another_name_than_the_coordinate_is_the_right_value():
    """The clash refused above, renamed: the drag moment -c * phi, a spring of c."""
    c = sp.Symbol("c", positive=True)
    mech = md.Mechanism("oscillator", [phi])
    mech.link("disc", J=1, angle=phi)
    mech.load("drag", -c * phi, along=phi)
    res = mech.simulate(md.Scene("s", initial={phi: 1, md.speed(phi): 0}, t_end=1), {c: 4})
    assert res.final(phi) == pytest.approx(np.cos(2.0), rel=1e-8)


# ------------------------------------------------------------- model files
def model_file(folder, text, name="model.py"):
    path = folder / name
    path.write_text(text)
    return path


BRAKE_TEXT = BRAKE.read_text()
MODEL_FILES = [
    ("import json\ndata = json.load(open('missing_data.json'))\n",
     "FileNotFoundError"),
    ("mechanism = 5\n", "defines no `mechanism`"),
    ("def broken(:\n", "SyntaxError"),
    ("import os\nfactor = os.environ['MECHDYN_TEST_UNSET_VARIABLE']\n", "KeyError"),
    (BRAKE_TEXT + "params = {I: 1 + 2j, f: 0.2, P: 20, R: 0.1}\n", "is not a real number"),
    (BRAKE_TEXT + "mechanism.link('t_link', J=sp.Symbol('t', positive=True), angle=phi)\n",
     "the parameter t has the name of the time t"),
    (BRAKE_TEXT.replace('md.coordinate("phi")', 'md.coordinate("")'),
     "coordinate name must be an identifier"),
]


@pytest.mark.parametrize("text, culprit", MODEL_FILES,
                         ids=[culprit for _, culprit in MODEL_FILES])
def test_a_broken_model_file_exits_2_with_one_line(text, culprit, tmp_path, capsys,
                                                   monkeypatch):
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("MECHDYN_CACHE", "off")
    path = model_file(tmp_path, text)
    status = main(["simulate", str(path), "--scene", "braking", "--csv", "out.csv"])
    err = capsys.readouterr().err
    assert status == 2 and said(err)[0].startswith("mechdyn: error:") and len(said(err)) == 1
    assert culprit in err and str(path) in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["model.py"]


# ------------------------------------------------------------- output files
@pytest.fixture
def workspace(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("MECHDYN_CACHE", "off")
    shutil.copy(BRAKE, tmp_path / "brake.py")
    return tmp_path


ANNOUNCED = re.compile(r"mechdyn: (compiling|deriving) ")      # progress.announce's lines
OUTPUTS = [
    (["--csv", "missing/run.csv"], "no folder missing"),
    (["--csv", "brake.py/run.csv"], "no folder brake.py"),
    (["--plot", "run.xyz"], "cannot write a figure with the suffix '.xyz'"),
    (["--plot", "."], "cannot write a figure with no suffix"),
    (["--csv", "run.json"], "cannot write a CSV file with the suffix '.json'"),
    (["--units", "speed=furlong"], "furlong"),
    (["--plot", "brake.py"], "cannot write a figure with the suffix '.py'"),
]


@pytest.mark.parametrize("argv, culprit", OUTPUTS, ids=[c for _, c in OUTPUTS])
def test_a_bad_output_option_exits_2_with_one_line_and_writes_nothing(argv, culprit,
                                                                      workspace, capsys):
    status = main(["simulate", "brake.py", "--scene", "braking", *argv])
    # a compilation over a second is announced (how long it takes depends on the machine
    # and on what this process compiled before): those lines are not the error's
    err = "".join(line for line in capsys.readouterr().err.splitlines(keepends=True)
                  if not ANNOUNCED.match(line))
    assert status == 2 and said(err)[0].startswith("mechdyn: error:") and len(said(err)) == 1, err
    assert culprit in err
    assert sorted(p.name for p in workspace.iterdir()) == ["brake.py"]


@pytest.mark.skipif(hasattr(os, "geteuid") and os.geteuid() == 0,
                    reason="root writes into read-only folders")
def test_a_read_only_folder_keeps_the_old_csv_and_says_which_file(workspace, capsys):
    folder = workspace / "results"
    folder.mkdir()
    (folder / "run.csv").write_text("old")
    folder.chmod(0o500)
    try:
        status = main(["simulate", "brake.py", "--scene", "braking",
                       "--csv", "results/run.csv"])
    finally:
        folder.chmod(0o700)
    err = capsys.readouterr().err
    assert status == 2 and "cannot write results/run.csv: Permission denied" in err
    assert (folder / "run.csv").read_text() == "old" and len(list(folder.iterdir())) == 1


def test_an_html_page_in_place_of_a_folder_is_refused(workspace, capsys):
    (workspace / "page.html").mkdir()
    status = main(["report", "brake.py", "--scene", "braking", "-o", "page.html"])
    err = capsys.readouterr().err
    assert status == 2 and "-o page.html: is a folder" in err


def test_an_animation_with_another_suffix_is_refused(workspace, capsys):
    status = main(["animate", "brake.py", "--scene", "braking", "--out", "film.mp4"])
    err = capsys.readouterr().err
    assert status == 2 and "cannot write an animation with the suffix '.mp4'" in err
    assert sorted(p.name for p in workspace.iterdir()) == ["brake.py"]


# ------------------------------------------------------------- the disk cache
@pytest.fixture
def private_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("MECHDYN_CACHE", str(tmp_path / "cache"))
    assert cache.store("entry.json", {"answer": 42})
    return tmp_path / "cache"


def test_an_entry_that_is_a_link_to_another_file_is_discarded(private_cache, tmp_path):
    target = tmp_path / "elsewhere.json"
    shutil.copy(private_cache / "entry.json", target)      # authentic bytes, elsewhere
    (private_cache / "entry.json").unlink()
    (private_cache / "entry.json").symlink_to(target)
    assert cache.load("entry.json") is None
    assert not (private_cache / "entry.json").is_symlink() and target.exists()


def test_a_key_that_is_a_folder_is_replaced_with_one_warning(private_cache):
    shutil.rmtree(private_cache / "key", ignore_errors=True)
    (private_cache / "key").unlink()
    (private_cache / "key").mkdir()
    with pytest.warns(md.MechdynWarning, match="its key file is not a file: replaced"):
        assert cache.store("entry.json", {"answer": 46})
    assert cache.load("entry.json") == {"answer": 46} and (private_cache / "key").is_file()


def test_an_entry_of_other_bytes_is_ignored_and_rebuilt(private_cache):
    (private_cache / "entry.json").write_bytes(b"mechdyn-cache-1 00\n{\"answer\": 666}")
    assert cache.load("entry.json") is None
    assert cache.store("entry.json", {"answer": 47}) and cache.load("entry.json") == \
        {"answer": 47}


def test_a_cache_setting_that_is_a_file_costs_the_cache_not_the_answer(tmp_path,
                                                                       monkeypatch):
    (tmp_path / "not_a_folder").write_text("x")
    monkeypatch.setenv("MECHDYN_CACHE", str(tmp_path / "not_a_folder"))
    mech = md.Mechanism("disc", [phi])               # a new declaration: not in memory
    mech.link(f"disc {uuid.uuid4().hex}", J=2, angle=phi)
    mech.load("drive", 6, along=phi)
    with pytest.warns(md.MechdynWarning, match="cannot be created"):
        res = mech.simulate(md.Scene("s", initial=START, t_end=1), {})
    assert res.final(phi) == pytest.approx(1.5, rel=1e-9)       # 6 t^2 / (2 * 2) at 1 s

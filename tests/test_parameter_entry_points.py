"""Every entry point that takes parameter values reads them through the one
``ParameterSet``: the same bad value gives the same named error (``md.ParameterError``)
with the same message, before anything is derived or compiled.

The list below is the list of entry points (docs/guide/simulate.md, "Parameters"): each is fed an
unknown name, a value in a wrong unit and a value outside the symbol's declared domain;
the call must fail with the ParameterSet's own words while the derivation and the code
generation are booby-trapped (the check comes before seconds of sympy or numba). A
value that is missing where it is needed is named alike by every entry point that
needs it, before anything is compiled by numba. The command line reads ``--param``
through the same set.
"""
import textwrap

import pytest
import sympy as sp

import mechdyn as md
from mechdyn import cli
from mechdyn.compile import compiler, numba_model
from mechdyn.derive import equations as derive_equations

# A disc on a spring and damper, driven by M cos(w t); its parameters carry units.
phi = md.coordinate("phi")
J, k, c, M, w = sp.symbols("J k c M w", positive=True)
UNITS = {J: "kg*m^2", k: "N*m", c: "N*m*s", M: "N*m", w: "rad/s"}
disc = md.Mechanism("disc", [phi], units=UNITS)
disc.link("disc", J=J, angle=phi)
disc.spring("spring", k, stretch=phi)
disc.damper("damper", c, stretch=phi)
disc.load("drive", M * sp.cos(w * md.t), along=phi)
run = md.Scene("run", initial={phi: 0, md.speed(phi): 1}, t_end=1)
free = md.Scene("free", effects=["damper"], initial={phi: 0, md.speed(phi): 1}, t_end=1)
DISC = {"J": 1, "k": 4, "c": 0.1, "M": 1, "w": 1}

# A crank of length a driving a slider s = a cos(theta) (a closed loop).
theta, s = md.coordinates("theta s")
a, m = sp.symbols("a m", positive=True)
yoke = md.Mechanism("yoke", [theta, s], independent=[theta],
                    units={s: "m", a: "m", m: "kg", M: "N*m"})
yoke.link("crank", J=m * a**2 / 3, angle=theta,
          points=[(0, 0), (a * sp.cos(theta), a * sp.sin(theta))])
yoke.link("slider", m=m, x=s)
yoke.constraint("pin", s - a * sp.cos(theta))
yoke.load("drive", M, along=theta)
turn = md.Scene("turn", initial={theta: 0, md.speed(theta): 1, s: 1}, t_end=0.2,
                backend="scipy")
YOKE = {"a": 1, "m": 1, "M": 1}


@pytest.fixture(scope="module")
def yoke_result():
    return yoke.simulate(turn, YOKE)


def _entry_points(tmp, yoke_result):
    """Entry point -> (call with params, the good values, a parameter it needs)."""
    return {
        "Mechanism.simulate": (lambda p: disc.simulate(run, p), DISC, "J"),
        "sweep": (lambda p: md.sweep(disc, run, p, {"k": [4, 9]}, progress=False,
                                     workers=1), DISC, "J"),
        "work_precision": (lambda p: md.work_precision(disc, run, p, methods=["RK45"],
                                                       rtols=[1e-6], repeats=1), DISC, "J"),
        "periodic_steady_state": (lambda p: md.periodic_steady_state(disc, run, p),
                                  DISC, "J"),
        "floquet": (lambda p: md.floquet(disc, run, p), DISC, "J"),
        "forcing_period": (lambda p: md.forcing_period(disc, run, p), DISC, "w"),
        "steady_running": (lambda p: md.steady_running(disc, free, p), DISC, "J"),
        "flywheel": (lambda p: md.flywheel(disc, free, p, delta=0.1, inertia=J), DISC, "J"),
        "Mechanism.linearize": (lambda p: disc.linearize(run, params=p), DISC, "J"),
        "linearize": (lambda p: md.linearize(disc, run, params=p), DISC, "J"),
        "natural_frequencies": (lambda p: md.natural_frequencies(disc, run, p), DISC, "J"),
        "duty_cycle": (lambda p: md.duty_cycle(disc, [run, run], p), DISC, "J"),
        "closed_form": (lambda p: md.closed_form(disc, free, p), DISC, None),
        "classify": (lambda p: md.classify(disc, run, p), DISC, None),
        "driving_moment": (lambda p: md.driving_moment(disc, md.uniform_rotation(1), p,
                                                       drive="drive"), DISC, None),
        "characteristic": (lambda p: md.characteristic(disc, run, p), DISC, "M"),
        "report": (lambda p: _report(disc, run, p), DISC, "J"),
        "Mechanism.export_fmu": (lambda p: disc.export_fmu(run, p, tmp / "disc.fmu"),
                                 DISC, "J"),
        "animate": (lambda p: md.animate(yoke, yoke_result, p, tmp / "yoke.gif"),
                    YOKE, "a"),
        "Linkage": (lambda p: md.Linkage(yoke, p, scene=turn), YOKE, "a"),
        "driving_moment (loops)": (lambda p: md.driving_moment(
            yoke, md.uniform_rotation(1), p, scene=turn, drive="drive"), YOKE, "a"),
        "shaking": (lambda p: md.shaking(yoke, p, [0.0], 1.0, scene=turn), YOKE, "a"),
        "kinetostatics": (lambda p: md.kinetostatics(yoke, p, [0.0], 1.0, scene=turn),
                          YOKE, "a"),
        "balance": (lambda p: md.balance(yoke, p, scene=turn), YOKE, "a"),
    }


ENTRY_POINTS = ["Mechanism.simulate", "sweep", "work_precision", "periodic_steady_state",
                "floquet", "forcing_period", "steady_running", "flywheel",
                "Mechanism.linearize", "linearize", "natural_frequencies", "duty_cycle",
                "closed_form", "classify", "driving_moment", "characteristic", "report",
                "Mechanism.export_fmu", "animate", "Linkage", "driving_moment (loops)",
                "shaking", "kinetostatics", "balance"]

# bad value of M (declared positive, in N*m) -> the core of the one message
BAD = {
    "unknown name": ({"Mx": 1}, "unknown parameter 'Mx' (did you mean 'M'?)"),
    "wrong unit": ({"M": "2 kg"}, "parameter M: '2 kg': kg is a mass but N*m (a moment "
                                  "or an energy) is expected"),
    "out of its domain": ({"M": -1}, "parameter M = -1 is negative, but M is declared "
                                     "positive=True (used by load 'drive')"),
}


def _report(mechanism, scene, params):
    from mechdyn.report.document import report
    return report(mechanism, scene, params)


def _refuse(what):
    def refused(*args, **kwargs):
        raise AssertionError(f"{what} before the parameter values were checked")
    return refused


@pytest.fixture
def nothing_derived_or_compiled(monkeypatch):
    """Deriving equations, generating code or compiling with numba fails the test."""
    monkeypatch.setattr(derive_equations, "equations", _refuse("derived the equations"))
    monkeypatch.setattr(compiler, "declaration_key", _refuse("compiled the scene"))
    nothing_compiled_by_numba(monkeypatch)


def nothing_compiled_by_numba(monkeypatch):
    monkeypatch.setattr(numba_model, "numba_functions", _refuse("compiled by numba"))
    monkeypatch.setattr(numba_model, "mode_functions", _refuse("compiled by numba"))


def test_the_list_is_every_entry_point(tmp_path, yoke_result):
    assert sorted(_entry_points(tmp_path, yoke_result)) == sorted(ENTRY_POINTS)


@pytest.mark.parametrize("case", list(BAD))
@pytest.mark.parametrize("entry", ENTRY_POINTS)
def test_the_same_bad_value_gives_the_same_error_before_any_work(
        entry, case, tmp_path, yoke_result, request):
    call, good, _ = _entry_points(tmp_path, yoke_result)[entry]
    bad, message = BAD[case]
    request.getfixturevalue("nothing_derived_or_compiled")
    with pytest.raises(md.ParameterError) as refused:
        call({**good, **bad})
    assert message in str(refused.value)


NEEDING = [e for e in ENTRY_POINTS if e not in ("closed_form", "classify", "driving_moment")]


@pytest.mark.parametrize("entry", NEEDING)
def test_a_missing_value_is_named_alike_before_numba_compiles(entry, tmp_path, yoke_result,
                                                              monkeypatch):
    """Closed forms keep a missing value as a symbol (docs/guide/simulate.md); every other entry point
    names it in the one wording, ``'mechanism': give values for NAME (needed by ...)``."""
    call, good, needed = _entry_points(tmp_path, yoke_result)[entry]
    nothing_compiled_by_numba(monkeypatch)
    owner = "yoke" if good is YOKE else "disc"
    with pytest.raises(md.ParameterError, match=rf"^'{owner}': give values for {needed} "
                                                r"\(needed by "):
        call({name: v for name, v in good.items() if name != needed})


def test_closed_forms_keep_a_missing_value_as_a_symbol():
    """J omega' = -c omega from omega = 1: omega = exp(-c t / J), here with J = 2."""
    solution = md.closed_form(disc, free, {"J": 2})
    assert md.same(solution["omega(t)"], sp.exp(-c * sp.Symbol("t") / 2))


def test_sweep_grid_values_take_the_declared_unit():
    """A grid value with a unit is converted as a parameter value is, and as --grid
    converts it ("100 N*mm*s" is 0.1 N m s); "2 kg" is refused (it was read as 2)."""
    on_scipy = md.Scene("free", effects=["damper"], initial={phi: 0, md.speed(phi): 1},
                        t_end=1, backend="scipy")
    table = md.sweep(disc, on_scipy, DISC, {"c": ["100 N*mm*s", "0.2 N*m*s"]},
                     progress=False)
    assert list(table["c"]) == [0.1, 0.2]
    with pytest.raises(md.ParameterError, match="parameter c: '2 kg': kg is a mass but "):
        md.sweep(disc, on_scipy, DISC, {"c": ["2 kg"]}, progress=False)


# ----------------------------------------------------------------------- command line
MODEL = textwrap.dedent('''
    """A disc on a spring and damper, driven by M cos(w t)."""
    import sympy as sp
    import mechdyn as md
    phi = md.coordinate("phi")
    J, k, c, M, w = sp.symbols("J k c M w", positive=True)
    mechanism = md.Mechanism("disc", [phi], units={J: "kg*m^2", k: "N*m", c: "N*m*s",
                                                   M: "N*m", w: "rad/s"})
    mechanism.link("disc", J=J, angle=phi)
    mechanism.spring("spring", k, stretch=phi)
    mechanism.damper("damper", c, stretch=phi)
    mechanism.load("drive", M * sp.cos(w * md.t), along=phi)
    params = {J: 1, k: 4, c: 0.1, M: 1, w: 1}
    scenes = {"run": md.Scene("run", initial={phi: 0, md.speed(phi): 1}, t_end=0.5,
                              backend="scipy")}
''')
YOKE_MODEL = textwrap.dedent('''
    """A crank driving a slider through a pin."""
    import sympy as sp
    import mechdyn as md
    theta, s = md.coordinates("theta s")
    a, m, M = sp.symbols("a m M", positive=True)
    mechanism = md.Mechanism("yoke", [theta, s], independent=[theta],
                             units={s: "m", a: "m", m: "kg", M: "N*m"})
    mechanism.link("crank", J=m * a**2 / 3, angle=theta)
    mechanism.link("slider", m=m, x=s)
    mechanism.constraint("pin", s - a * sp.cos(theta))
    mechanism.load("drive", M, along=theta)
    params = {a: 1, m: 1, M: 1}
    scenes = {"turn": md.Scene("turn", initial={theta: 0, md.speed(theta): 1, s: 1},
                               t_end=0.2)}
''')
COMMANDS = {
    "simulate": ["simulate", "{disc}", "--scene", "run"],
    "simulate (duty cycle)": ["simulate", "{disc}", "--scene", "run+run"],
    "precision": ["precision", "{disc}", "--scene", "run", "--methods", "RK45"],
    "periodic": ["periodic", "{disc}", "--scene", "run"],
    "report": ["report", "{disc}", "--scene", "run", "-o", "{tmp}/disc.html"],
    "sweep": ["sweep", "{disc}", "--scene", "run", "--grid", "k=4,9"],
    "characteristic": ["characteristic", "{disc}", "--scene", "run"],
    "animate": ["animate", "{disc}", "--scene", "run", "--out", "{tmp}/disc.gif"],
    "linkage": ["linkage", "{yoke}", "--scene", "turn"],
    "fmu": ["fmu", "{disc}", "--scene", "run", "--out", "{tmp}/disc.fmu"],
}
PARAM_TEXT = {"unknown name": "Mx=1", "wrong unit": "M=2 kg", "out of its domain": "M=-1"}


@pytest.fixture(scope="module")
def model_files(tmp_path_factory):
    folder = tmp_path_factory.mktemp("models")
    (folder / "disc.py").write_text(MODEL)
    (folder / "yoke.py").write_text(YOKE_MODEL)
    return folder


def _cli(capsys, argv):
    try:
        status = cli.main(argv)
    except SystemExit as exit_:
        status = exit_.code
    out, err = capsys.readouterr()
    return status, out, err


@pytest.mark.parametrize("case", list(PARAM_TEXT))
@pytest.mark.parametrize("command", list(COMMANDS))
def test_the_command_line_gives_the_same_error(command, case, model_files, tmp_path,
                                               capsys, request):
    argv = [part.format(disc=model_files / "disc.py", yoke=model_files / "yoke.py",
                        tmp=tmp_path) for part in COMMANDS[command]]
    request.getfixturevalue("nothing_derived_or_compiled")
    status, out, err = _cli(capsys, argv + ["--param", PARAM_TEXT[case]])
    assert status == 2 and out == ""
    assert err.startswith("mechdyn: ") and BAD[case][1] in err


def test_a_warm_start_never_skips_the_check(model_files, capsys, monkeypatch):
    """A run stores its warm start; the same command with a bad value is refused alike
    (and so is a second try, which a stored failure would not be)."""
    from mechdyn.declare import model_file
    argv = ["simulate", str(model_files / "disc.py"), "--scene", "run"]
    assert _cli(capsys, argv + ["--param", "M=2"])[0] == 0
    with monkeypatch.context() as warm:                 # the model file is not read
        warm.setattr(model_file, "load_model", _refuse("read the model file"))
        assert _cli(capsys, argv + ["--param", "M=2"])[0] == 0
    for _ in range(2):
        status, _, err = _cli(capsys, argv + ["--param", "M=-2"])
        assert status == 2
        assert "parameter M = -2 is negative, but M is declared positive=True" in err

"""The catalogue of bad inputs: each gives its error type and a message naming the culprit.

(More cases of each family live beside the feature they guard: declaration errors in
tests/test_declaration_errors.py, simulation errors in tests/test_simulation_errors.py.)
"""
import numpy as np
import pytest
import sympy as sp

import mechdyn as md
from mechdyn.cli.command import main

phi = md.coordinate("phi")
J, M, m = sp.symbols("J M m", positive=True)
START = {phi: 0, md.speed(phi): 0}


def disc():
    mech = md.Mechanism("disc", [phi])
    mech.link("disc", J=J, angle=phi)
    mech.load("drive", M, along=phi)
    return mech


def missing_parameter():
    disc().simulate(md.Scene("s", initial=START, t_end=1), {J: 1})


def unknown_effect():
    disc().simulate(md.Scene("s", effects=["clutch"], initial=START, t_end=1), {J: 1, M: 1})


def undeclared_initial_coordinate():
    psi = md.coordinate("psi")
    disc().simulate(md.Scene("s", initial=START | {psi: 0}, t_end=1), {J: 1, M: 1})


def nan_parameter():
    disc().simulate(md.Scene("s", initial=START, t_end=1), {J: float("nan"), M: 1})


def infinite_parameter():
    disc().simulate(md.Scene("s", initial=START, t_end=1), {J: 1, M: float("inf")})


def negative_mass():
    md.Mechanism("cart", [phi]).link("cart", m=-2, x=phi)


def zero_gear_ratio_in_a_declaration():
    gear = md.Mechanism("gear pair", [phi])
    gear.link("gear 2", J=1, angle=phi / sp.Integer(0))


def zero_gear_ratio_in_a_reduction():
    md.reduction.inertia(J=2.0, i=0.0)


def period_of_zero():
    spring = md.Mechanism("oscillator", [phi])
    spring.link("mass", m=1, x=phi)
    spring.spring("spring", 1, stretch=phi)
    spring.load("force", sp.cos(md.t), along=phi)
    md.periodic_steady_state(spring, md.Scene("steady", initial=START, t_end=1), {}, period=0)


CATALOGUE = [
    (missing_parameter, md.ParameterError, "M"),
    (unknown_effect, md.SceneError, "clutch"),
    (undeclared_initial_coordinate, md.SceneError, "psi"),
    (nan_parameter, md.ParameterError, "J = nan"),
    (infinite_parameter, md.ParameterError, "M = inf"),
    (negative_mass, md.DeclarationError, "link 'cart': m"),
    (zero_gear_ratio_in_a_declaration, md.DeclarationError, "gear 2"),
    (zero_gear_ratio_in_a_reduction, md.MechdynError, "i = 0"),
    (period_of_zero, md.MechdynError, "period"),
]


@pytest.mark.parametrize("make, error, culprit", CATALOGUE,
                         ids=[make.__name__ for make, _, _ in CATALOGUE])
def test_bad_input_names_its_culprit(make, error, culprit):
    with pytest.raises(error) as raised:
        make()
    assert culprit in str(raised.value)


def test_model_file_without_mechanism(tmp_path):
    path = tmp_path / "empty_model.py"
    path.write_text("params = {}\n")
    with pytest.raises(md.MechdynError, match="defines no `mechanism`"):
        md.load_model(path)
    assert main(["equations", str(path)]) == 2


@pytest.mark.parametrize("text", ["__import__('os').system('true')", "1e400",
                                  "open('/etc/passwd').read()", "(1).__class__"])
def test_command_line_values_go_through_the_restricted_parser(text, capsys):
    status = main(["simulate", "models/shoe_brake.py", "--scene", "braking",
                   "--param", f"P={text}"])
    error = capsys.readouterr().err
    assert status == 2
    assert error.startswith("mechdyn: error:") and len(error.strip().splitlines()) == 1
    assert text[:10] in error


# ----------------------------------------------------------- the second round's catalogue
eta = sp.Symbol("eta", positive=True)
k, c, n = sp.Symbol("k", nonnegative=True), sp.Symbol("c"), sp.Symbol("n", integer=True)
RUN = md.Scene("s", initial=START, t_end=1)


def geared(efficiency):
    mech = disc()
    mech.load("lift", -M / 2, along=phi, efficiency=efficiency)
    return mech


def efficiency_zero_declared():
    geared(0)


def efficiency_parameter(value):
    return lambda: geared(eta).simulate(RUN, {J: 1, M: 1, eta: value})


def elastic(**values):
    """A disc on a spring k and damper c (k declared nonnegative, c not)."""
    mech = disc()
    mech.spring("shaft", k, stretch=phi)
    mech.damper("oil", c, stretch=phi)
    return lambda: mech.simulate(RUN, {"J": 1, "M": 1, "k": 1, "c": 1, **values})


def reaches_undeclared():
    psi = md.coordinate("psi")
    disc().simulate(md.Scene("s", initial=START, until=md.reaches(psi, 1)), {J: 1, M: 1})


def scene(**fields):
    return lambda: md.Scene("s", initial=START, **{"t_end": 1, **fields})


def counted(value):
    """A drive of n identical motors: n must be a whole number."""
    mech = md.Mechanism("motors", [phi])
    mech.link("rotor", J=J, angle=phi)
    mech.load("motors", n * M, along=phi)
    return lambda: mech.simulate(RUN, {J: 1, M: 1, n: value})


def inertia_of(expression, values):
    """A link whose inertia is an expression of parameters a, b."""
    mech = md.Mechanism("rotor", [phi])
    mech.link("rotor", J=expression, angle=phi)
    return lambda: mech.simulate(RUN, values)


a, b = sp.symbols("a b")

SECOND_ROUND = [
    (inertia_of(1 / (a - b), {"a": 1, "b": 1}), md.ParameterError,
     "parameter a, b: link 'rotor': J = 1/(a - b) is not a finite real number with a = 1"),
    (inertia_of(sp.sqrt(a), {"a": -1}), md.ParameterError,
     "link 'rotor': J = sqrt(a) is not a finite real number with a = -1"),
    (inertia_of(a - b, {"a": 1, "b": 2}), md.ParameterError,
     "link 'rotor': J = a - b = -1 is negative with a = 1, b = 2"),
    (efficiency_zero_declared, md.DeclarationError, "load 'lift': efficiency"),
    (efficiency_parameter(0), md.ParameterError, "parameter eta = 0 is zero"),
    (efficiency_parameter(1.5), md.ParameterError, "load 'lift': efficiency = eta lies "
                                                   "outside (0, 1] with eta = 1.5"),
    (elastic(k=-3), md.ParameterError, "parameter k = -3 is negative, but k is declared "
                                       "nonnegative=True (used by spring 'shaft')"),
    (elastic(c=-0.5), md.ParameterError, "parameter c: damper 'oil': c = c is negative"),
    (elastic(c=np.float32(-0.5)), md.ParameterError, "damper 'oil': c = c is negative"),
    (elastic(c=sp.Rational(-1, 2)), md.ParameterError, "damper 'oil': c = c is negative"),
    (elastic(c=np.int64(-2)), md.ParameterError, "damper 'oil': c = c is negative"),
    (elastic(J=np.float64(-1)), md.ParameterError, "parameter J = -1 is negative"),
    (elastic(J=sp.Integer(-1)), md.ParameterError, "used by link 'disc'"),
    (elastic(M="heavy"), md.ParameterError, "parameter M: 'heavy'"),
    (elastic(M=1 + 2j), md.ParameterError, "parameter M = (1+2j) is not a real number"),
    (elastic(M=None), md.ParameterError, "parameter M = None is not a number"),
    (elastic(M=True), md.ParameterError, "parameter M = True is not a number"),
    (elastic(m=1), md.ParameterError, "unknown parameter 'm' (did you mean 'M'?)"),
    (counted(2.5), md.ParameterError, "parameter n = 2.5 is not a whole number"),
    (reaches_undeclared, md.SceneError, "reaches(psi, 1) uses psi, which is not a coordinate"),
    (scene(t_end="10 kg"), md.SceneError, "t_end: '10 kg': kg is a mass but s (a time) is"),
    (scene(t_end=float("inf")), md.SceneError, "t_end = inf is not finite"),
    (scene(t_end=float("nan")), md.SceneError, "t_end = nan is not finite"),
    (scene(t_start="0 m"), md.SceneError, "t_start: '0 m': m is a length but s"),
    (scene(t_end="ten"), md.SceneError, "t_end: 'ten': expected a number before the unit"),
    (scene(rtol=float("inf")), md.SceneError, "rtol = inf is not finite"),
    (scene(rtol=5), md.SceneError, "rtol = 5.0 must lie in [2.22e-14, 1)"),
    (scene(rtol=1), md.SceneError, "rtol = 1.0 must lie in"),
    (scene(rtol=1e-15), md.SceneError, "rtol = 1e-15 must lie in"),
    (scene(rtol="1e-8"), md.SceneError, "rtol must be a number"),
    (scene(atol=float("inf")), md.SceneError, "atol = inf is not finite"),
    (scene(atol=float("nan")), md.SceneError, "atol = nan is not finite"),
    (scene(atol=-1e-9), md.SceneError, "atol must be a positive number, got -1e-09"),
    (scene(atol={phi: 0.0}), md.SceneError, "atol[phi(t)] must be a positive number"),
]


@pytest.mark.parametrize("make, error, culprit", SECOND_ROUND,
                         ids=[f"{i}-{make.__name__}" for i, (make, _, _) in
                              enumerate(SECOND_ROUND)])
def test_second_round_bad_input_names_its_culprit(make, error, culprit):
    with pytest.raises(error) as raised:
        make()
    assert culprit in str(raised.value)


def test_the_smallest_accepted_rtol_is_scipys_floor():
    assert md.Scene("s", initial=START, t_end=1, rtol=2.3e-14).rtol == 2.3e-14


@pytest.mark.parametrize("argv, culprit", [
    (["--plot", "x.xyz"], "--plot x.xyz: cannot write a figure with the suffix '.xyz'"),
    (["--plot", "/no/such/folder/x.png"], "no folder /no/such/folder"),
    (["--csv", "trajectory"], "--csv trajectory: cannot write a CSV file with no suffix"),
    (["--param", "I=__import__('os')"], "parameter I: \"__import__('os')\""),
    (["--param", "P=-20"], "parameter P = -20 is negative, but P is declared positive=True "
                           "(used by friction 'shoe')"),
    (["--param", "p=20"], "unknown parameter 'p' (did you mean 'P'?)"),
])
def test_command_line_input_is_refused_before_anything_is_simulated(argv, culprit, capsys,
                                                                     monkeypatch):
    def never(*args, **kwargs):
        raise AssertionError("simulated before the input was checked")
    monkeypatch.setattr(md.Mechanism, "simulate", never)
    status = main(["simulate", "models/shoe_brake.py", "--scene", "braking", *argv])
    error = capsys.readouterr().err
    assert status == 2 and error.startswith("mechdyn: error:") and error.count("\n") == 1
    assert culprit in error


def test_a_report_page_with_another_suffix_is_refused_first(capsys, monkeypatch):
    monkeypatch.setattr(md.Mechanism, "simulate", lambda *a: pytest.fail("simulated"))
    assert main(["report", "models/shoe_brake.py", "--scene", "braking", "-o", "x.pdf"]) == 2
    assert "-o x.pdf: cannot write an HTML page with the suffix '.pdf'" in \
        capsys.readouterr().err

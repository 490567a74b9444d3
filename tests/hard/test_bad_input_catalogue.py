"""The catalogue of bad inputs: each gives its error type and a message naming the culprit.

(More cases of each family live beside the feature they guard: declaration errors in
tests/test_declaration_errors.py, simulation errors in tests/test_simulation_errors.py.)
"""
import pytest
import sympy as sp

import mechdyn as md
from mechdyn.cli import main

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

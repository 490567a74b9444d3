"""Fuzzing what users type and write: the value parser, parameter values, the grid
syntax and model files. Whatever comes in, the answer is a value or a named MechdynError
(exit 2 on the command line), never another exception (exit 3) or a crash."""
import math
import tempfile
from decimal import Decimal
from fractions import Fraction
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import mechdyn as md
from mechdyn.analyse import sweeps
from mechdyn.cli.command import main
from mechdyn.declare.model_file import ModelFileError
from mechdyn.declare.parameters import ParameterSet, to_number
from mechdyn.parse import ValueTextError, number

ROOT = Path(__file__).resolve().parents[2]
BRAKE = md.load_model(ROOT / "models" / "shoe_brake.py")

TOKENS = ["1", "2.5", "1e3", "1e400", "0", "-", "+", "*", "/", "**", "(", ")", "pi", "e",
          "sqrt(", "log(", "exp(", "sin(", "x", "__import__", "'os'", ".", ",", "[", "]",
          "1j", "lambda", ":", " ", "=", "9**9**9", "True", "open", "_", "\x00", "\u00e9"]


@settings(max_examples=300, deadline=None)
@given(st.one_of(st.text(max_size=60),
                 st.lists(st.sampled_from(TOKENS), max_size=12).map("".join)))
def test_the_value_parser_gives_a_finite_number_or_a_named_error(text):
    try:
        value = number(text)
    except ValueTextError as error:
        assert repr(text)[:11] in str(error)                # it quotes the text
        return
    assert isinstance(value, float) and math.isfinite(value)


VALUES = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True), st.integers(-10 ** 400, 10 ** 400),
    st.text(max_size=20), st.complex_numbers(), st.booleans(), st.none(),
    st.fractions(), st.decimals(allow_nan=True, allow_infinity=True),
    st.lists(st.integers(), max_size=2), st.sampled_from(["2*pi", "1e400", "-1", "3"]))


@settings(max_examples=300, deadline=None)
@given(VALUES)
def test_a_parameter_value_is_a_float_or_a_parameter_error_naming_it(value):
    try:
        number_ = to_number("P", value)
    except md.ParameterError as error:
        assert "parameter P" in str(error)
        return
    assert isinstance(number_, float)


@settings(max_examples=200, deadline=None)
@given(VALUES)
def test_a_brake_force_is_accepted_only_when_positive_and_finite(value):
    """The brake's P is declared positive: anything else is refused, naming P."""
    try:
        values = ParameterSet({"P": value}, defaults=BRAKE.params, mechanism=BRAKE.mechanism)
    except md.ParameterError as error:
        assert "P" in str(error)
        return
    assert math.isfinite(values["P"]) and values["P"] > 0


class _Reached(md.MechdynError):
    """Raised by the stand-in sweep: the grid passed every check."""


GRID_TOKENS = ["P", "f", "Q", "=", ":", ",", "1", "10", "0", "-1", "2.5", "1e9", "1e400",
               "pi", "nan", "inf", " ", "x", "()", "2*3", "1000"]


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.one_of(st.lists(st.sampled_from(GRID_TOKENS), max_size=8).map("".join),
                          st.text(max_size=20)), min_size=1, max_size=2))
def test_grid_text_is_a_grid_or_a_usage_error(texts):
    seen = {}

    def stand_in(mechanism, scene, params, grid, *args, **options):
        seen.update(grid)
        raise _Reached("checked")
    original, sweeps.sweep = sweeps.sweep, stand_in
    try:
        argv = ["sweep", str(ROOT / "models" / "shoe_brake.py"), "--scene", "braking",
                "--max-points", "1000"]
        for text in texts:
            argv += [f"--grid={text}"]
        try:
            status = main(argv)
        except SystemExit as exited:         # argparse: an option-like text
            status = exited.code
    finally:
        sweeps.sweep = original
    assert status == 2
    for values in seen.values():
        assert 1 <= len(values) <= 1000 and all(math.isfinite(v) for v in values)


STATEMENTS = [
    "import sys", "sys.exit(3)", "raise KeyboardInterrupt", "raise SystemExit('bye')",
    "raise GeneratorExit", "1/0", "def f(:", "x = [", "scenes = 5", "scenes = {'a': 1}",
    "scenes = {1: 2}", "params = [1]", "params = {1: 2}", "params = {'J': -1}",
    "params = {'J': 'heavy'}", "params = {'J': float('nan')}", "mechanism = 3",
    "__doc__ = None", "__doc__ = 7", "import mechdyn as md", "phi = md.coordinate('phi')",
    "mechanism = md.Mechanism('m', [phi])", "mechanism.link('d', J=1, angle=phi)",
    "mechanism.link('d', J=-1, angle=phi)", "mechanism.load('drive', 1, along=phi)",
    "scenes = {'run': md.Scene('run', initial={phi: 0, md.speed(phi): 0}, t_end=1)}",
    "scenes = {'run': md.Scene('run', initial={}, t_end='1')}", "params = {}",
    "import sympy as sp", "J = sp.Symbol('J', positive=True)",
    "mechanism.link('e', J=J, angle=phi)", "params = {J: 0}",
]


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.one_of(st.sampled_from(STATEMENTS), st.text(max_size=30)), max_size=10))
def test_any_model_file_loads_or_is_a_model_file_error(lines):
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "model.py"
        path.write_text("\n".join(lines) + "\n", errors="surrogatepass")
        try:
            model = md.load_model(path)
        except ModelFileError as error:
            assert str(path) in str(error)
            return
        assert isinstance(model.mechanism, md.Mechanism)
        assert all(isinstance(s, md.Scene) for s in model.scenes.values())


@pytest.mark.parametrize("contents", [b"\xff\xfe\x00garbage", b"\x00" * 10,
                                      b"(" * 10000, "x = '\u00e9'\n".encode("latin-1")],
                         ids=["binary", "nul", "deep", "latin-1"])
def test_undecodable_or_binary_model_files_are_model_file_errors(contents, tmp_path):
    path = tmp_path / "model.py"
    path.write_bytes(contents)
    with pytest.raises(ModelFileError):
        md.load_model(path)
    assert main(["models", str(tmp_path)]) == 2


def test_values_of_every_kind_from_the_fuzzer_are_also_handled_by_sweep_grids():
    for value in (Fraction(50, 3), Decimal("12.5"), "8*pi"):      # stops within 1000 s
        table = md.sweep(BRAKE.mechanism, BRAKE.scenes["braking"], BRAKE.params,
                         {"P": [value]}, workers=1, progress=False)
        assert table["t_end"][0] == pytest.approx(1000 / float(to_number("P", value)),
                                                  rel=1e-9)

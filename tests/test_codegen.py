"""Generated code through codegen's public functions: a scalar state, Python floats from a
numpy state (so a division by zero raises instead of giving inf), docstrings."""
import math

import numpy as np
import pytest
import sympy as sp

from mechdyn.compile.codegen import compile_source, function_source

x, v, k = sp.symbols("x v k")


def test_a_single_state_argument_is_the_state_itself():
    source = function_source("f", ["x"], ["k"], [k * sp.sin(x) ** 2, sp.cos(x)],
                             "return [{0}, {1}]")
    f = compile_source(source)["f"]
    assert f(0.0, 0.5, [2.0]) == pytest.approx([2 * math.sin(0.5) ** 2, math.cos(0.5)],
                                               rel=1e-15)
    assert f.__doc__ is None                       # no docstring unless one is given


def test_state_from_a_numpy_array_is_unpacked_to_python_floats():
    source = function_source("g", ["x", "v"], [], [1 / x, v], "return [{0}, {1}]",
                             doc="y = [x, v]")
    g = compile_source(source)["g"]
    assert g.__doc__ == "y = [x, v]"
    out = g(0.0, np.array([4.0, 3.0]), [])
    assert out == [0.25, 3.0] and all(type(value) is float for value in out)
    with pytest.raises(ZeroDivisionError):
        g(0.0, np.array([0.0, 1.0]), [])

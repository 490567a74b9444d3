"""The internals of numba, scipy and sympy that mechdyn reads where they have no public
API, pinned: a new release that renames or changes one fails here by name, not silently
elsewhere (the guarded code raises mechdyn.errors.DependencyError, or falls back).

- numba: ``numba.experimental.function_type._get_jit_address`` /
  ``_get_wrapper_address`` and the ``c_addr``/``py_addr``/``jit_addr`` fields of a
  FunctionType (mechdyn/kernels/functions.py);
- scipy: the ``_estimate_error_norm`` hook of the explicit Runge-Kutta solvers and the
  fields it reads (mechdyn/simulate/error_control.py), the fields of each dense-output
  class (mechdyn/simulate/stepping.py);
- sympy: ``sympy.simplify.cse_main.tree_cse`` (mechdyn/compile/codegen.py).

pint is read through its public API only (``list(registry)``, ``Quantity.to_tuple``).
"""
import math

import numpy as np
import pytest
import sympy as sp
from numba import njit
from scipy.integrate._ivp import rk

from mechdyn.errors import DependencyError
from mechdyn.simulate import error_control
from mechdyn.simulate.stepping import METHODS, ScipySegment, step_polynomial
from mechdyn.simulate.trajectory import Segment


# ------------------------------------------------------------------------------ numba
def test_numba_function_type_has_the_fields_the_kernels_write():
    from numba.core.datamodel import default_manager
    from mechdyn.kernels.functions import FUNCTION_FIELDS, JAC_TYPE, RHS_TYPE
    for function_type in (RHS_TYPE, JAC_TYPE):
        assert set(FUNCTION_FIELDS) <= set(default_manager.lookup(function_type)._fields)


@njit("void(float64, float64[::1], float64[::1], float64[::1])")
def _decay(t, y, p, out):
    out[0] = -p[0] * y[0] + t


def test_a_model_function_is_called_through_its_addresses():
    from mechdyn.kernels.functions import as_rhs, model_functions

    @njit
    def call(addresses, t, y, p, out):
        as_rhs(addresses[0], addresses[1])(t, y, p, out)

    addresses = model_functions(_decay).addresses
    assert addresses[0] != 0 and addresses[1] != 0
    out = np.zeros(1)
    call(addresses, 0.5, np.array([2.0]), np.array([3.0]), out)
    assert out[0] == -3.0 * 2.0 + 0.5


# ------------------------------------------------------------------ scipy: error norm
@pytest.mark.parametrize("method", ["RK45", "RK23", "DOP853"])
def test_the_error_norm_override_is_what_scipy_calls(method, monkeypatch):
    calls = []
    original = error_control._Guarded._estimate_error_norm

    def counted(self, K, h, scale):
        calls.append(h)
        return original(self, K, h, scale)
    monkeypatch.setattr(error_control._Guarded, "_estimate_error_norm", counted)
    solver = error_control.guarded(method)(lambda t, y: [y[1], -math.sin(y[0])], 0.0,
                                           [0.0, 3.0], 5.0, rtol=1e-8, atol=1e-10,
                                           revolving=[0])
    steps = 0
    while solver.status == "running":
        solver.step()
        steps += 1
    assert steps > 10 and len(calls) >= steps          # every step, rejected ones too


def test_a_scipy_without_the_error_norm_hook_is_named(monkeypatch):
    monkeypatch.delattr(rk.RungeKutta, "_estimate_error_norm")
    monkeypatch.setattr(error_control, "_CHECKED", set())
    with pytest.raises(DependencyError, match=r"scipy .* has no RK45\._estimate_error_norm"):
        error_control.guarded("RK45")(lambda t, y: -y, 0.0, [1.0], 1.0)


def test_a_scipy_without_the_fields_the_norm_reads_is_named(monkeypatch):
    monkeypatch.delattr(rk.DOP853, "E5")
    monkeypatch.setattr(error_control, "_CHECKED", set())
    with pytest.raises(DependencyError, match=r"DOP853\.E5"):
        error_control.guarded("DOP853")(lambda t, y: -y, 0.0, [1.0], 1.0)


# ---------------------------------------------------------------- scipy: dense output
@pytest.mark.parametrize("method", METHODS)
def test_the_polynomial_read_from_each_dense_output_is_the_solvers_own(method):
    """Each step's polynomial, read from the dense output's fields, agrees with the
    dense output's public call across the step."""
    def fun(t, y):
        return np.array([y[1], -math.sin(y[0]) - 0.3 * y[1] + 0.5 * math.cos(t)])

    def jac(t, y):
        return np.array([[0.0, 1.0], [-math.cos(y[0]), -0.3]])
    run = ScipySegment(method, fun, jac, 0.0, np.array([1.0, 0.0]), 3.0, 1e-6, 1e-9,
                       Segment(0.0, [1.0, 0.0], mode=(), method=method))
    solver, checked = run.solver, 0
    while solver.status == "running" and checked < 40:
        solver.step()
        dense = solver.dense_output()
        coefficients = step_polynomial(dense)
        for x in (0.0, 0.25, 0.6, 1.0):
            t = dense.t_old + x * (dense.t - dense.t_old)
            assert np.allclose(np.polynomial.polynomial.polyval(x, coefficients),
                               dense(t), rtol=1e-11, atol=1e-13), (method, checked, x)
        checked += 1
    assert checked > 5


def test_a_dense_output_without_its_fields_is_named():
    stripped = type("RkDenseOutput", (), {"y_old": np.zeros(2), "t": 1.0, "t_old": 0.0})()
    with pytest.raises(DependencyError, match=r"RkDenseOutput\.Q"):
        step_polynomial(stripped)
    unknown = type("SplineDenseOutput", (), {})()
    with pytest.raises(DependencyError, match="SplineDenseOutput"):
        step_polynomial(unknown)


# -------------------------------------------------------------------- sympy: tree_cse
def test_sympy_has_the_tree_pass_of_cse_and_the_fallback_gives_the_same_values(
        monkeypatch):
    from mechdyn.compile import codegen
    assert codegen._tree_cse is not None       # the tested sympy releases have it
    x, v, k = sp.symbols("x v k")
    expressions = [k * sp.sin(x) ** 2 + sp.sin(x) * v, sp.cos(x) * sp.sin(x) - k * v ** 2,
                   sp.sqrt(1 + sp.sin(x) ** 2) * sp.cos(x)]
    body = [f"out[{i}] = {{{i}}}" for i in range(3)]

    def values():
        source = codegen.function_source("f", ["x", "v"], ["k"], expressions, body,
                                         large=True)
        out = [0.0] * 3
        codegen.compile_source(source)["f"](0.0, [0.7, -1.3], [2.5], out)
        return out
    with_tree = values()
    monkeypatch.setattr(codegen, "_tree_cse", None)
    assert np.allclose(values(), with_tree, rtol=1e-15, atol=0)
    exact = [float(e.subs({x: 0.7, v: -1.3, k: 2.5})) for e in expressions]
    assert np.allclose(with_tree, exact, rtol=1e-14, atol=0)


# ------------------------------------------------------------------------------- pint
def test_pint_facts_come_from_its_public_api():
    from mechdyn import units
    assert "revolution" in list(units.registry())
    assert units._facts_from_pint([("rpm", 1)])["angle"] == "1"
    assert units._facts_from_pint([("N", 1), ("m", 1)])["angle"] == "0"
    with pytest.raises(units.UnitError, match="did you mean rpm"):
        units._facts_from_pint([("rmp", 1)])

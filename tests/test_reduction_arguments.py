"""Every argument of every reduction formula: a value that makes no physical sense is
refused with an error that starts with that argument's name; the boundary values that do
make sense (zero mass, eta = 1, no gear stages) are accepted; defaults are the documented
ones. Expected values by hand (J / i^2, m r^2 / i^2, ...)."""
import re

import pytest
import sympy as sp

from mechdyn import reduction as red

# (call with one argument bad, the argument's name). Everything else is valid.
BAD = [
    (lambda v: red.inertia(v, 2), "J", -1.0),
    (lambda v: red.inertia(1.0, v), "i", 0.0),
    (lambda v: red.drum_mass(v, 0.2, 5), "m", -1.0),
    (lambda v: red.drum_mass(100, v, 5), "r_b", 0.0),
    (lambda v: red.drum_mass(100, 0.2, v), "i", 0.0),
    (lambda v: red.torsional_stiffness(v, 2), "c", 0.0),
    (lambda v: red.torsional_stiffness(9.0, v), "i", 0.0),
    (lambda v: red.rope_stiffness(v, 20.0, 0.2, 40), "E_k", 0.0),
    (lambda v: red.rope_stiffness(8e6, v, 0.2, 40), "length", -2.0),
    (lambda v: red.rope_stiffness(8e6, 20.0, v, 40), "r_b", 0.0),
    (lambda v: red.rope_stiffness(8e6, 20.0, 0.2, v), "i", 0.0),
    (lambda v: red.mesh_stiffness(v, 0.05), "C_l", 0.0),
    (lambda v: red.mesh_stiffness(1e8, v), "r", -0.05),
    (lambda v: red.mesh_stiffness(1e8, 0.05, v), "i", 0.0),
    (lambda v: red.efficiency(eta_gear=v), "eta_gear", 1.5),
    (lambda v: red.efficiency(eta_bearing=v), "eta_bearing", 0.0),
    (lambda v: red.efficiency(bearings=v), "bearings", -1),
    (lambda v: red.efficiency(gear_stages=v), "gear_stages", -1),
    (lambda v: red.moment(v, 2), "M_c", -1.0),
    (lambda v: red.moment(10.0, v), "i", 0.0),
    (lambda v: red.moment(10.0, 2, eta=v), "eta", 0.0),
    (lambda v: red.drum_force(v, 0.2, 10), "P", -1.0),
    (lambda v: red.drum_force(10.0, v, 10), "r_b", 0.0),
    (lambda v: red.drum_force(10.0, 0.2, v), "i", 0.0),
    (lambda v: red.drum_force(10.0, 0.2, 10, eta=v), "eta", 1.01),
]


@pytest.mark.parametrize("call, name, value", BAD, ids=[f"{i}-{n}" for i, (_, n, _) in
                                                       enumerate(BAD)])
def test_a_bad_argument_is_named_first_in_the_error(call, name, value):
    with pytest.raises(red.ReductionError, match=rf"^{re.escape(name)} = "):
        call(value)


def test_zero_is_a_valid_mass_inertia_moment_and_force():
    assert red.inertia(0.0, 2) == 0.0
    assert red.drum_mass(0.0, 0.2, 5) == 0.0
    assert red.moment(0.0, 2) == 0.0
    assert red.drum_force(0.0, 0.2, 10) == 0.0


def test_efficiency_bounds_are_open_at_zero_and_closed_at_one():
    assert red.moment(10.0, 2, eta=1.0) == pytest.approx(5.0)
    assert red.efficiency(eta_gear=1.0, eta_bearing=1.0, gear_stages=3, bearings=2) == 1.0
    with pytest.raises(red.ReductionError, match="^eta = "):
        red.moment(10.0, 2, eta=0.0)


def test_symbolic_efficiency_is_checked_by_its_known_sign_and_bound():
    # 1/2 is an efficiency; 3/2 and 2 are not; a positive symbol may be one.
    assert float(red.moment(10, 2, eta=sp.Rational(1, 2))) == 10.0
    for value in (sp.Rational(3, 2), sp.Integer(2), sp.Integer(0), sp.Integer(-1)):
        with pytest.raises(red.ReductionError, match="^eta = "):
            red.moment(10, 2, eta=value)
    eta = sp.Symbol("eta", positive=True)
    assert sp.simplify(red.moment(10, 2, eta=eta) - 5 / eta) == 0


def test_symbolic_zero_mass_is_valid_and_a_negative_symbol_is_not():
    assert red.inertia(sp.Integer(0), 2) == 0
    with pytest.raises(red.ReductionError, match="^J = "):
        red.inertia(sp.Symbol("J", negative=True), 2)
    with pytest.raises(red.ReductionError, match="^r_b = "):
        red.drum_mass(1, sp.Integer(0), 2)


def test_defaults_are_no_stages_no_bearings_lossless_and_ratio_one():
    assert red.efficiency() == 1.0
    assert red.efficiency(gear_stages=0, bearings=2) == pytest.approx(0.98 ** 2)
    assert red.efficiency(gear_stages=2, bearings=0) == pytest.approx(0.95 ** 2)
    assert red.efficiency(gear_stages=1) == pytest.approx(0.95)
    assert red.efficiency(bearings=1) == pytest.approx(0.98)
    assert red.moment(800.0, 8) == pytest.approx(100.0)              # eta = 1
    assert red.moment(800.0, 8, overhauling=True) == pytest.approx(100.0)
    assert red.drum_force(1000.0, 0.5, 10) == pytest.approx(50.0)    # 1000 * 0.5 / 10
    assert red.mesh_stiffness(1e8, 0.05) == pytest.approx(2.5e5)     # 1e8 * 0.05^2, i = 1


def test_series_of_no_stiffness_is_a_named_error_and_of_some_the_textbook_sum():
    with pytest.raises(red.ReductionError, match="at least one stiffness"):
        red.series()
    assert red.series(100.0, 100.0, 50.0) == pytest.approx(25.0, rel=1e-15)  # 1/c = sum 1/c_k

"""One ParameterSet: every entry point takes parameters by symbol or by name, with the
same values, the same checks and the same messages.

References: the shoe brake stops at t = I omega_0 / (2 f P R) (docs/guide/simulate.md, worked example 1);
a mass m on a spring k with damper c has omega = sqrt(k/m), zeta = c / (2 sqrt(k m)); an
undamped oscillator driven by F cos(w t) settles to the amplitude F / (k - m w^2).
"""
import math
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

import mechdyn as md
from mechdyn.declare.parameters import ParameterSet

ROOT = Path(__file__).resolve().parents[1]
x = md.coordinate("x")
m, k, c, F = sp.symbols("m k c F", positive=True)


@pytest.fixture(scope="module")
def brake():
    return md.load_model(ROOT / "models" / "shoe_brake.py")


def by_name(params):
    return {str(key): value for key, value in params.items()}


def oscillator(force=0):
    mech = md.Mechanism("oscillator", [x])
    mech.link("mass", m=m, x=x)
    mech.spring("spring", k, stretch=x)
    mech.damper("damper", c, stretch=x)
    if force:
        mech.load("force", force, along=x)
    return mech


def test_names_symbols_defaults_and_the_vector_order(brake):
    values = ParameterSet({"P": 40, sp.Symbol("f"): 0.25},     # f without assumptions
                          defaults=brake.params, mechanism=brake.mechanism)
    assert values.vector(["R", "P", "f", "I"]) == [0.1, 40.0, 0.25, 0.4]
    assert dict(values) == {"I": 0.4, "f": 0.25, "P": 40.0, "R": 0.1}


@pytest.mark.parametrize("value", [40, 40.0, np.float64(40), np.int32(40), sp.Integer(40),
                                   sp.Float(40), Fraction(80, 2), "40", "4*10",
                                   np.array(40.0)])
def test_every_kind_of_number_is_the_same_value(value, brake):
    result = brake.mechanism.simulate(brake.scenes["braking"],
                                      {**by_name(brake.params), "P": value})
    assert result.t_end == pytest.approx(1000 / 40, rel=1e-9)


def test_a_value_may_be_an_expression_of_other_parameters(brake):
    R = sp.Symbol("R", positive=True)
    params = {**by_name(brake.params), "P": 4 / R}                  # P = 40
    assert brake.mechanism.simulate(brake.scenes["braking"], params).t_end == \
        pytest.approx(25.0, rel=1e-9)
    assert ParameterSet({"P": 4 / R, "R": 0.1}).vector(["P"]) == pytest.approx([40.0])


def test_simulate_and_closed_form_take_names(brake):
    scene = brake.scenes["braking"]
    names = by_name(brake.params)
    assert brake.mechanism.simulate(scene, names).t_end == pytest.approx(50.0, rel=1e-9)
    for params in (brake.params, names):
        solution = md.closed_form(brake.mechanism, scene, params)
        assert solution.stop.t == 50 and solution.stop.phi == 2500
        assert md.classify(brake.mechanism, scene, params).case == 1


def test_natural_frequencies_take_names_and_symbols_alike():
    for params in ({m: 4, k: 1600, c: 8}, {"m": 4, "k": 1600, "c": 8}):
        modes = md.natural_frequencies(oscillator(), params=params)
        assert modes.omega == pytest.approx([20.0])                    # sqrt(1600 / 4)
        assert modes.damping_ratios == pytest.approx([8 / (2 * math.sqrt(1600 * 4))])


def test_periodic_steady_state_takes_names():
    w = sp.Symbol("w", positive=True)
    mech = oscillator(F * sp.cos(w * md.t))
    scene = md.Scene("steady", initial={x: 0, md.speed(x): 0}, t_end=1)
    steady = md.periodic_steady_state(mech, scene, {"m": 1, "k": 2.25, "c": 0.01, "F": 3,
                                                    "w": 1})
    assert steady.period == pytest.approx(2 * math.pi)
    # F / sqrt((k - m w^2)^2 + (c w)^2); amplitudes() samples 2001 points a period, so
    # its peak may sit (pi / 2000)^2 / 2 = 1.2e-6 below the true one
    assert steady.amplitudes()["x"] == pytest.approx(3 / math.hypot(1.25, 0.01), rel=3e-6)


def test_work_precision_and_sweep_take_names(brake):
    names = by_name(brake.params)
    table = md.work_precision(brake.mechanism, brake.scenes["braking"], names,
                              methods=["DOP853"], rtols=[1e-8], repeats=1)
    assert table.reference.kind == "closed form" and not table.rows[0].failed
    swept = md.sweep(brake.mechanism, brake.scenes["braking"], names, {"P": [20, 40]},
                     workers=1, progress=False)
    assert list(swept["t_end"]) == pytest.approx([50.0, 25.0], rel=1e-9)


def test_the_same_parameter_twice_with_two_values_is_refused(brake):
    with pytest.raises(md.ParameterError, match="parameter P is given twice, as 20 and 30"):
        brake.mechanism.simulate(brake.scenes["braking"],
                                 {**brake.params, "P": 30})


def test_all_missing_values_are_named_at_once(brake):
    with pytest.raises(md.ParameterError, match="give values for P, R"):
        brake.mechanism.simulate(brake.scenes["braking"], {"I": 0.4, "f": 0.2})


def test_two_symbols_of_one_name_are_a_declaration_error():
    mech = md.Mechanism("twins", [x])
    mech.link("mass", m=sp.Symbol("m"), x=x)
    with pytest.raises(md.DeclarationError, match="the parameter m .declared positive=True. "
                       "is another symbol than the parameter m of link 'mass': m"):
        mech.spring("spring", sp.Symbol("m", positive=True), stretch=x)


def test_a_parameter_of_the_scene_only_is_known(brake):
    """A stop angle used only by the scene's stop condition is a parameter too."""
    phi = brake.mechanism.coordinates[0]
    phi_end = sp.Symbol("phi_end", positive=True)
    scene = md.Scene("part", effects=["shoe"], initial={phi: 0, md.speed(phi): 100},
                     until=md.reaches(phi, phi_end), t_end=60)
    result = brake.mechanism.simulate(scene, {**by_name(brake.params), "phi_end": 1900})
    # phi = 100 t - t^2 reaches 1900 at t = 50 - sqrt(600)
    assert result.t_end == pytest.approx(50 - math.sqrt(600), rel=1e-9)

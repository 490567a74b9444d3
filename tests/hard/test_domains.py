"""Expressions without a real value for part of the motion (issue 17): a run that reaches
the edge of an element's expression (a root of a negative number ahead) stops with an
error naming the element, the expression and the configuration, and keeps the result so
far; it never ends quietly with a stalled or NaN state."""
import math

import numpy as np
import pytest
import sympy as sp

import mechdyn as md

phi = md.coordinate("phi")


def test_a_link_position_that_stops_being_real_is_named_where_the_motion_stalls():
    # y = sqrt(cos phi) is real for |phi| <= pi/2 only; driven from 0 the reduced inertia
    # 1 + sin^2 / (4 cos) grows without bound there and the motion creeps up to pi/2.
    mech = md.Mechanism("bob on a root", [phi])
    mech.link("crank", J=1, angle=phi)
    mech.link("bob", m=1, y=sp.sqrt(sp.cos(phi)))
    mech.load("drive", 2, along=phi)
    scene = md.Scene("s", initial={phi: 0, md.speed(phi): 0}, t_end=5)
    with pytest.raises(md.SimulationError) as error:
        mech.simulate(scene, {})
    message = str(error.value)
    assert "link 'bob': y = sqrt(cos(phi))" in message and "phi = 1.5708" in message
    partial = error.value.partial
    assert partial is not None and np.all(np.isfinite(partial.y))
    assert partial.final(phi) == pytest.approx(math.pi / 2, abs=1e-6)


def test_a_load_with_a_fractional_power_of_a_coordinate_that_turns_negative_is_named():
    mech = md.Mechanism("odd spring", [phi])
    mech.link("disc", J=1, angle=phi)
    mech.load("odd", -phi ** sp.Rational(3, 2), along=phi)
    scene = md.Scene("s", initial={phi: 1, md.speed(phi): -3}, t_end=5)
    with pytest.raises(md.SimulationError) as error:
        mech.simulate(scene, {})
    assert "load 'odd': value = -phi**(3/2)" in str(error.value)
    partial = error.value.partial
    assert np.all(np.isfinite(partial.y)) and abs(partial.final(phi)) < 1e-6


def test_a_start_outside_an_expression_s_domain_is_refused_at_once():
    mech = md.Mechanism("bob on a root", [phi])
    mech.link("bob", m=1, J=1, y=sp.sqrt(sp.cos(phi)), angle=phi)
    scene = md.Scene("s", initial={phi: 2.0, md.speed(phi): 0}, t_end=1)
    with pytest.raises(md.SimulationError, match=r"link 'bob'.*no real value.*phi = 2"):
        mech.simulate(scene, {})


def test_a_root_that_stays_real_costs_nothing():
    # the exact slider-crank's rod term sqrt(L^2 - r^2 sin^2 phi) never nears zero
    model = md.load_model("models/slider_crank.py")
    result = model.mechanism.simulate(model.scenes["startup"], model.params)
    assert result.reason == "t_end"

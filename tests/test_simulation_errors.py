"""Bad input to simulation gets a clear error naming the culprit; failures keep what was
computed."""
import numpy as np
import pytest
import sympy as sp

import mechdyn as md

phi = md.coordinate("phi")
J, k, M = sp.symbols("J k M", positive=True)
START = {phi: 0, md.speed(phi): 0}


def disc(load=M):
    mech = md.Mechanism("disc", [phi])
    mech.link("disc", J=J, angle=phi)
    mech.load("drive", load, along=phi)
    return mech


def test_missing_parameters_are_all_named_in_one_error():
    with pytest.raises(md.ParameterError) as error:
        disc().simulate(md.Scene("s", initial=START, t_end=1), {})
    assert "J" in str(error.value) and "M" in str(error.value)


@pytest.mark.parametrize("bad", [float("nan"), float("inf")])
def test_non_finite_parameter_is_named(bad):
    with pytest.raises(md.ParameterError, match="J = "):
        disc().simulate(md.Scene("s", initial=START, t_end=1), {J: bad, M: 1})


def test_negative_inertia_by_parameter_value_is_named():
    with pytest.raises(md.ParameterError, match="link 'disc'"):
        disc().simulate(md.Scene("s", initial=START, t_end=1), {J: -1, M: 1})


def test_missing_initial_values_are_named():
    with pytest.raises(md.SceneError, match="phidot"):
        disc().simulate(md.Scene("s", initial={phi: 0}, t_end=1), {J: 1, M: 1})


def test_initial_value_for_an_undeclared_coordinate():
    psi = md.coordinate("psi")
    with pytest.raises(md.SceneError, match="psi"):
        disc().simulate(md.Scene("s", initial=START | {psi: 1}, t_end=1), {J: 1, M: 1})


def test_unknown_effect_is_named_with_the_known_ones():
    with pytest.raises(md.SceneError) as error:
        disc().simulate(md.Scene("s", effects=["brake"], initial=START, t_end=1), {J: 1, M: 1})
    assert "'brake'" in str(error.value) and "drive" in str(error.value)


def test_overflow_during_integration_reports_time_and_state_and_keeps_the_partial_result():
    # omega' = exp(k phi) blows up in finite time; math.exp overflows near phi = 709.
    mech = disc(sp.exp(k * phi))
    scene = md.Scene("runaway", initial={phi: 0, md.speed(phi): 1}, t_end=100)
    with pytest.raises(md.SimulationError) as error:
        mech.simulate(scene, {J: 1, k: 1})
    message = str(error.value)
    assert "t = " in message and "phi = " in message
    partial = error.value.partial
    assert partial is not None and 0 < partial.t_end < 100
    assert len(partial.t) > 2 and np.all(np.isfinite(partial.y))


def test_a_state_where_the_reduced_inertia_vanishes_is_named_not_integrated():
    # A yoke whose only inertia is its mass: I_red = m l^2 sin^2(phi) vanishes at phi = 0.
    m, l = sp.symbols("m l", positive=True)
    yoke = md.Mechanism("bare yoke", [phi])
    yoke.link("yoke", m=m, x=l * sp.cos(phi))
    yoke.load("drive", 1, along=phi)
    scene = md.Scene("dead centre", initial={phi: 0, md.speed(phi): 0}, t_end=1)
    with pytest.raises(md.SimulationError, match="coordinate phi") as error:
        yoke.simulate(scene, {m: 1, l: 0.1})
    assert error.value.partial is not None


def test_stop_condition_met_at_the_start_is_watched_from_there_not_met_at_once():
    # Issue 20: a condition met exactly at the start does not end an empty run; it is
    # watched from the side the motion takes. A driven disc from rest never stops again.
    scene = md.Scene("s", initial=START, until=md.stopped(phi), t_end=2)
    res = disc().simulate(scene, {J: 1, M: 1})
    assert res.reason == "t_end (stop condition not reached)"
    assert res.final(md.speed(phi)) == pytest.approx(2.0, rel=1e-12)   # M t / J


def test_unknown_method_is_named():
    scene = md.Scene("s", initial=START, t_end=1, method="Euler")
    with pytest.raises(md.SceneError, match="Euler"):
        disc().simulate(scene, {J: 1, M: 1})


def test_scene_without_an_end_is_refused():
    with pytest.raises(md.SceneError, match="t_end"):
        md.Scene("endless", initial=START)


def test_output_of_an_unknown_element_is_named():
    scene = md.Scene("s", initial=START, t_end=1, outputs=["shaft"])
    with pytest.raises(md.SceneError, match="shaft"):
        disc().simulate(scene, {J: 1, M: 1})

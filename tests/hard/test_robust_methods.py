"""Issue 13: every hard case finishes at default settings with the right answer, in
bounded work. Work is bounded by step budgets far above what a sound method needs (a
method that goes pathological on some CPU fails the test instead of hanging it); no
assertion depends on step counts or timings of this machine."""
import math

import numpy as np
import pytest
import sympy as sp
from scipy.linalg import expm

import mechdyn as md

phi1, phi2 = md.coordinates("phi_1 phi_2")
AT_REST = {phi1: 0, phi2: 0, md.speed(phi1): 0, md.speed(phi2): 0}


def pair(J1, J2, k, c, M):
    mech = md.Mechanism("two inertias", [phi1, phi2])
    mech.link("motor", J=J1, angle=phi1)
    mech.link("load", J=J2, angle=phi2)
    mech.spring("shaft", k, stretch=phi1 - phi2)
    if c:
        mech.damper("shaft damping", c, stretch=phi1 - phi2)
    mech.load("motor moment", M, along=phi1)
    return mech


def test_the_stiff_damped_pair_matches_its_exact_solution_in_bounded_work():
    # k = 1e6 between 1 and 1e-4 kg m^2, damping ratio 0.025: the case whose Radau run
    # took 501,227 steps on one CPU. Reference: the matrix exponential of the linear
    # system, and the rigid drive (uniform acceleration M / (J1 + J2)) to 1e-6 rad.
    J1, J2, k, M = 1.0, 1e-4, 1e6, 20.0
    c = 2 * 0.025 * math.sqrt(k * J1 * J2 / (J1 + J2))
    stiff = pair(J1, J2, k, c, M).simulate(
        md.Scene("stiff", initial=AT_REST, t_end=1.0, max_steps=30_000), {})
    A = np.array([[0, 0, 1, 0], [0, 0, 0, 1], [-k / J1, k / J1, -c / J1, c / J1],
                  [k / J2, -k / J2, c / J2, -c / J2]])
    augmented = np.zeros((5, 5))
    augmented[:4, :4], augmented[2, 4] = A, M / J1
    times = np.linspace(0, 1, 41)
    exact = np.array([(expm(augmented * t) @ [0, 0, 0, 0, 1])[:4] for t in times]).T
    assert np.max(np.abs(stiff.at(times, "phi_1") - exact[0])) < 1e-8
    rigid = M * times**2 / (2 * (J1 + J2))
    assert np.max(np.abs(stiff.at(times, "phi_2") - rigid)) < 1e-6
    # the same model with a soft shaft (k = 2000): the stiff run takes at most 30x its steps
    soft = pair(J1, J2, 2000.0, 2 * 0.025 * math.sqrt(2000 * J1 * J2 / (J1 + J2)), M)
    soft_run = soft.simulate(md.Scene("soft", initial=AT_REST, t_end=1.0), {})
    assert stiff.stats["steps"] <= 30 * soft_run.stats["steps"]


def test_the_undamped_stiff_pair_keeps_its_energy_equal_to_the_work_of_the_motor():
    # Without damping DOP853's stiffness test fired at t = 0.105 s ("probably stiff")
    # and the run aborted; now the method changes and the run ends with T + V = M phi_1.
    M = 20.0
    result = pair(1.0, 1e-4, 1e6, 0.0, M).simulate(
        md.Scene("undamped", initial=AT_REST, t_end=1.0, max_steps=500_000), {})
    T, V = result.energy()
    work = M * result["phi_1"]
    assert np.max(np.abs(T + V - work)) <= 1e-6 * np.max(work)
    assert result.t_end == 1.0


def test_a_coupling_that_engages_late_conserves_angular_momentum():
    # A stiff damped coupling (k = 1e6, c = 50) between a 1 kg m^2 motor driven by 10 N m
    # and a 1e-3 kg m^2 load engages at t = 0.5 s (a Piecewise in time): it failed with
    # "step size becomes too small" at 0.5 s. Momentum: both speeds end at M t / (J1 + J2).
    J1, J2, k, c, M, t_on = 1.0, 1e-3, 1e6, 50.0, 10.0, 0.5
    mech = md.Mechanism("late coupling", [phi1, phi2])
    mech.link("motor", J=J1, angle=phi1)
    mech.link("load", J=J2, angle=phi2)
    mech.load("motor moment", M, along=phi1)
    twist = phi1 - phi2 - M * t_on**2 / (2 * J1)            # relaxed when it engages
    engaged = sp.Piecewise((0, md.t < t_on), (1, True))
    mech.load("coupling", -engaged * (k * twist + c * (md.speed(phi1) - md.speed(phi2))),
              along=phi1 - phi2)
    result = mech.simulate(md.Scene("late", initial=AT_REST, t_end=1.0, max_steps=50_000), {})
    final = M * 1.0 / (J1 + J2)
    assert result.final(md.speed(phi1)) == pytest.approx(final, abs=1e-5)
    assert result.final(md.speed(phi2)) == pytest.approx(final, abs=1e-5)
    assert result.at([0.25], "phidot_2")[0] == 0.0            # not engaged yet


def test_a_method_named_in_the_scene_is_not_replaced_and_its_failure_is_named():
    # A named method is the user's choice (precision reports compare them): no retries.
    scene = md.Scene("named", initial=AT_REST, t_end=1.0, method="RK23", max_steps=2000)
    with pytest.raises(md.SimulationError, match="step budget of 2000.*RK23"):
        pair(1.0, 1e-4, 1e6, 0.0, 20.0).simulate(scene, {})


def test_a_run_over_its_budget_keeps_what_it_computed_and_says_what_to_try():
    scene = md.Scene("budget", initial=AT_REST, t_end=1.0, max_steps=50, method="DOP853")
    with pytest.raises(md.SimulationError) as error:
        pair(1.0, 1e-4, 1e6, 0.0, 20.0).simulate(scene, {})
    message = str(error.value)
    assert "scene 'budget'" in message and "step budget of 50" in message
    assert "DOP853" in message and "last step" in message and "max_steps" in message
    partial = error.value.partial
    assert partial is not None and 0 < partial.t_end < 1.0 and len(partial.t) > 50


def test_method_changes_are_recorded_with_time_and_reason():
    result = pair(1.0, 1e-4, 1e6, 0.0, 20.0).simulate(
        md.Scene("switching", initial=AT_REST, t_end=0.2, rtol=1e-6, atol=1e-8), {})
    for switch in result.stats["switches"]:
        assert set(switch) == {"t", "from", "to", "why"} and switch["why"]
        assert 0.0 <= switch["t"] <= 0.2
    assert sum(result.stats["methods"].values()) == result.stats["steps"]

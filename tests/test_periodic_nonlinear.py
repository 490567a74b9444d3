"""Periodic motion and Floquet multipliers of a nonlinear (Duffing) oscillator with
symbolic parameters, through shooting with an explicit and an implicit integrator, and
details of the periodic solution (start time, extremes, the multipliers' text).

Independent references: Liouville's formula (the product of the multipliers of
x'' + c x' + f(x, t) = 0 over T is exp(-c T), whatever f), a hand-written scipy
integration of the same equation, and the forced linear oscillator's closed form."""
import math
from dataclasses import replace

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp

import mechdyn as md

x = md.coordinate("x")
k, c, beta, F, W = sp.symbols("k c beta F Omega", positive=True)
DUFFING = {k: 1.0, c: 0.3, beta: 0.5, F: 0.8, W: 1.2}
T = 2 * math.pi / 1.2


def duffing():
    mech = md.Mechanism("Duffing", [x])
    mech.link("mass", m=1, x=x)
    mech.spring("spring", k, stretch=x)
    mech.load("hardening", -beta * x ** 3, along=x)
    mech.damper("damper", c, stretch=x)
    mech.load("force", F * sp.cos(W * md.t), along=x)
    return mech


def by_hand(t, y):
    return [y[1], -1.0 * y[0] - 0.5 * y[0] ** 3 - 0.3 * y[1] + 0.8 * math.cos(1.2 * t)]


@pytest.mark.parametrize("method", ["auto", "Radau"])
def test_duffing_periodic_state_closes_and_obeys_liouville(method):
    scene = md.Scene("steady", initial={x: 0, md.speed(x): 0}, t_end=1, method=method)
    steady = md.periodic_steady_state(duffing(), scene, DUFFING)
    assert steady.method == "shooting" and not steady.linear
    assert steady.period == pytest.approx(T, rel=1e-14)
    end = solve_ivp(by_hand, (0, T), steady.y0, method="DOP853", rtol=1e-12, atol=1e-13)
    assert end.y[:, -1] == pytest.approx(steady.y0, abs=1e-6)
    assert np.prod(steady.floquet.multipliers).real == pytest.approx(math.exp(-0.3 * T),
                                                                     rel=1e-6)


def test_floquet_of_the_nonlinear_oscillator_alone():
    scene = md.Scene("steady", initial={x: 0, md.speed(x): 0}, t_end=1)
    mu = md.floquet(duffing(), scene, DUFFING)
    assert np.prod(mu.multipliers).real == pytest.approx(math.exp(-0.3 * T), rel=1e-6)
    assert mu.verdict == "asymptotically stable"


# ------------------------------------------------ forced linear oscillator, m = 1
K_, C_, F_, W_ = 4.0, 0.8, 1.5, 1.3
D2 = (K_ - W_ ** 2) ** 2 + (C_ * W_) ** 2


def linear(t_start=0.0):
    mech = md.Mechanism("forced oscillator", [x])
    mech.link("mass", m=1, x=x)
    mech.spring("spring", K_, stretch=x)
    mech.damper("damper", C_, stretch=x)
    mech.load("force", F_ * sp.cos(W_ * md.t), along=x)
    return mech, md.Scene("steady", initial={x: 0, md.speed(x): 0}, t_start=t_start,
                          t_end=t_start + 1)


def exact(t):
    return F_ * ((K_ - W_ ** 2) * math.cos(W_ * t) + C_ * W_ * math.sin(W_ * t)) / D2


def test_floquet_over_a_given_period_of_two_forcing_periods():
    # Both multipliers have modulus exp(-c T2 / 2) over T2 = 2 * (2 pi / W).
    mech, scene = linear()
    period = 4 * math.pi / W_
    mu = md.floquet(mech, scene, {}, period=period)
    assert np.abs(mu.multipliers) == pytest.approx([math.exp(-C_ * period / 2)] * 2, rel=1e-7)


def test_periodic_solution_starting_later_is_the_same_motion():
    mech, scene = linear(t_start=0.5)
    steady = md.periodic_steady_state(mech, scene, {})
    assert steady.t0 == 0.5
    for time in (0.7, 3.9, 12.0):
        assert steady.at(time)["x"] == pytest.approx(exact(time), abs=1e-9)


def test_extremes_include_the_acceleration_swing():
    # x'' = -W^2 x in the steady state: amplitude W^2 F / sqrt(D2).
    mech, scene = linear()
    extremes = md.periodic_steady_state(mech, scene, {}).extremes()
    assert list(extremes) == ["x", "xdot", "xddot"]
    amplitude = F_ / math.sqrt(D2)
    for name, scale in (("x", 1), ("xdot", W_), ("xddot", W_ ** 2)):
        low, high = extremes[name]
        assert high == pytest.approx(scale * amplitude, rel=1e-5)
        assert low == pytest.approx(-scale * amplitude, rel=1e-5)


def test_multipliers_are_written_as_complex_numbers_or_reals():
    mech, scene = linear()
    mu = md.periodic_steady_state(mech, scene, {}).floquet
    assert np.all(np.abs(mu.multipliers.imag) > 1e-3)          # an underdamped pair
    for m in mu.multipliers:
        assert f"{m.real:.6g}{m.imag:+.6g}j" in str(mu)
    overdamped = md.Mechanism("overdamped", [x])
    overdamped.link("mass", m=1, x=x)
    overdamped.spring("spring", 1, stretch=x)
    overdamped.damper("damper", 5, stretch=x)
    overdamped.load("force", sp.cos(md.t), along=x)
    real = md.floquet(overdamped, replace(scene, name="s"), {})
    assert np.all(real.multipliers.imag == 0)
    # c = 5, k = 1: poles (-5 +- sqrt(21)) / 2, multipliers exp(pole * 2 pi)
    poles = [(-5 + math.sqrt(21)) / 2, (-5 - math.sqrt(21)) / 2]
    assert sorted(real.multipliers.real) == pytest.approx(
        sorted(math.exp(s * 2 * math.pi) for s in poles), rel=1e-6)
    assert ", ".join(f"{m.real:.6g}" for m in real.multipliers) in str(real)


@pytest.mark.parametrize("forcing, period", [
    (sp.cos(2 * md.t) + sp.sin(3 * md.t), 2 * math.pi),          # gcd of 2 and 3 is 1
    (sp.cos(1.5 * md.t) + sp.cos(2.5 * md.t), 4 * math.pi),      # rates 3/2, 5/2: 1/2
    (sp.cos(4 * md.t) * sp.sin(6 * md.t), math.pi),              # rates 4, 6: 2
])
def test_forcing_period_is_the_common_period_of_all_frequencies(forcing, period):
    mech = md.Mechanism("forced", [x])
    mech.link("mass", m=1, x=x)
    mech.spring("spring", 1, stretch=x)
    mech.load("force", forcing, along=x)
    scene = md.Scene("s", initial={x: 0, md.speed(x): 0}, t_end=1)
    assert md.forcing_period(mech, scene, {}) == pytest.approx(period, rel=1e-12)


def test_forcing_period_follows_the_scene_and_needs_the_frequency_value():
    mech, scene = linear()
    free = replace(scene, effects=["spring", "damper"])       # the force left out
    with pytest.raises(md.PeriodicError, match="do not depend on t"):
        md.forcing_period(mech, free, {})
    symbolic = md.Mechanism("forced", [x])
    symbolic.link("mass", m=1, x=x)
    symbolic.spring("spring", 1, stretch=x)
    symbolic.load("force", sp.cos(W * md.t), along=x)
    with pytest.raises(md.ParameterError,          # the one missing-value error
                       match=r"give values for Omega \(needed by the period of cos\(Omega\*t\)"):
        md.forcing_period(symbolic, scene, {})
    assert md.forcing_period(symbolic, scene, {W: 2.0}) == pytest.approx(math.pi)


@pytest.mark.parametrize("options", [{"method": "Radau"},
                                     {"atol": {x: 1e-12, md.speed(x): 1e-12}}],
                         ids=["implicit", "per-state atol"])
def test_linear_steady_state_with_an_implicit_method_or_per_state_tolerances(options):
    # The method of initial parameters with Radau (analytic Jacobian) and with atol per
    # state: the closed form x(0) = F (k - W^2) / D^2, x'(0) = F c W^2 / D^2.
    mech, scene = linear()
    steady = md.periodic_steady_state(mech, replace(scene, **options), {})
    assert steady.method == "initial parameters"
    assert steady.initial["x"] == pytest.approx(F_ * (K_ - W_ ** 2) / D2, abs=1e-8)
    assert steady.initial["xdot"] == pytest.approx(F_ * C_ * W_ ** 2 / D2, abs=1e-8)
    assert steady.at(2.0)["x"] == pytest.approx(exact(2.0), abs=1e-8)

"""Periodic motion near resonance and near a Floquet multiplier of 1: correct amplitudes
where a unique periodic motion exists, a clear error where it does not."""
import math

import numpy as np
import pytest
import sympy as sp

import mechdyn as md

x = md.coordinate("x")
k, c, F, w = sp.symbols("k c F w", positive=True)


def oscillator(damped=True):
    mech = md.Mechanism("forced oscillator", [x], units={x: "m"})
    mech.link("mass", m=1, x=x)
    mech.spring("spring", k, stretch=x)
    if damped:
        mech.damper("damper", c, stretch=x)
    mech.load("force", F * sp.cos(w * md.t), along=x)
    return mech


SCENE = md.Scene("steady", initial={x: 0, md.speed(x): 0}, t_end=1)


def amplitude(steady):
    times = np.linspace(0, steady.period, 2001)
    return np.max(np.abs(steady.result.at(times, x)))


def test_lightly_damped_oscillator_just_below_resonance():
    # |X| = F / sqrt((k - w^2)^2 + (c w)^2) = 98.0 for k = 1, c = 0.01, w = 0.999.
    params = {k: 1.0, c: 0.01, F: 1.0, w: 0.999}
    steady = md.periodic_steady_state(oscillator(), SCENE, params, period=2 * math.pi / 0.999)
    exact = 1 / math.sqrt((1 - 0.999**2) ** 2 + (0.01 * 0.999) ** 2)
    assert amplitude(steady) == pytest.approx(exact, rel=1e-6)
    assert max(abs(m) for m in steady.floquet.multipliers) < 1


def test_undamped_oscillator_detuned_from_a_multiplier_of_one():
    # Multipliers exp(+-2 pi i sqrt(k)/w) sit 6e-3 from 1: the periodic motion is unique,
    # X = F / (k - w^2) = 500.25 for w = 0.999.
    params = {k: 1.0, F: 1.0, w: 0.999}
    steady = md.periodic_steady_state(oscillator(damped=False), SCENE, params,
                                      period=2 * math.pi / 0.999)
    assert amplitude(steady) == pytest.approx(1 / (1 - 0.999**2), rel=1e-6)
    assert np.allclose(np.abs(steady.floquet.multipliers), 1.0, atol=1e-8)


def test_undamped_oscillator_at_resonance_has_no_periodic_motion():
    params = {k: 1.0, F: 1.0, w: 1.0}
    with pytest.raises(md.NoPeriodicSolutionError, match="multiplier"):
        md.periodic_steady_state(oscillator(damped=False), SCENE, params, period=2 * math.pi)

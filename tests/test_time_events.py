"""Conditions, switches and loads of time alone (issue 27 item 1): their crossings are
solved without the state, and sines and cosines of t bound the step, so a machine at
rest (whose solver steps would otherwise grow to the whole run) misses none of them.

References are worked by hand: a unit mass pushed by a unit force during [a, b] gains
speed b - a and travels (b - a)(T - (a + b)/2) by the time T; under cos(w t) from rest
its speed is sin(w T)/w.
"""
import math

import numpy as np
import pytest
import sympy as sp
from scipy.optimize import brentq

import mechdyn as md

q = md.coordinate("q")
BACKENDS = ["scipy", "compiled"]


def unit_mass(force):
    mech = md.Mechanism("unit mass", [q], units={q: "m"})
    mech.link("mass", m=1, x=q)
    mech.load("push", force, along=q)
    return mech


def run(mech, backend, t_end=10.0, u0=0.0, until=()):
    scene = md.Scene("run", initial={q: 0, md.speed(q): u0}, t_end=t_end, until=until,
                     rtol=1e-10)
    return mech.simulate(scene, {}, backend=backend)


def pulses(intervals, t_end):
    speed = sum(b - a for a, b in intervals)
    position = sum((b - a) * (t_end - (a + b) / 2) for a, b in intervals)
    return speed, position


@pytest.mark.parametrize("backend", BACKENDS)
def test_piecewise_switch_of_time_alone_pushes_a_mass_at_rest_exactly_when_it_should(
        backend):
    # F = 1 while sin t > 1/2: on (pi/6, 5 pi/6) and (13 pi/6, 17 pi/6) within 10 s.
    res = run(unit_mass(sp.Piecewise((1, sp.sin(md.t) > sp.Rational(1, 2)), (0, True))),
              backend)
    speed, position = pulses([(math.pi / 6, 5 * math.pi / 6),
                              (13 * math.pi / 6, 17 * math.pi / 6)], 10.0)
    assert res.final(md.speed(q)) == pytest.approx(speed, rel=1e-9)
    assert res.final(q) == pytest.approx(position, rel=1e-9)


@pytest.mark.parametrize("backend", BACKENDS)
def test_heaviside_of_a_slow_time_function_switches_at_each_crossing(backend):
    # F = Heaviside(sin(t/2) - 0.9): on where sin(t/2) > 0.9, i.e. t/2 in (asin 0.9,
    # pi - asin 0.9), one short pulse around t = pi within 10 s.
    a = 2 * math.asin(0.9)
    res = run(unit_mass(sp.Heaviside(sp.sin(md.t / 2) - sp.Rational(9, 10))), backend)
    speed, position = pulses([(a, 2 * math.pi - a)], 10.0)
    assert res.final(md.speed(q)) == pytest.approx(speed, rel=1e-9)
    assert res.final(q) == pytest.approx(position, rel=1e-9)


@pytest.mark.parametrize("backend", BACKENDS)
def test_load_faster_than_the_error_control_would_step_is_resolved(backend):
    # A unit mass gliding at 1 m/s under a small cos(200 t) mN: the load changes its speed
    # by 5e-6 m/s at most, below what the error control sees at rtol 1e-6, so its steps
    # grow over many periods (and alias the load); the step is bounded by the period.
    # From q = 0, u = 1: u(T) = 1 + a sin(w T)/w, q(T) = T + a (1 - cos(w T))/w^2.
    a, w = 1e-3, 200.0
    scene = md.Scene("glide", initial={q: 0, md.speed(q): 1}, t_end=10.0, rtol=1e-6)
    res = unit_mass(a * sp.cos(w * md.t)).simulate(scene, {}, backend=backend)
    assert res.final(md.speed(q)) - 1 == pytest.approx(a * math.sin(w * 10) / w, rel=1e-5)
    assert res.final(q) - 10 == pytest.approx(a * (1 - math.cos(w * 10)) / w ** 2,
                                              rel=1e-3)


@pytest.mark.parametrize("backend", BACKENDS)
def test_fast_oscillating_condition_on_a_slow_state_stops_at_its_first_crossing(backend):
    # q = t exactly (a free unit mass at unit speed: the solver's error estimate is 0);
    # the condition q + sin(20 t)/2 = 1.2 first rises through 1.2 before t = 1.2.
    def g(time):
        return time + 0.5 * math.sin(20 * time) - 1.2
    grid = np.linspace(0, 10, 100_001)
    k = next(i for i in range(1, len(grid)) if g(grid[i - 1]) < 0 <= g(grid[i]))
    expected = brentq(g, grid[k - 1], grid[k], xtol=1e-15)
    res = run(unit_mass(0), backend, u0=1.0,
              until=md.reaches(q + sp.sin(20 * md.t) / 2, 1.2, direction=+1))
    assert res.reason.startswith("reaches")
    assert res.t_end == pytest.approx(expected, rel=1e-9)
    assert expected < 1.0

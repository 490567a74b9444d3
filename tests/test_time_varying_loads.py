"""Held elements and closed loops under loads that vary with time: accelerations, holding
forces and constraint forces are those of the time asked for (mutants of friction.py that
evaluated them without the time survived: docs/mutation.md). Expected values by hand."""
import math

import numpy as np
import pytest
import sympy as sp

import mechdyn as md

phi = md.coordinate("phi")
TIMES = [0.3, 1.1, 2.0, 2.9]


def test_a_shaft_held_under_a_varying_load_has_zero_acceleration_and_holds_minus_the_load():
    # J = 1, load 10 sin t against a brake of 25: |load| <= 10 < 25, held for good. The
    # brake's moment is the holding moment -10 sin t; the acceleration is exactly zero.
    mech = md.Mechanism("held shaft", [phi])
    mech.link("shaft", J=1, angle=phi)
    mech.load("load", 10 * sp.sin(md.t), along=phi)
    mech.friction("brake", 25, along=phi)
    res = mech.simulate(md.Scene("held", initial={phi: 0, md.speed(phi): 0}, t_end=3,
                                 outputs=["brake"]), {})
    assert [e.kind for e in res.events] == []
    assert np.all(res.accelerations_at(TIMES) == 0.0)
    assert res.outputs_at(TIMES)["brake"] == pytest.approx(
        [-10 * math.sin(t) for t in TIMES], rel=1e-12)


def test_constraint_force_of_a_bead_on_a_line_follows_a_growing_push():
    # A bead of 2 kg on the line y = x, pushed along x by 4 t: both coordinates
    # accelerate at 4 t / (2 * 2) = t; the line supplies the y-force m a_y = 2 t.
    x, y = md.coordinates("x y")
    bead = md.Mechanism("bead on a line", [x, y])
    bead.link("bead", m=2, x=x, y=y)
    bead.load("push", 4 * md.t, along=x)
    bead.constraint("line", y - x)
    res = bead.simulate(md.Scene("push", initial={x: 0, y: 0, md.speed(x): 0}, t_end=3,
                                 outputs=["line"]), {})
    assert res.outputs_at(TIMES)["line"] == pytest.approx([2 * t for t in TIMES], rel=1e-9)
    assert res.accelerations_at(TIMES) == pytest.approx(np.array([TIMES, TIMES]), rel=1e-9)
    assert res.final(x) == pytest.approx(3.0 ** 3 / 6, rel=1e-8)       # x = t^3 / 6

"""Stiff couplings: stiffness-to-inertia ratio 1e10, inertia ratio 1e4.

``method="auto"`` measures the Jacobian's spectrum and takes the stiff method where the
fast modes are damped, and the elastic result matches the rigid limit (the same
declaration with the coupling made rigid). No assertion here depends on the machine:
the work is bounded by a step budget far above what a sound method needs, so a method
that goes pathological on some CPU fails the test instead of hanging it."""
import pytest
import sympy as sp

import mechdyn as md

phi1, phi2 = md.coordinates("phi_1 phi_2")
k, c = sp.symbols("k c", positive=True)
J1, J2, MOMENT = 1.0, 1e-4, 1.0


def coupled(damped):
    drive = md.Mechanism("stiff coupling", [phi1, phi2])
    drive.link("motor", J=J1, angle=phi1)
    drive.link("load", J=J2, angle=phi2)
    drive.spring("coupling", k, stretch=phi1 - phi2)
    if damped:
        drive.damper("coupling damping", c, stretch=phi1 - phi2)
    drive.load("drive", MOMENT, along=phi1)
    return drive


START = {phi1: 0, phi2: 0, md.speed(phi1): 0, md.speed(phi2): 0}
RIGID_ANGLE = MOMENT / (J1 + J2) / 2          # phi = M t^2 / (2 (J1 + J2)) at t = 1 s


def test_auto_takes_the_stiff_method_for_damped_fast_modes_and_matches_the_rigid_limit():
    # Damping ratio c / (2 sqrt(k J1 J2 / (J1 + J2))) = 0.1: a real coupling.
    drive = coupled(damped=True)
    scene = md.Scene("start", initial=START, t_end=1.0, max_steps=20_000)
    res = drive.simulate(scene, {k: 1e6, c: 2.0})
    assert res.stats["method"].split("+")[0] in ("Radau", "Rodas5P") and res.stats["njev"] >= 1
    assert res.final(phi1) == pytest.approx(RIGID_ANGLE, rel=1e-6)
    assert res.final(phi2) == pytest.approx(RIGID_ANGLE, rel=1e-6)
    rigid = drive.simulate(md.Scene("rigid", initial=START, t_end=1.0, rigid=["coupling"]),
                           {k: 1e6, c: 2.0})
    assert rigid.final(phi1) == pytest.approx(RIGID_ANGLE, rel=1e-12)
    assert res.final(phi1) == pytest.approx(rigid.final(phi1), rel=1e-6)


def test_undamped_coupling_at_a_tolerance_above_its_oscillation_is_stepped_over():
    # The step load excites a 1e5 rad/s oscillation of 1e-5 rad/s in the speeds: at
    # rtol = atol = 1e-6 the stiff method steps over it.
    scene = md.Scene("start", initial=START, t_end=1.0, rtol=1e-6, atol=1e-6,
                     max_steps=20_000)
    res = coupled(damped=False).simulate(scene, {k: 1e6})
    assert res.stats["method"].split("+")[0] in ("Radau", "Rodas5P")
    assert res.final(phi1) == pytest.approx(RIGID_ANGLE, rel=1e-6)
    assert res.final(phi2) == pytest.approx(RIGID_ANGLE, rel=1e-6)


def test_soft_coupling_is_left_to_an_explicit_method():
    res = coupled(damped=False).simulate(md.Scene("start", initial=START, t_end=0.1), {k: 1.0})
    assert res.stats["method"] in ("DOP853", "RK45")

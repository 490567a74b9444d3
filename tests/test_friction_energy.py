"""Friction only dissipates: a slider-crank coasting against slider friction passes its
dead centres and stops when the friction's work has used up its kinetic energy; and in
every bundled model with friction, clutches, stops or gears the energy balance closes
(the change of T + V equals the work of every element, minus what impacts took)."""
import dataclasses
import math

import numpy as np
import pytest
import sympy as sp

import mechdyn as md

phi = md.coordinate("phi")
R, L, J, MASS, F, OMEGA = 0.1, 0.4, 0.05, 2.0, 5.0, 19.5


def test_slider_crank_coasting_against_slider_friction_passes_its_dead_centres():
    # The slider's speed passes through zero at every dead centre while the crank turns
    # on: the friction must not stick there. It stops when F * path = J omega_0^2 / 2
    # (the start is a dead centre: I_red = J there), 9.5 J / 5 N = 1.9 m: nine and a
    # half strokes.
    x = R * sp.cos(phi) + sp.sqrt(L**2 - R**2 * sp.sin(phi) ** 2)
    crank = md.Mechanism("slider-crank", [phi])
    crank.link("crank", J=J, angle=phi)
    crank.link("slider", m=MASS, x=x)
    crank.friction("slider friction", F, along=x)
    res = crank.simulate(md.Scene("coast", initial={phi: 0, md.speed(phi): OMEGA},
                                  t_end=6), {})
    stick = [e for e in res.events if e.kind == "stick"]
    assert len(stick) == 1 and stick[0].time < 6
    assert res.final(md.speed(phi)) == 0.0
    assert 9 * math.pi < res.final(phi) < 10 * math.pi    # past nine dead centres
    # kinetic energy, from the kinematics (not from mechdyn), never increases
    times = np.linspace(0, stick[0].time, 40001)
    states = res.at(times)
    angle, omega = states["phi"], states["phidot"]
    slope = -R * np.sin(angle) - R**2 * np.sin(angle) * np.cos(angle) / np.sqrt(
        L**2 - R**2 * np.sin(angle) ** 2)
    kinetic = 0.5 * (J + MASS * slope**2) * omega**2
    assert np.all(np.diff(kinetic) <= 1e-9 * kinetic[0])
    # it stops where F times the slider's path has used up the initial kinetic energy
    position = R * np.cos(angle) + np.sqrt(L**2 - R**2 * np.sin(angle) ** 2)
    path = np.sum(np.abs(np.diff(position)))
    assert F * path == pytest.approx(0.5 * J * OMEGA**2, rel=2e-3)


FRICTION_MODELS = [("shoe_brake", "braking"), ("motor_startup", "braking"),
                   ("hoist_drive", "lower_brake"), ("hoist_drive", "lower_brake_rigid"),
                   ("clutch_engagement", "engage"), ("clutch_engagement", "engage_loaded"),
                   ("freewheel", "ride"), ("worm_hoist", "lift"), ("worm_hoist", "lower"),
                   ("worm_hoist", "hold"), ("hard_stop", "bounce")]


@pytest.mark.parametrize("name, scene_name", FRICTION_MODELS)
def test_energy_balance_of_every_friction_model(name, scene_name):
    model = md.load_model(f"models/{name}.py")
    mech = model.mechanism
    scene = model.scenes[scene_name]
    eqs = mech.equations(scene)
    working = [n for n in eqs.elements if not isinstance(mech.elements[n],
                                                         (md.Spring, md.Gravity, md.Stop))]
    labels = [f"power:{n}" for n in working + [g.name for g in eqs.gears]]
    scene = dataclasses.replace(scene, outputs=labels, until=(),
                                t_end=scene.t_end or 60.0)
    res = mech.simulate(scene, model.params)
    kinetic, potential = res.energy()
    change = kinetic[-1] + potential[-1] - kinetic[0] - potential[0]
    nodes, weights = np.polynomial.legendre.leggauss(8)
    work = 0.0
    for a, b in zip(res.t[:-1], res.t[1:]):
        if b > a:
            times = (a + b) / 2 + (b - a) / 2 * nodes
            powers = res.outputs_at(times)
            work += (b - a) / 2 * sum(weights @ powers[label] for label in labels)
    impacts = sum(e.energy or 0.0 for e in res.events if e.kind == "impact")
    scale = max(np.max(np.abs(kinetic)), np.max(np.abs(potential - potential[0])),
                abs(work), 1.0)
    assert change == pytest.approx(work - impacts, abs=1e-7 * scale)

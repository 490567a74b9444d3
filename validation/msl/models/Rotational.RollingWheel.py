"""Modelica.Mechanics.Rotational.Examples.RollingWheel: a torque step drives a wheel
inertia that rolls a mass against a quadratic speed-dependent resistance.

MSL components (Examples/RollingWheel.mo) and their mechdyn counterparts:

- ``torqueStep`` (stepTorque 10, offsetTorque 0, startTime 0.1) on ``inertia``: the load
  ``10`` for ``t >= 0.1`` (0 before) along ``phi``.
- ``inertia`` (J = 1), angle ``phi``.
- ``idealRollingWheel`` (radius 1): ``flangeT.s = radius * flangeR.phi``.
- ``mass`` (m = 1, L = 0) at ``x = radius * phi``.
- ``quadraticSpeedDependentForce`` (f_nominal = -10, ForceDirection = false,
  v_nominal = 5): the force on the mass is ``f_nominal (v/v_nominal)^2`` for ``v >= 0``
  and ``-f_nominal (v/v_nominal)^2`` for ``v < 0`` (a resistance both ways), along ``x``
  with ``v = radius * phi'``.

Start: inertia.phi = inertia.w = 0. Reference signals: inertia.phi = phi,
inertia.w = phi'.
"""
import sympy as sp

import mechdyn as md

phi = md.coordinate("phi")
J, m, radius, step_torque, start, f_nominal, v_nominal = sp.symbols(
    "J m radius stepTorque startTime f_nominal v_nominal")

v = radius * md.speed(phi)

mechanism = md.Mechanism("MSL Rotational.RollingWheel", coordinates=[phi])
mechanism.link("inertia", J=J, angle=phi)
mechanism.link("mass", m=m, x=radius * phi)
mechanism.load("torqueStep", sp.Piecewise((0, md.t < start), (step_torque, True)), along=phi)
mechanism.load("quadraticSpeedDependentForce",
               sp.Piecewise((f_nominal * (v / v_nominal)**2, v >= 0),
                            (-f_nominal * (v / v_nominal)**2, True)),
               along=radius * phi)

params = {J: 1, m: 1, radius: 1, step_torque: 10, start: 0.1, f_nominal: -10, v_nominal: 5}

scenes = {
    "reference": md.Scene("reference", t_end=5.0, initial={phi: 0, md.speed(phi): 0}),
}

signals = {"inertia.phi": phi, "inertia.w": md.speed(phi)}

"""Modelica.Mechanics.Rotational.Examples.LossyGearDemo2: LossyGearDemo1 with Coulomb
bearing friction on the driving inertia (both friction elements can be stuck at once).

MSL components (Examples/LossyGearDemo2.mo, Components/LossyGear.mo,
Components/BearingFriction.mo) and their mechdyn counterparts:

- ``DriveSine`` (amplitude 10, f = 1 Hz) -> ``torque1`` -> ``bearingFriction`` ->
  ``Inertia1`` (J = 1), angle ``phi_a``.
- ``bearingFriction`` (tau_pos = [0, 0.5; 1, 1], peak = 1, support fixed): Coulomb
  friction of magnitude ``0.5 + 0.5 |phi_a'|`` (the table's line, extrapolated through
  its last two points) along ``phi_a``; static limit 0.5.
- ``gear`` (LossyGear, ratio 2, lossTable = [0, 0.5, 0.5, 0, 0], support fixed).
- ``Inertia2`` (J = 1.5, phi = w = 0 at the start), angle ``phi_b``, loaded by ``load``
  (Ramp height 5, duration 2, offset -10) through ``torque2``.

Both stuck, the gear and the bearing hold together: the gear's holding interval depends
on the bearing's share, so any share that holds keeps them stuck (validation/msl/NEEDS.md).

Reference signals: Inertia2.phi = phi_b, Inertia2.w = phi_b'.
"""
import sympy as sp

import mechdyn as md


phi_a, phi_b = md.coordinates("phi_a phi_b")
t = md.t
w_a = md.speed(phi_a)

mechanism = md.Mechanism("MSL Rotational.LossyGearDemo2", coordinates=[phi_a, phi_b])
mechanism.link("Inertia1", J=1, angle=phi_a)
mechanism.link("Inertia2", J=1.5, angle=phi_b)
mechanism.load("torque1", 10 * sp.sin(2 * sp.pi * t), along=phi_a)
mechanism.friction("bearingFriction", 0.5 + 0.5 * sp.Piecewise((w_a, w_a >= 0), (-w_a, True)),
                   along=phi_a)
mechanism.load("torque2", -10 + 5 * sp.Min(t / 2, 1), along=phi_b)
mechanism.lossy_gear("gear", input=phi_a, output=phi_b, ratio=2, eta_forward=0.5,
                     eta_backward=0.5, bearing_forward=0, bearing_backward=0)

params = {}

scenes = {
    "reference": md.Scene("reference", t_end=0.5, initial={
        phi_a: 0, w_a: 0, phi_b: 0, md.speed(phi_b): 0}),
}

signals = {"Inertia2.phi": phi_b, "Inertia2.w": md.speed(phi_b)}

"""Modelica.Mechanics.Rotational.Examples.LossyGearDemo1: two inertias coupled by a gear
with 50 % mesh efficiency both ways; the gear locks when the drive cannot overcome it.

MSL components (Examples/LossyGearDemo1.mo, Components/LossyGear.mo) and their mechdyn
counterparts:

- ``Inertia1`` (J = 1), angle ``phi_a``, driven by ``torque1`` = ``DriveSine``
  (amplitude 10, f = 1 Hz): ``10 sin(2 pi t)`` along ``phi_a``.
- ``gear`` (LossyGear, ratio 2: ``phi_a = 2 phi_b``, lossTable = [0, 0.5, 0.5, 0, 0]:
  eta_mf1 = eta_mf2 = 0.5, no bearing friction; support fixed). Its mesh loss depends on
  the direction of power flow through the gear and it locks at zero speed while the
  driving side cannot overcome the loss (validation/msl/NEEDS.md has the equations).
- ``Inertia2`` (J = 1.5, phi = 0, w = 0 at the start), angle ``phi_b``, loaded by
  ``torque2`` = ``load`` (Ramp height 5, duration 2, offset -10):
  ``-10 + 5 min(t/2, 1)`` along ``phi_b``.

The gear is ``lossy_gear(name, input=, output=, ratio=, eta_forward=, eta_backward=,
bearing_forward=, bearing_backward=)``, which imposes ``input = ratio * output`` between
two coordinates and acts with the loss law (validation/msl/NEEDS.md).

Reference signals: Inertia2.phi = phi_b, Inertia2.w = phi_b'.
"""
import sympy as sp

import mechdyn as md


phi_a, phi_b = md.coordinates("phi_a phi_b")
t = md.t

mechanism = md.Mechanism("MSL Rotational.LossyGearDemo1", coordinates=[phi_a, phi_b])
mechanism.link("Inertia1", J=1, angle=phi_a)
mechanism.link("Inertia2", J=1.5, angle=phi_b)
mechanism.load("torque1", 10 * sp.sin(2 * sp.pi * t), along=phi_a)
mechanism.load("torque2", -10 + 5 * sp.Min(t / 2, 1), along=phi_b)
mechanism.lossy_gear("gear", input=phi_a, output=phi_b, ratio=2, eta_forward=0.5,
                     eta_backward=0.5, bearing_forward=0, bearing_backward=0)

params = {}

scenes = {
    "reference": md.Scene("reference", t_end=0.5, initial={
        phi_a: 0, md.speed(phi_a): 0, phi_b: 0, md.speed(phi_b): 0}),
}

signals = {"Inertia2.phi": phi_b, "Inertia2.w": md.speed(phi_b)}

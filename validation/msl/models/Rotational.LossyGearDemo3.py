"""Modelica.Mechanics.Rotational.Examples.LossyGearDemo3: two small inertias spinning at
10 rad/s through a lossy gear with bearing friction, no drive: the driving side is not
obvious (the case that failed before MSL 3.1's fix).

MSL components (Examples/LossyGearDemo3.mo, Components/LossyGear.mo) and their mechdyn
counterparts:

- ``Inertia1`` (J = 0.001, w start 10 (a guess, not fixed)), angle ``phi_a``;
  ``torque1`` = ``step`` (height 0): no drive.
- ``gear`` (LossyGear, ratio 1, lossTable = [0, 0.25, 0.25, 0.625, 2.5]: eta_mf1 =
  eta_mf2 = 0.25, tau_bf1 = 0.625, tau_bf2 = 2.5, so tau_bf_a = (tau_bf1 - tau_bf2) /
  (eta_mf1 - 1/eta_mf2) = 0.5; useSupport = false).
- ``Inertia2`` (J = 0.001, phi = 0, w = 10 fixed), angle ``phi_b``; ``torque2`` =
  ``step1`` (height 1, startTime 0.5) along ``phi_b``.

Expected from LossyGear's equations: with w_a > 0 and no drive, tau_eta = flange_a.tau -
tau_bf_a = 0, quadrant 1 applies, tauLoss = 0.75 * 0.5 + 0.625 = 1 N m on a total
inertia of 0.002: -500 rad/s^2, rest at t = 0.02 s, phi_b = 0.1; then locked (the step of
1 N m at 0.5 s cannot break it loose).

The gear: ``lossy_gear`` (validation/msl/NEEDS.md).

Reference signals: Inertia2.phi = phi_b, Inertia2.w = phi_b'.
"""
import sympy as sp

import mechdyn as md


phi_a, phi_b = md.coordinates("phi_a phi_b")
t = md.t

mechanism = md.Mechanism("MSL Rotational.LossyGearDemo3", coordinates=[phi_a, phi_b])
mechanism.link("Inertia1", J=0.001, angle=phi_a)
mechanism.link("Inertia2", J=0.001, angle=phi_b)
mechanism.load("torque2", sp.Piecewise((0, t < 0.5), (1, True)), along=phi_b)
mechanism.lossy_gear("gear", input=phi_a, output=phi_b, ratio=1, eta_forward=0.25,
                     eta_backward=0.25, bearing_forward=0.625, bearing_backward=2.5)

params = {}

scenes = {
    "reference": md.Scene("reference", t_end=1.0, initial={
        phi_a: 0, md.speed(phi_a): 10, phi_b: 0, md.speed(phi_b): 10}),
}

signals = {"Inertia2.phi": phi_b, "Inertia2.w": md.speed(phi_b)}

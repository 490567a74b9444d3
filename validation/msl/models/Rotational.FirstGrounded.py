"""Modelica.Mechanics.Rotational.Examples.FirstGrounded: Rotational.First with the torque
source and the gear grounded implicitly (useSupport = false) instead of through the
``fixed`` flange. The dynamics are the same as First's; so is the reference.

MSL components (Examples/FirstGrounded.mo) and their mechdyn counterparts:

- ``sine`` (Blocks.Sources.Sine, amplitude 10, f = 5 Hz) -> ``torque`` on ``inertia1``:
  the load ``10 sin(2 pi 5 t)`` along the motor angle ``ratio * phi_2``.
- ``inertia1`` (J = Jmotor = 0.1) on the motor side of ``idealGear`` (ratio 10:
  ``flange_a.phi = ratio * flange_b.phi``): the link ``motor`` turning by ``10 phi_2``.
- ``inertia2`` (J = 2, written as a literal in First.mo), angle ``phi_2``.
- ``spring`` (c = 1e4) between ``inertia2`` and ``inertia3``: stretch ``phi_3 - phi_2``.
- ``inertia3`` (J = Jload = 2), angle ``phi_3``.
- ``damper`` (d = damping = 10) from ``inertia2`` (flange_a) to ``fixed`` (flange_b):
  damps ``phi_2``; its ``phi_rel = flange_b.phi - flange_a.phi = -phi_2``.

Start: inertia2.phi = 0, inertia2.w = 0, spring.phi_rel = 0 (so phi_3 = 0),
inertia3.w = 0. Reference signals: damper.phi_rel = -phi_2, damper.w_rel = -phi_2',
inertia3.phi = phi_3, inertia3.w = phi_3'.
"""
import sympy as sp

import mechdyn as md

phi_2, phi_3 = md.coordinates("phi_2 phi_3")
J_motor, J_2, J_load, ratio, c, d, amplitude, f = sp.symbols(
    "J_motor J_2 J_load ratio c d amplitude f", positive=True)

mechanism = md.Mechanism("MSL Rotational.FirstGrounded", coordinates=[phi_2, phi_3])
mechanism.link("inertia1", J=J_motor, angle=ratio * phi_2)
mechanism.link("inertia2", J=J_2, angle=phi_2)
mechanism.link("inertia3", J=J_load, angle=phi_3)
mechanism.load("torque", amplitude * sp.sin(2 * sp.pi * f * md.t), along=ratio * phi_2)
mechanism.spring("spring", c, stretch=phi_3 - phi_2)
mechanism.damper("damper", d, stretch=phi_2)

params = {J_motor: 0.1, J_2: 2, J_load: 2, ratio: 10, c: 1e4, d: 10, amplitude: 10, f: 5}

scenes = {
    "reference": md.Scene("reference", t_end=1.0, initial={
        phi_2: 0, md.speed(phi_2): 0, phi_3: 0, md.speed(phi_3): 0}),
}

signals = {
    "damper.phi_rel": -phi_2,
    "damper.w_rel": -md.speed(phi_2),
    "inertia3.phi": phi_3,
    "inertia3.w": md.speed(phi_3),
}

"""Modelica.Mechanics.Rotational.Examples.CoupledClutches: four inertias coupled by three
clutches that engage at different times (2^3 configurations, 3^3 friction states).

MSL components (Examples/CoupledClutches.mo, Components/Clutch.mo,
Interfaces/PartialFriction.mo) and their mechdyn counterparts:

- ``J1``..``J4`` (J = 1 each), angles ``phi_1..phi_4``; J1 starts at w = 10, the others
  at rest, all at phi = 0.
- ``sin1`` (amplitude 10, f = 5 Hz) -> ``torque`` (support fixed) on J1.
- ``clutch1`` (J1 -> J2), ``clutch2`` (J2 -> J3), ``clutch3`` (J3 -> J4): Clutch with
  peak = 1.1, fn_max = 20, mu_pos = [0, 0.5], cgeo = 1: sliding torque
  ``cgeo mu fn_max f_normalized = 10 f_normalized``, static limit 1.1 times that, free
  (no torque, never stuck) while ``fn <= 0``; ``phi_rel = phi_(i+1) - phi_i``.
- ``f_normalized``: clutch1 ``sin2`` (amplitude 1, f = 0.2 Hz, phase pi/2, so
  ``cos(0.4 pi t)``, negative after 1.25 s: free); clutch2 ``step1`` (startTime 0.4);
  clutch3 ``step2`` (startTime 0.9).

The static limit above the sliding torque is ``friction(..., peak=...)``. Before the
friction state machine was rebuilt, clutch3 (zero torque capacity at rest) held from the
start, dragging J4 along: issue 14 defect 1.

Reference signals: J1.phi/w, clutch<i>.phi_rel/w_rel = phi_(i+1) - phi_i and its rate.
"""
import sympy as sp

import mechdyn as md


phi = md.coordinates("phi_1 phi_2 phi_3 phi_4")
mu, fn_max, peak, cgeo = sp.symbols("mu fn_max peak cgeo", positive=True)
t = md.t

f_normalized = [sp.sin(2 * sp.pi * 0.2 * t + 1.570796326794897),
                sp.Piecewise((0, t < 0.4), (1, True)),
                sp.Piecewise((0, t < 0.9), (1, True))]

mechanism = md.Mechanism("MSL Rotational.CoupledClutches", coordinates=phi)
for i, angle in enumerate(phi, start=1):
    mechanism.link(f"J{i}", J=1, angle=angle)
mechanism.load("torque", 10 * sp.sin(2 * sp.pi * 5 * t), along=phi[0])
for i in range(3):
    mechanism.friction(f"clutch{i + 1}", cgeo * mu * fn_max * sp.Max(f_normalized[i], 0),
                       along=phi[i + 1] - phi[i], peak=peak)

params = {mu: 0.5, fn_max: 20, peak: 1.1, cgeo: 1}

scenes = {
    "reference": md.Scene("reference", t_end=1.5, initial={
        phi[0]: 0, md.speed(phi[0]): 10, phi[1]: 0, md.speed(phi[1]): 0,
        phi[2]: 0, md.speed(phi[2]): 0, phi[3]: 0, md.speed(phi[3]): 0}),
}

signals = {"J1.phi": phi[0], "J1.w": md.speed(phi[0])}
for i in range(3):
    signals[f"clutch{i + 1}.phi_rel"] = phi[i + 1] - phi[i]
    signals[f"clutch{i + 1}.w_rel"] = md.speed(phi[i + 1]) - md.speed(phi[i])

"""Modelica.Mechanics.Rotational.Examples.Friction: a drive train with a slipping clutch
and a brake that engages at 0.5 s, when the motor torque is switched off.

MSL components (Examples/Friction.mo, Components/Clutch.mo, Components/Brake.mo,
Interfaces/PartialFriction.mo) and their mechdyn counterparts:

- ``sine`` (amplitude 200, f = 50/pi Hz, so ``200 sin(100 t)``) times ``step2``
  (height -1, offset 1, startTime 0.5: 1 before 0.5 s, 0 after) -> ``torque`` (support
  fixed) on ``inertia3``: the load along ``phi_3``.
- ``inertia3`` (J = 1, phi = 0, w = 100), ``inertia2`` (J = 0.05, phi = 0, w = 90),
  ``inertia1`` (J = 1, phi = 0, w = 90): angles ``phi_3, phi_2, phi_1``.
- ``clutch`` (fn_max = 160, mu_pos = [0, 0.5], peak = 1, cgeo = 1, f_normalized = 1 from
  ``const``) between inertia3 (flange_a) and inertia2 (flange_b): Coulomb friction of
  magnitude ``cgeo mu fn_max = 80 N m`` along ``phi_rel = phi_2 - phi_3``.
- ``spring`` (SpringDamper c = 160, d = 1) between inertia2 and the brake flange (=
  inertia1): spring and damper on ``phi_rel = phi_1 - phi_2``.
- ``brake`` (fn_max = 1600, mu_pos = [0, 0.5], peak = 1, cgeo = 1, support fixed,
  f_normalized = ``step`` (startTime 0.5)): Coulomb friction of magnitude 0 before 0.5 s
  and ``800 N m`` after, along ``phi_1``.

Reference signals: clutch.phi_rel/w_rel = phi_2 - phi_3 and its rate, inertia3.phi/w,
spring.phi_rel/w_rel = phi_1 - phi_2 and its rate.
"""
import sympy as sp

import mechdyn as md

phi_3, phi_2, phi_1 = md.coordinates("phi_3 phi_2 phi_1")
J_3, J_2, J_1, c, d, mu, fn_clutch, fn_brake, start = sp.symbols(
    "J_3 J_2 J_1 c d mu fn_clutch fn_brake startTime", positive=True)
t = md.t

mechanism = md.Mechanism("MSL Rotational.Friction", coordinates=[phi_3, phi_2, phi_1])
mechanism.link("inertia3", J=J_3, angle=phi_3)
mechanism.link("inertia2", J=J_2, angle=phi_2)
mechanism.link("inertia1", J=J_1, angle=phi_1)
mechanism.load("torque", 200 * sp.sin(100 * t) * sp.Piecewise((1, t < start), (0, True)),
               along=phi_3)
mechanism.friction("clutch", mu * fn_clutch, along=phi_2 - phi_3)
mechanism.spring("spring", c, stretch=phi_1 - phi_2)
mechanism.damper("spring damping", d, stretch=phi_1 - phi_2)
mechanism.friction("brake", mu * fn_brake * sp.Piecewise((0, t < start), (1, True)),
                   along=phi_1)

params = {J_3: 1, J_2: 0.05, J_1: 1, c: 160, d: 1, mu: 0.5, fn_clutch: 160,
          fn_brake: 1600, start: 0.5}

scenes = {
    "reference": md.Scene("reference", t_end=3.0, initial={
        phi_3: 0, md.speed(phi_3): 100, phi_2: 0, md.speed(phi_2): 90,
        phi_1: 0, md.speed(phi_1): 90}),
}

signals = {
    "clutch.phi_rel": phi_2 - phi_3, "clutch.w_rel": md.speed(phi_2) - md.speed(phi_3),
    "inertia3.phi": phi_3, "inertia3.w": md.speed(phi_3),
    "spring.phi_rel": phi_1 - phi_2, "spring.w_rel": md.speed(phi_1) - md.speed(phi_2),
}

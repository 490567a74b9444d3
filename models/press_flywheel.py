"""Crank press with a flywheel: steady running, speed fluctuation, flywheel size.

An induction motor (Kloss characteristic) and the flywheel sit on one fast shaft geared
to the crankshaft (ratio i: fast shaft speed i omega). The crank (radius r) drives the
ram (mass m_r, connecting rod l, lam = r/l) down by the slider-crank law

    s(phi) = r (1 - cos phi) + l (1 - sqrt(1 - lam^2 sin^2 phi))      (phi = 0: top)

The rod's mass is split between crank pin (in J_c) and ram (in m_r). The ram weighs on
the crank (gravity), and over the working part of the stroke, phi_w +- beta before the
bottom dead centre, the workpiece resists with a force rising from zero to F_p and back:
F_p (cos(phi - phi_w) - cos beta) / (1 - cos beta). Reduced to the crank:

    I_red = J_c + (J_m + J_f) i^2 + m_r s'(phi)^2               (periodic in phi, 2 pi)
    M_red = i kloss(i omega) + m_r g s'(phi) - F(phi) s'(phi)

Hand estimates with the values below: work per stroke F_p * s'(150 deg) *
integral of the pulse = 60 kN * 0.0207 m * 0.695 rad = 860 J (852 J exactly); at
about 100 strokes a minute the motor gives 1.4 kW (9 N m at 153 rad/s, slip 2.6 %).
The motor keeps pulling during the 60 degrees of working, so Delta E_max is about 5/6
of the work, 710 J, and the textbook flywheel for delta = 1/50 at 10.2 rad/s is
J_f = (710 / (0.02 * 10.2^2) - 6.7) / 15^2 = 1.49 kg m^2 on the fast shaft (6.7 kg m^2:
the rest of the mean I_red). The motor's slip evens the speed a little as well
(``md.flywheel`` solves for J_f: 1.42 kg m^2).

Scenes: ``steady`` (working strokes, started near the steady speed) and ``idle`` (no
workpiece).
"""
import sympy as sp

import mechdyn as md

phi = md.coordinate("phi")
r, l, m_r, J_c, J_m, J_f, i = sp.symbols("r l m_r J_c J_m J_f i", positive=True)
M_k, s_k, omega_s, F_p, phi_w, beta = sp.symbols("M_k s_k omega_s F_p phi_w beta",
                                                  positive=True)

stroke = r * (1 - sp.cos(phi)) + l * (1 - sp.sqrt(1 - (r / l) ** 2 * sp.sin(phi) ** 2))
pulse = (sp.cos(phi - phi_w) - sp.cos(beta)) / (1 - sp.cos(beta))
process = F_p * sp.Piecewise((pulse, pulse > 0), (0, True))

mechanism = md.Mechanism("Crank press with flywheel", coordinates=[phi], units={
    r: "m", l: "m", m_r: "kg", J_c: "kg*m^2", J_m: "kg*m^2", J_f: "kg*m^2", i: "1",
    M_k: "N*m", s_k: "1", omega_s: "rad/s", F_p: "N", phi_w: "rad", beta: "rad"})
mechanism.link("crank", J=J_c, angle=phi)
mechanism.link("motor rotor", J=J_m, angle=i * phi)
mechanism.link("flywheel", J=J_f, angle=i * phi)
mechanism.link("ram", m=m_r, y=-stroke)
mechanism.load("motor", md.motors.kloss(M_k, s_k, omega_s)(i * md.speed(phi)),
               along=i * phi)
mechanism.load("workpiece", -process, along=stroke, tags=["process"])
mechanism.gravity()

params = {r: 0.05, l: 0.25, m_r: 150, J_c: 2.0, J_m: 0.02, J_f: 1.5, i: 15,
          M_k: 36, s_k: 0.2, omega_s: 157.08, F_p: 60e3, phi_w: 5 * sp.pi / 6,
          beta: sp.pi / 6}

scenes = {
    "steady": md.Scene("steady", initial={phi: 0, md.speed(phi): 10}, t_end=20,
                       outputs=["motor", "workpiece"]),
    "idle": md.Scene("idle", effects=["motor", "gravity"],
                     initial={phi: 0, md.speed(phi): 10}, t_end=20, outputs=["motor"]),
}

"""Crank press duty cycle: start-up, working strokes, braking, holding at rest.

The press of ``press_flywheel.py`` (induction motor and flywheel on a fast shaft geared
1 : i to the crankshaft, slider-crank ram, workpiece resisting over phi_w +- beta) with a
shoe brake on the flywheel shaft (moment M_b there, i M_b at the crank). One cycle:

1. ``startup``: from rest at the top dead centre, motor on, no workpiece, until the
   crank reaches 95 rpm (the motor idles the crank at about 99.7 rpm);
2. ``steady``: working strokes for 10 s (about 16 strokes of 852 J each);
3. ``braking``: motor off, brake on, until the crank stops;
4. ``hold``: the brake holds the crank against the ram's weight for 2 s.

``mechdyn simulate models/press_cycle.py --scene startup+steady+braking+hold``. The
phase scenes after the first give no initial values: each starts where the one before
ended. Values carry units where they are typed (``"1500 rpm"``, ``"80 N*m"``).

Hand estimates: I_red at the crank is about J_c + (J_m + J_f) i^2 = 344 kg m^2, so the
kinetic energy at 10 rad/s is 17 kJ; braking with i M_b = 1200 N*m stops the crank in
about 344 * 10 / 1200 = 2.9 s, after about 2.3 turns; the ram's weight needs at most
m_r g r (1 + lam) = 92 N*m to hold, far below the brake's 1200 N*m.
"""
import sympy as sp

import mechdyn as md

phi = md.coordinate("phi")
r, l, m_r, J_c, J_m, J_f, i = sp.symbols("r l m_r J_c J_m J_f i", positive=True)
M_k, s_k, omega_s, F_p, phi_w, beta, M_b = sp.symbols(
    "M_k s_k omega_s F_p phi_w beta M_b", positive=True)

stroke = r * (1 - sp.cos(phi)) + l * (1 - sp.sqrt(1 - (r / l) ** 2 * sp.sin(phi) ** 2))
pulse = (sp.cos(phi - phi_w) - sp.cos(beta)) / (1 - sp.cos(beta))
process = F_p * sp.Piecewise((pulse, pulse > 0), (0, True))

mechanism = md.Mechanism("Crank press duty cycle", coordinates=[phi], units={
    r: "m", l: "m", m_r: "kg", J_c: "kg*m^2", J_m: "kg*m^2", J_f: "kg*m^2", i: "1",
    M_k: "N*m", s_k: "1", omega_s: "rad/s", F_p: "N", phi_w: "rad", beta: "rad",
    M_b: "N*m"})
mechanism.link("crank", J=J_c, angle=phi)
mechanism.link("motor rotor", J=J_m, angle=i * phi)
mechanism.link("flywheel", J=J_f, angle=i * phi)
mechanism.link("ram", m=m_r, y=-stroke)
mechanism.load("motor", md.motors.kloss(M_k, s_k, omega_s)(i * md.speed(phi)),
               along=i * phi)
mechanism.load("workpiece", -process, along=stroke, tags=["process"])
mechanism.friction("brake", M_b, along=i * phi)
mechanism.gravity()

params = {r: "50 mm", l: "250 mm", m_r: 150, J_c: 2.0, J_m: 0.02, J_f: 1.5, i: 15,
          M_k: "36 N*m", s_k: 0.2, omega_s: "1500 rpm", F_p: "60 kN", phi_w: 5 * sp.pi / 6,
          beta: sp.pi / 6, M_b: "80 N*m"}

scenes = {
    "startup": md.Scene("startup", effects=["motor", "gravity"],
                        initial={phi: 0, md.speed(phi): 0},
                        until=md.reaches(md.speed(phi), "95 rpm", direction=1),
                        outputs=["motor", "power:motor"]),
    "steady": md.Scene("steady", effects=["motor", "workpiece", "gravity"], t_end="10 s",
                       outputs=["motor", "power:motor", "workpiece"]),
    "braking": md.Scene("braking", effects=["brake", "gravity"], until=md.stopped(phi),
                        outputs=["brake"]),
    "hold": md.Scene("hold", effects=["brake", "gravity"], t_end="2 s", outputs=["brake"]),
}

"""Hoist drive: induction motor, coupling with brake pulley, two-stage gearbox, drum,
elastic rope, load.

Coordinates: the motor angle phi and the load's height h. The rope's stretch is the arc
the drum has wound in minus the height the load has risen, r_b phi / i - h, with
i = i_1 i_2 and the rope stiffness E_k / l. Made rigid (scenes ``*_rigid``) the rope
fixes h = r_b phi / i and the drive reduces to the motor shaft by hand:
I_red = J_m + J_c + J_g / i_1^2 + J_d / i^2 + m r_b^2 / i^2,
M_red = M_motor - m g r_b / (i eta) lifting, M_motor + m g r_b eta / i lowering.

The weight m g reaches the drum through the rope and the motor through the gearbox
(a load with ``efficiency=eta``: losses follow the power flow, as in the hand
reduction). The load mass hangs on the rope, which is linear, so its motion is taken
about the static stretch m g / k: the output ``rope`` is the rope force above the
static weight, and the rope starts relaxed at rest or at steady speed.

The motor follows Kloss's formula M = 2 M_k / (s / s_k + s_k / s), s = 1 - omega / omega_0
(a crane motor with a soft characteristic); the brake is a Coulomb friction moment M_br
on the coupling. Values: a 2 t load on a 0.2 m drum, i = 5 * 8 = 40, lifting at about
0.75 m/s; rope E A = 8e6 N over 20 m (k = 4e5 N/m, 10 N m/rad at the motor).
"""
import sympy as sp

import mechdyn as md
from mechdyn import reduction

phi, h = md.coordinates("phi h")
J_m, J_c, J_g, J_d, i_1, i_2, r_b = sp.symbols("J_m J_c J_g J_d i_1 i_2 r_b", positive=True)
m, g, E_k, l, d_r, eta = sp.symbols("m g E_k l d_r eta", positive=True)
M_k, s_k, omega_0, M_br = sp.symbols("M_k s_k omega_0 M_br", positive=True)

i = i_1 * i_2
drum_arc = r_b * phi / i

mechanism = md.Mechanism("Hoist drive", coordinates=[phi, h], units={
    h: "m", J_m: "kg*m^2", J_c: "kg*m^2", J_g: "kg*m^2", J_d: "kg*m^2", i_1: "1", i_2: "1",
    r_b: "m", m: "kg", g: "m/s^2", E_k: "N", l: "m", d_r: "N*s/m", eta: "1", M_k: "N*m",
    s_k: "1", omega_0: "rad/s", M_br: "N*m"})
mechanism.link("motor rotor", J=J_m, angle=phi)
mechanism.link("coupling", J=J_c, angle=phi)
mechanism.link("intermediate shaft", J=J_g, angle=phi / i_1)
mechanism.link("drum", J=J_d, angle=phi / i)
mechanism.link("load", m=m, y=h)
mechanism.load("motor", md.motors.kloss(M_k, s_k, omega_0)(md.speed(phi)), along=phi)
mechanism.load("weight", -m * g, along=drum_arc, efficiency=eta)
mechanism.spring("rope", E_k / l, stretch=drum_arc - h)
mechanism.damper("rope damping", d_r, stretch=drum_arc - h)
mechanism.friction("brake", M_br, along=phi)

params = {J_m: 0.2, J_c: 0.15, J_g: 0.05, J_d: 6.0, i_1: 5, i_2: 8, r_b: 0.2,
          m: 2000, g: 9.81, E_k: 8e6, l: 20, d_r: 1100,   # about 2 % of critical
          eta: reduction.efficiency(gear_stages=2, bearings=3),   # 0.849
          M_k: 450, s_k: 0.35, omega_0: 50 * sp.pi, M_br: 200}

lifting = ["motor", "weight", "rope", "rope damping"]
braking = ["brake", "weight", "rope", "rope damping"]
lowering = -0.75 * i / r_b            # motor speed while lowering at 0.75 m/s, rad/s
scenes = {
    # Released from the brake at rest.
    "lift_start": md.Scene("lift_start", effects=lifting, t_end=2.0, outputs=["rope"],
                           initial={phi: 0, md.speed(phi): 0, h: 0, md.speed(h): 0}),
    "lift_start_rigid": md.Scene("lift_start_rigid", effects=lifting, rigid=["rope"],
                                 t_end=2.0, initial={phi: 0, md.speed(phi): 0}),
    # Lowering at 0.75 m/s, motor switched off, the brake sets in.
    "lower_brake": md.Scene("lower_brake", effects=braking, t_end=2.0, outputs=["rope"],
                            initial={phi: 0, md.speed(phi): lowering, h: 0,
                                     md.speed(h): -0.75}),
    "lower_brake_rigid": md.Scene("lower_brake_rigid", effects=braking, rigid=["rope"],
                                  t_end=2.0, initial={phi: 0, md.speed(phi): lowering}),
}

"""Scotch yoke, the sine mechanism (worked example 4).

Crank 1 (J1A, length l) turns the yoke 3 (mass m3), s3 = l cos(phi); F3 acts on the yoke.
I_red = J1A + m3 (l sin phi)^2, M_red = M1 - F3 l sin(phi).
"""
import sympy as sp

import mechdyn as md

phi = md.coordinate("phi")
J_1A, m_3, l, M_1, F_3 = sp.symbols("J_1A m_3 l M_1 F_3", positive=True)

s_3 = l * sp.cos(phi)

mechanism = md.Mechanism("Scotch yoke", coordinates=[phi], units={
    J_1A: "kg*m^2", m_3: "kg", l: "m", M_1: "N*m", F_3: "N"})
mechanism.link("crank", J=J_1A, angle=phi, points=[(0, 0), (s_3, l * sp.sin(phi))])
mechanism.link("yoke", m=m_3, x=s_3, points=[(s_3, -l), (s_3, l)])    # the slot
mechanism.load("drive", M_1, along=phi, tags=["motor"])
mechanism.load("resistance", F_3, along=s_3, tags=["process"])

params = {J_1A: 0.02, m_3: 2.0, l: 0.1, M_1: 2.0, F_3: 10.0}

scenes = {
    "startup": md.Scene("startup", initial={phi: 0, md.speed(phi): 0}, t_end=1.0,
                        outputs=["power:drive"]),
}

"""Cam with a translating follower (worked example 3), uniform-velocity rise.

Rise s = h phi / Phi: I_red = J1A + m2 (h/Phi)^2, M_red = M1 - F2 h/Phi.
"""
import sympy as sp

import mechdyn as md

phi = md.coordinate("phi")
J_1A, m_2, h, Phi, M_1, F_2 = sp.symbols("J_1A m_2 h Phi M_1 F_2", positive=True)

rise = h * phi / Phi

mechanism = md.Mechanism("Cam and translating follower", coordinates=[phi],
                         units={J_1A: "kg*m^2", m_2: "kg", h: "m", Phi: "rad",
                                M_1: "N*m", F_2: "N"})
mechanism.link("cam", J=J_1A, angle=phi)
mechanism.link("follower", m=m_2, y=rise)
mechanism.load("drive", M_1, along=phi)
mechanism.load("follower force", -F_2, along=rise)

params = {J_1A: 0.01, m_2: 0.5, h: 0.02, Phi: sp.pi / 2, M_1: 0.5, F_2: 20}

scenes = {
    "rise": md.Scene("rise", initial={phi: 0, md.speed(phi): 0}, t_end=0.5,
                     until=md.reaches(phi, Phi)),
}

"""Rope hoist with two shafts (worked example 6).

Shaft 1 (I1 = m1 rho1^2 = 8 kg m^2, pulley R1) is driven by M = 4200 + 200 t N m and drives
shaft 2 (pulley R2, own inertia m2 rho2^2, drum r2) by a belt without slip; the drum lifts
m3 = 400 kg against a resisting moment Mc. Coordinate: shaft 2's angle phi_2.
eps2 = 4.0336 t + 0.45983 rad/s^2.
"""
import sympy as sp

import mechdyn as md

phi_2 = md.coordinate("phi_2")
I_1, R_1, R_2, m_2, rho_2, r_2, m_3, M_c, g = sp.symbols(
    "I_1 R_1 R_2 m_2 rho_2 r_2 m_3 M_c g", positive=True)
M_0, M_t = sp.symbols("M_0 M_t", positive=True)     # motor moment M_0 + M_t t

phi_1 = R_2 / R_1 * phi_2        # belt without slip: R1 omega1 = R2 omega2
height = r_2 * phi_2             # the load climbs with the drum

mechanism = md.Mechanism("Rope hoist", coordinates=[phi_2], units={
    I_1: "kg*m^2", R_1: "m", R_2: "m", m_2: "kg", rho_2: "m", r_2: "m", m_3: "kg",
    M_c: "N*m", g: "m/s^2", M_0: "N*m", M_t: "N*m/s"})
mechanism.link("shaft 1", J=I_1, angle=phi_1)
mechanism.link("shaft 2", J=m_2 * rho_2**2, angle=phi_2)
mechanism.link("load", m=m_3, y=height)
mechanism.load("motor", M_0 + M_t * md.t, along=phi_1)
mechanism.load("resistance", -M_c, along=phi_2)
mechanism.gravity(g)

params = {I_1: 100 * 0.08, R_1: 0.6, R_2: 0.4, m_2: 150, rho_2: 0.3, r_2: 0.2,
          m_3: 400, M_c: 2000, g: 9.81, M_0: 4200, M_t: 200}

scenes = {
    "startup": md.Scene("startup", initial={phi_2: 0, md.speed(phi_2): 3}, t_end=3.0),
}

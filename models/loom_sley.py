"""Loom sley drive with an elastic crankshaft and an elastic sley beam (worked example 8).

The main shaft turns at the imposed speed omega (250 rpm) at crank A. Crank B, at the
far end of the shaft, lags by the torsion angle phi_2 (crankshaft stiffness k_t between
the cranks). Each crank drives its sword by a slider-crank of radius lam and rod l whose
transmission function is lam sin(theta) - (lam^2 / (2 l)) sin(2 theta), so the sword's
travel is s(theta) = -lam cos(theta) + (lam^2 / (4 l)) cos(2 theta). The sley beam,
carried by the swords, is lumped into masses 3 and 4 (0.206 kg each) at its thirds,
each held by the beam's bending stiffness k_b to the straight line between the sword
ends; x_3, x_4 are their travels. Three coordinates, positions periodic in t: for small
deflections the linear system Y' + A(t) Y = b(t) of the worked example.

Values the text does not give (a light loom, chosen so the torsion amplitude is of the
reported order 0.0037 rad): lam = 0.08 m, l = 0.25 m; crank B with its share of the
shaft J_2 = 0.01 kg m^2; sword and rod of side B reduced to the sword end m_s = 1.5 kg;
crankshaft a steel bar of 23 mm over 1.5 m, k_t = G pi d^4 / (32 L) = 1450 N m/rad;
beam k_b = 3.25e5 N/m (mass 3 alone would ring at about 200 Hz); dampers at about 5 %
of critical. The sword of side A follows the imposed crank and adds nothing.
"""
import sympy as sp

import mechdyn as md

phi_2, x_3, x_4 = md.coordinates("phi_2 x_3 x_4")
omega, lam, l, J_2, m_s, m_3, m_4 = sp.symbols("omega lambda l J_2 m_s m_3 m_4",
                                                positive=True)
k_t, d_t, k_b, d_b = sp.symbols("k_t d_t k_b d_b", positive=True)


def sword(theta):
    """Sword travel of a slider-crank turned by theta (first order in lam / l)."""
    return -lam * sp.cos(theta) + lam**2 / (4 * l) * sp.cos(2 * theta)


crank_A = omega * md.t                 # imposed
crank_B = omega * md.t + phi_2         # lags by the crankshaft's torsion
s_A, s_B = sword(crank_A), sword(crank_B)
bend_3 = x_3 - (2 * s_A + s_B) / 3     # deflection of the beam at mass 3
bend_4 = x_4 - (s_A + 2 * s_B) / 3

mechanism = md.Mechanism("Loom sley drive", coordinates=[phi_2, x_3, x_4], units={
    x_3: "m", x_4: "m", omega: "rad/s", lam: "m", l: "m", J_2: "kg*m^2", m_s: "kg",
    m_3: "kg", m_4: "kg", k_t: "N*m/rad", d_t: "N*m*s/rad", k_b: "N/m", d_b: "N*s/m"})
mechanism.link("crank B", J=J_2, angle=crank_B)
mechanism.link("sword B", m=m_s, x=s_B)
mechanism.link("beam 3", m=m_3, x=x_3)
mechanism.link("beam 4", m=m_4, x=x_4)
mechanism.spring("crankshaft", k_t, stretch=phi_2)
mechanism.damper("crankshaft damping", d_t, stretch=phi_2)
mechanism.spring("beam at 3", k_b, stretch=bend_3)
mechanism.spring("beam at 4", k_b, stretch=bend_4)
mechanism.damper("beam damping at 3", d_b, stretch=bend_3)
mechanism.damper("beam damping at 4", d_b, stretch=bend_4)

params = {omega: 250 * 2 * sp.pi / 60, lam: 0.08, l: 0.25, J_2: 0.01, m_s: 1.5,
          m_3: 0.206, m_4: 0.206, k_t: 1450, d_t: 0.5, k_b: 3.25e5, d_b: 26}

at_dead_centre = sword(0)            # both swords at the back dead centre at t = 0
scenes = {
    # the default method: the 200 Hz beam is only mildly stiff, so it runs the compiled
    # DOP853 (10 turns: 12k steps, 19 ms; scipy's LSODA 0.56 s and 45x the error)
    "run": md.Scene("run", t_end=2.4, outputs=["crankshaft"],
                    initial={phi_2: 0, x_3: at_dead_centre, x_4: at_dead_centre,
                             md.speed(phi_2): 0, md.speed(x_3): 0, md.speed(x_4): 0}),
}

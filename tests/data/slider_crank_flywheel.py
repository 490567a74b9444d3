"""A user's slider-crank with a flywheel (issue 29): exact slider position
x_s = r cos(phi) + sqrt(L^2 - r^2 sin^2 phi), a Kloss induction motor, Coulomb friction
on the slider guide and a shoe brake on the flywheel; start-up, then braking.
"""
import sympy as sp

import mechdyn as md

phi = md.coordinate("phi")
r, L, J_f, m_s, F_r, M_b, M_k, s_k, omega_s = sp.symbols(
    "r L J_f m_s F_r M_b M_k s_k omega_s", positive=True)
x_s = r * sp.cos(phi) + sp.sqrt(L**2 - r**2 * sp.sin(phi)**2)

mechanism = md.Mechanism("Slider-crank with flywheel", [phi], units={
    r: "m", L: "m", J_f: "kg*m^2", m_s: "kg", F_r: "N", M_b: "N*m", M_k: "N*m", s_k: "1",
    omega_s: "rad/s"})
mechanism.link("flywheel", J=J_f, angle=phi)
mechanism.link("slider", m=m_s, x=x_s)
mechanism.load("motor", md.motors.kloss(M_k, s_k, omega_s), along=phi)   # at phidot
mechanism.friction("guide", F_r, along=x_s)
mechanism.friction("brake", M_b, along=phi)

params = {r: 0.1, L: 0.4, J_f: 0.5, m_s: 2.0, F_r: 5.0, M_b: 40.0, M_k: 60.0, s_k: 0.2,
          omega_s: 157.0}
scenes = {
    "startup": md.Scene("startup", effects=["motor", "guide"],
                        initial={phi: 0, md.speed(phi): 0}, t_end=4.0),
    "braking": md.Scene("braking", effects=["guide", "brake"],
                        initial={phi: 0, md.speed(phi): 150}, until=md.stopped(phi)),
}

"""Exact slider-crank (crank r = 0.1 m, rod L = 0.4 m) started by a DC shunt motor.

No small-rod-angle series: the slider sits at x = r cos(phi) + sqrt(L^2 - r^2 sin^2 phi),
the rod's centre of mass halfway along it, the rod turned by asin(r sin(phi) / L). The
reduced inertia varies with the crank angle and the motor moment with the speed (case 5):
there is no closed form. Started from rest, the motor M_0 (1 - omega / omega_0) brings the
crank towards omega_0 = 100 rad/s, the speed rippling with the crank angle.
"""
import sympy as sp

import mechdyn as md

phi = md.coordinate("phi")
r, L, J_1, m_2, J_2, m_3, M_0, omega_0 = sp.symbols(
    "r L J_1 m_2 J_2 m_3 M_0 omega_0", positive=True)

rod_run = sp.sqrt(L**2 - r**2 * sp.sin(phi)**2)   # slider travel beyond the crank pin

mechanism = md.Mechanism("Slider-crank", coordinates=[phi], units={
    r: "m", L: "m", J_1: "kg*m^2", m_2: "kg", J_2: "kg*m^2", m_3: "kg", M_0: "N*m",
    omega_0: "rad/s"})
pin = (r * sp.cos(phi), r * sp.sin(phi))
slider_x = r * sp.cos(phi) + rod_run
mechanism.link("crank", J=J_1, angle=phi, points=[(0, 0), pin])
mechanism.link("rod", m=m_2, J=J_2, x=r * sp.cos(phi) + rod_run / 2, y=r * sp.sin(phi) / 2,
               angle=-sp.asin(r * sp.sin(phi) / L), points=[pin, (slider_x, 0)])
mechanism.link("slider", m=m_3, x=slider_x,
               points=[(slider_x - r / 4, 0), (slider_x + r / 4, 0)])
mechanism.load("motor", md.motors.dc_shunt(M_0, omega_0)(md.speed(phi)), along=phi)

params = {r: 0.1, L: 0.4, J_1: 0.01, m_2: 0.5, J_2: 0.5 * 0.4**2 / 12, m_3: 1.0,
          M_0: 5.0, omega_0: 100.0}

scenes = {
    "startup": md.Scene("startup", initial={phi: 0, md.speed(phi): 0}, t_end=1.0),
}

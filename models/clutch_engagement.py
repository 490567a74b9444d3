"""Clutch engagement: an engine's flywheel J_1 spinning at omega_0 is coupled to a load
J_2 at rest by a dry clutch whose normal force ramps up, F = F_max min(t / t_r, 1).

The clutch slips while the moment it transmits, M_c = mu r_m F (friction coefficient
mu, mean radius r_m), accelerates the load and brakes the flywheel; it locks when both
turn at the same speed, and holds while the moment needed stays within its static limit
peak * mu r_m F. Until the lock the slip speed falls as
omega_0 - (1/J_1 + 1/J_2) mu r_m F_max t^2 / (2 t_r) (within the ramp); the heat of the
slip is the kinetic energy lost, J_1 J_2 omega_0^2 / (2 (J_1 + J_2)) (momentum is kept).
Scene ``engage``: no engine moment; ``engage_loaded``: a load moment M_L on J_2 that the
locked clutch carries, so it stays locked while M_L J_1 / (J_1 + J_2) stays within its
static limit.
"""
import sympy as sp

import mechdyn as md

phi_1, phi_2 = md.coordinates("phi_1 phi_2")
J_1, J_2, mu, r_m, F_max, t_r, omega_0, M_L = sp.symbols(
    "J_1 J_2 mu r_m F_max t_r omega_0 M_L", positive=True)

mechanism = md.Mechanism("Clutch engagement", coordinates=[phi_1, phi_2], units={
    J_1: "kg*m^2", J_2: "kg*m^2", mu: "1", r_m: "m", F_max: "N", t_r: "s",
    omega_0: "rad/s", M_L: "N*m"})
mechanism.link("flywheel", J=J_1, angle=phi_1)
mechanism.link("load", J=J_2, angle=phi_2)
mechanism.clutch("clutch", normal_force=F_max * sp.Min(md.t / t_r, 1), mu=mu,
                 along=phi_2 - phi_1, peak=1.25, geometry=r_m)
mechanism.load("load moment", -M_L, along=phi_2, tags=["loaded"])

params = {J_1: 0.5, J_2: 1.5, mu: 0.3, r_m: 0.1, F_max: 2000, t_r: 0.5, omega_0: 100,
          M_L: 20}

start = {phi_1: 0, phi_2: 0, md.speed(phi_1): omega_0, md.speed(phi_2): 0}
outputs = ["clutch", "clutch.slip", "clutch.mode"]
scenes = {
    "engage": md.Scene("engage", effects=["clutch"], initial=start, t_end=2,
                       outputs=outputs),
    "engage_loaded": md.Scene("engage_loaded", initial=start, t_end=2, outputs=outputs),
}

"""Two-mass drive: motor J1 -> elastic shaft (stiffness k, damping c) -> load J2.

A constant motor moment M applied suddenly at rest. Natural frequency
omega = sqrt(k (J1 + J2) / (J1 J2)) (here 209.8 rad/s, 33.4 Hz) besides the rigid-body
mode. Rigid, the drive accelerates at M / (J1 + J2) and the shaft carries
M J2 / (J1 + J2); elastic and undamped, the shaft moment swings up to twice that.
"""
import sympy as sp

import mechdyn as md

phi_1, phi_2 = md.coordinates("phi_1 phi_2")
J_1, J_2, k, c, M = sp.symbols("J_1 J_2 k c M", positive=True)

twist = phi_1 - phi_2

mechanism = md.Mechanism("Two-mass drive", coordinates=[phi_1, phi_2], units={
    J_1: "kg*m^2", J_2: "kg*m^2", k: "N*m/rad", c: "N*m*s/rad", M: "N*m"})
mechanism.link("motor", J=J_1, angle=phi_1)
mechanism.link("load", J=J_2, angle=phi_2)
mechanism.spring("shaft", k, stretch=twist)
mechanism.damper("shaft damping", c, stretch=twist)
mechanism.load("motor moment", M, along=phi_1)

params = {J_1: 0.05, J_2: 0.5, k: 2000, c: 0.5, M: 20}

at_rest = {phi_1: 0, phi_2: 0, md.speed(phi_1): 0, md.speed(phi_2): 0}
scenes = {
    "start": md.Scene("start", initial=at_rest, t_end=0.5, outputs=["shaft"]),
    "start_undamped": md.Scene("start_undamped", effects=["motor moment", "shaft"],
                               initial=at_rest, t_end=0.5, outputs=["shaft"]),
    "start_rigid": md.Scene("start_rigid", rigid=["shaft"], t_end=0.5,
                            initial={phi_1: 0, md.speed(phi_1): 0}),
}

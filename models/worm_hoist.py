"""Hoist with a self-locking worm gear: a motor (J_m) turns the worm, the worm wheel
turns the drum (J_d, radius r) that carries a load m; ratio i, forward efficiency eta
(worm driving), backward efficiency 0 (the load can never drive the worm: self-locking).

Lifting with the motor moment M, the worm drives and the loss is (1 - eta) of the
moment it passes on: the drum accelerates at (i eta M - m g r) / (J_d + m r^2 + eta i^2
J_m). With the motor off the drive coasts up, the worm's own inertia still driving
(-m g r / (J_d + m r^2 + eta i^2 J_m)), stops and stays locked: the load hangs on the
gear. Lowering, the motor must drive the worm backward; the load would overhaul the gear
but cannot drive the worm, so the drive turns at the motor's pace alone:
phi_m'' = -M_low / J_m, whatever the load.
"""
import sympy as sp

import mechdyn as md

phi_m, phi_d = md.coordinates("phi_m phi_d")
J_m, J_d, i, eta, r, m, g, M, t_m, M_low = sp.symbols(
    "J_m J_d i eta r m g M t_m M_low", positive=True)

mechanism = md.Mechanism("Worm hoist", coordinates=[phi_m, phi_d], units={
    J_m: "kg*m^2", J_d: "kg*m^2", i: "1", eta: "1", r: "m", m: "kg", g: "m/s^2",
    M: "N*m", t_m: "s", M_low: "N*m"})
mechanism.link("motor", J=J_m, angle=phi_m)
mechanism.link("drum", J=J_d, angle=phi_d)
mechanism.link("load", m=m, y=r * phi_d)
mechanism.gravity(g)
mechanism.lossy_gear("worm gear", input=phi_m, output=phi_d, ratio=i, eta_forward=eta,
                     eta_backward=0)
mechanism.load("lift", M * sp.Heaviside(t_m - md.t), along=phi_m, tags=["lifting"])
mechanism.load("lower", -M_low, along=phi_m, tags=["lowering"])

params = {J_m: 0.01, J_d: 0.5, i: 40, eta: 0.4, r: 0.1, m: 200, g: 9.81, M: 15,
          t_m: 1, M_low: 0.2}

at_rest = {phi_m: 0, phi_d: 0, md.speed(phi_m): 0, md.speed(phi_d): 0}
outputs = ["worm gear", "worm gear.loss", "worm gear.mode", "power:worm gear"]
scenes = {
    "lift": md.Scene("lift", effects=["lifting", "gravity"], initial=at_rest, t_end=3,
                     outputs=outputs),
    "lower": md.Scene("lower", effects=["lowering", "gravity"], initial=at_rest,
                      t_end=1, outputs=outputs),
    "hold": md.Scene("hold", effects=["gravity"], initial=at_rest, t_end=1,
                     outputs=outputs),
}

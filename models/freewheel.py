"""Freewheel (an overrunning clutch, as in a bicycle hub): the pedal side J_h drives the
wheel J_w through a freewheel that lets the wheel run ahead but never behind.

Pedalling with a moment M_p for t_p seconds locks the freewheel: both turn together at
(M_p - M_r) / (J_h + J_w) against the wheel's rolling resistance M_r. Then the rider
stops pedalling and the legs brake the pedals (a friction M_b): the pedals stop within
J_h omega_p / M_b while the wheel overruns and coasts, decelerating at M_r / J_w, to a
stop at t_p + J_w omega_p / M_r.
"""
import sympy as sp

import mechdyn as md

phi_h, phi_w = md.coordinates("phi_h phi_w")
J_h, J_w, M_p, t_p, M_r, M_b = sp.symbols("J_h J_w M_p t_p M_r M_b", positive=True)

mechanism = md.Mechanism("Freewheel", coordinates=[phi_h, phi_w], units={
    J_h: "kg*m^2", J_w: "kg*m^2", M_p: "N*m", t_p: "s", M_r: "N*m", M_b: "N*m"})
mechanism.link("pedals", J=J_h, angle=phi_h)
mechanism.link("wheel", J=J_w, angle=phi_w)
mechanism.load("pedalling", M_p * sp.Heaviside(t_p - md.t), along=phi_h)
mechanism.friction("legs", M_b * sp.Heaviside(md.t - t_p), along=phi_h)
mechanism.friction("rolling resistance", M_r, along=phi_w)
mechanism.freewheel("freewheel", along=phi_w - phi_h)

params = {J_h: 0.05, J_w: 0.2, M_p: 30, t_p: 2, M_r: 2, M_b: 5}

scenes = {
    "ride": md.Scene("ride", initial={phi_h: 0, phi_w: 0, md.speed(phi_h): 0,
                                      md.speed(phi_w): 0},
                     t_end=10, outputs=["freewheel", "freewheel.slip", "freewheel.mode"]),
}

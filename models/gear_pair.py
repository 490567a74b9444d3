"""Gear pair (worked example 2): gear 1 drives gear 2 against a resisting moment.

Reduced to gear 1: I_red = J1 + J2 (z1/z2)^2, M_red = M1 - M2 z1/z2.
"""
import sympy as sp

import mechdyn as md

phi_1 = md.coordinate("phi_1")
z_1, z_2, J_1, J_2, M_1, M_2 = sp.symbols("z_1 z_2 J_1 J_2 M_1 M_2", positive=True)

# Gear 2's angle, counted in its own sense of rotation (it turns against gear 1).
phi_2 = z_1 / z_2 * phi_1

mechanism = md.Mechanism("Gear pair", coordinates=[phi_1],
                         units={z_1: "1", z_2: "1", J_1: "kg*m^2", J_2: "kg*m^2",
                                M_1: "N*m", M_2: "N*m"})
mechanism.link("gear 1", J=J_1, angle=phi_1)
mechanism.link("gear 2", J=J_2, angle=phi_2)
mechanism.load("drive", M_1, along=phi_1)
mechanism.load("resistance", -M_2, along=phi_2)

params = {z_1: 20, z_2: 50, J_1: 0.05, J_2: 0.4, M_1: 30, M_2: 40}

scenes = {
    "startup": md.Scene("startup", initial={phi_1: 0, md.speed(phi_1): 0}, t_end=2.0),
}

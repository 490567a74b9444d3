"""Planetary 2K-H train start-up (worked example 5).

Sun 1 drives; planets 2 and 3 share one shaft; the carrier H carries the load.
Willis: i_1H = 1 - (z2 z4)/(z1 z3) = -3, so omega_H/omega_1 = -1/3 and omega_2/omega_1 = -1.
I_red = 0.80 kg m^2; the least starting moment is 5 N m; 21.76 N m reaches 600 rpm in 3 s.
"""
import sympy as sp

import mechdyn as md

phi_1 = md.coordinate("phi_1")
z_1, z_2, z_3, z_4 = sp.symbols("z_1 z_2 z_3 z_4", positive=True)
J_1, J_2, J_3, J_H, M_1, M_H = sp.symbols("J_1 J_2 J_3 J_H M_1 M_H", positive=True)

i_1H = 1 - (z_2 * z_4) / (z_1 * z_3)                    # sun to carrier, carrier held
phi_H = phi_1 / i_1H                                    # carrier angle
phi_2 = phi_H - z_1 / z_2 * (phi_1 - phi_H)             # planet shaft (relative to carrier)
teeth = {z_1: 20, z_2: 40, z_3: 20, z_4: 40}            # the train's geometry

mechanism = md.Mechanism("Planetary 2K-H train", coordinates=[phi_1], units={
    z_1: "1", z_2: "1", z_3: "1", z_4: "1", J_1: "kg*m^2", J_2: "kg*m^2", J_3: "kg*m^2",
    J_H: "kg*m^2", M_1: "N*m", M_H: "N*m"})
mechanism.link("sun 1", J=J_1, angle=phi_1)
mechanism.link("planets 2+3", J=J_2 + J_3, angle=phi_2.subs(teeth))
mechanism.link("carrier H", J=J_H, angle=phi_H.subs(teeth))
mechanism.load("drive", M_1, along=phi_1)
# The carrier turns against the sun; its load moment resists that turning.
mechanism.load("carrier load", -M_H, along=-phi_H.subs(teeth))

params = {J_1: 0.18, J_2: 0.38, J_3: 0.22, J_H: 0.18, M_H: 15,
          M_1: 5 + 0.8 * (20 * 3.141592653589793 / 3)}  # the textbook's 21.76 N m

scenes = {
    "startup": md.Scene("startup", initial={phi_1: 0, md.speed(phi_1): 0}, t_end=3.0),
}

"""Three-mass elastic drive (a benchmark model file): DC shunt motor J_1 -> shaft k_1 ->
gear wheel J_2 -> shaft k_2 -> load J_3 against a constant load moment.

Absolute angles as coordinates (as a user of the obvious path would write them);
natural frequencies 176 and 608 rad/s (damping ratios 5 % and 9 %) plus the rigid mode.
Start-up from rest over 0.5 s.
"""
import sympy as sp

import mechdyn as md

phi_1, phi_2, phi_3 = md.coordinates("phi_1 phi_2 phi_3")
J_1, J_2, J_3, k_1, k_2, c_1, c_2, M_0, omega_0, M_L = sp.symbols(
    "J_1 J_2 J_3 k_1 k_2 c_1 c_2 M_0 omega_0 M_L", positive=True)

mechanism = md.Mechanism("Three-mass elastic drive", coordinates=[phi_1, phi_2, phi_3])
mechanism.link("rotor", J=J_1, angle=phi_1)
mechanism.link("gear", J=J_2, angle=phi_2)
mechanism.link("load", J=J_3, angle=phi_3)
mechanism.spring("shaft 1", k_1, stretch=phi_1 - phi_2)
mechanism.spring("shaft 2", k_2, stretch=phi_2 - phi_3)
mechanism.damper("shaft 1 damping", c_1, stretch=phi_1 - phi_2)
mechanism.damper("shaft 2 damping", c_2, stretch=phi_2 - phi_3)
mechanism.load("motor", md.motors.dc_shunt(M_0, omega_0)(md.speed(phi_1)), along=phi_1)
mechanism.load("load moment", -M_L, along=phi_3)

params = {J_1: 0.05, J_2: 0.02, J_3: 0.5, k_1: 2000.0, k_2: 5000.0, c_1: 1.0, c_2: 1.0,
          M_0: 40.0, omega_0: 150.0, M_L: 10.0}

scenes = {
    "start": md.Scene("start", initial={phi_1: 0, phi_2: 0, phi_3: 0, md.speed(phi_1): 0,
                                        md.speed(phi_2): 0, md.speed(phi_3): 0},
                      t_end=0.5, outputs=["shaft 2"]),
}

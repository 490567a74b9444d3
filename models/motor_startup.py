"""Induction motor start-up and braking of a flywheel drive.

The motor (Kloss characteristic) drives a flywheel against a constant load moment.
Scene `startup`: motor on, until 95 % of the steady speed. Scene `braking`: motor off,
shoe brake on, from the steady speed to rest. One mechanism, two scenes, different effects.
"""
import sympy as sp

import mechdyn as md

phi = md.coordinate("phi")
J_m, J_f, M_k, s_k, omega_s, M_L, M_b = sp.symbols(
    "J_m J_f M_k s_k omega_s M_L M_b", positive=True)

mechanism = md.Mechanism("Motor and flywheel", coordinates=[phi], units={
    J_m: "kg*m^2", J_f: "kg*m^2", M_k: "N*m", s_k: "1", omega_s: "rad/s", M_L: "N*m",
    M_b: "N*m"})
mechanism.link("rotor", J=J_m, angle=phi)
mechanism.link("flywheel", J=J_f, angle=phi)
mechanism.load("motor", md.motors.kloss(M_k, s_k, omega_s)(md.speed(phi)), along=phi)
mechanism.load("load", -M_L, along=phi, tags=["process"])
mechanism.friction("brake", M_b, along=phi)

# Steady speed: the stable root of kloss(omega) = M_L (small slip).
steady_slip = s_k * (M_k - sp.sqrt(M_k**2 - M_L**2)) / M_L
omega_steady = omega_s * (1 - steady_slip)

params = {J_m: 0.5, J_f: 4.5, M_k: 200, s_k: 0.2, omega_s: 157.08, M_L: 60, M_b: 150}

scenes = {
    "startup": md.Scene("startup", effects=["motor", "load"],
                        initial={phi: 0, md.speed(phi): 0},
                        until=md.reaches(md.speed(phi), 0.95 * omega_steady,
                                          label="95 % of steady speed"),
                        outputs=["motor", "power:motor"]),
    "braking": md.Scene("braking", effects=["brake", "load"],
                        initial={phi: 0, md.speed(phi): omega_steady},
                        until=md.stopped(phi), outputs=["brake"]),
}

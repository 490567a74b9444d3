"""Crank-rocker four-bar with a flywheel, driven by a DC shunt motor (a closed loop).

Ground pivots O = (0, 0) and D = (d, 0); crank OA (a), coupler AB (b), rocker DB (c):
a = 0.1 m, b = 0.35 m, c = 0.3 m, d = 0.4 m, so s + l = 0.5 < p + q = 0.65 and the
shortest link, the crank, turns fully (Grashof: crank-rocker). The crank angle phi is
the independent coordinate; the coupler and rocker angles theta_2, theta_3 are
dependent, fixed by the loop

    a e^(i phi) + b e^(i theta_2) - c e^(i theta_3) - d = 0       (loop ABCD)

The initial guesses theta_2 = 1.2, theta_3 = 1.9 at phi = 0 pick the open assembly
(B above the line OD). Coupler and rocker are uniform bars (centres at their middles,
J = m l^2 / 12); a flywheel is keyed on the crank. The rocker works against a moment
M_w while it swings forward (theta_3 growing) and runs free back; the motor
M_0 (1 - omega / omega_0) turns the crank; the linkage moves in a vertical plane.

Joints (for kinetostatics, ``mechdyn linkage``): O, A, B, D pins, the flywheel welded.

Scenes: ``startup`` (from rest, 4 s) and ``steady`` (started near the running speed,
8 s), both recording the motor moment and the loop's constraint forces.
"""
import sympy as sp

import mechdyn as md

phi, theta_2, theta_3 = md.coordinates("phi theta_2 theta_3")
a, b, c, d = sp.symbols("a b c d", positive=True)
J_1, J_f, m_2, m_3, M_0, omega_0, M_w = sp.symbols("J_1 J_f m_2 m_3 M_0 omega_0 M_w",
                                                   positive=True)

A = (a * sp.cos(phi), a * sp.sin(phi))
B = (d + c * sp.cos(theta_3), c * sp.sin(theta_3))

mechanism = md.Mechanism("Crank-rocker four-bar with flywheel", [phi, theta_2, theta_3],
                         independent=[phi],
                         units={a: "m", b: "m", c: "m", d: "m", J_1: "kg*m^2",
                                J_f: "kg*m^2", m_2: "kg", m_3: "kg", M_0: "N*m",
                                omega_0: "rad/s", M_w: "N*m"})
mechanism.link("crank", J=J_1, angle=phi)
mechanism.link("flywheel", J=J_f, angle=phi)
mechanism.link("coupler", m=m_2, J=m_2 * b**2 / 12, x=A[0] + b / 2 * sp.cos(theta_2),
               y=A[1] + b / 2 * sp.sin(theta_2), angle=theta_2)
mechanism.link("rocker", m=m_3, J=m_3 * c**2 / 12, x=d + c / 2 * sp.cos(theta_3),
               y=c / 2 * sp.sin(theta_3), angle=theta_3)
mechanism.loop("ABCD", (a, phi), (b, theta_2), (-c, theta_3), (-d, 0))
mechanism.joint("O", ("frame", "crank"), at=(0, 0))
mechanism.joint("key", ("crank", "flywheel"), at=(0, 0), kind="weld")
mechanism.joint("A", ("crank", "coupler"), at=A)
mechanism.joint("B", ("coupler", "rocker"), at=B)
mechanism.joint("D", ("frame", "rocker"), at=(d, 0))
mechanism.load("motor", md.motors.dc_shunt(M_0, omega_0)(md.speed(phi)), along=phi,
               on="crank")
work = sp.Piecewise((-M_w, md.speed(theta_3) > 0), (0, True))
mechanism.load("work", work, along=theta_3, tags=["process"])
mechanism.gravity()

coupler_mid = (A[0] + b / 2 * sp.cos(theta_2), A[1] + b / 2 * sp.sin(theta_2))
points = {"P": (coupler_mid[0] - 0.1 * sp.sin(theta_2),          # 0.1 m off the coupler
                coupler_mid[1] + 0.1 * sp.cos(theta_2))}          # (its coupler curve)

params = {a: 0.1, b: 0.35, c: 0.3, d: 0.4, J_1: 0.002, J_f: 0.25, m_2: 1.5, m_3: 1.2,
          M_0: 40.0, omega_0: 40.0, M_w: 15.0}

scenes = {
    "startup": md.Scene("startup", initial={phi: 0, md.speed(phi): 0, theta_2: 1.2,
                                            theta_3: 1.9},
                        t_end=4, outputs=["motor", "ABCD"]),
    "steady": md.Scene("steady", initial={phi: 0, md.speed(phi): 30, theta_2: 1.2,
                                          theta_3: 1.9},
                       t_end=8, outputs=["motor", "ABCD"]),
}

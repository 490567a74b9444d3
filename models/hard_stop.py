"""A lever driven against an end stop: a moment M swings a lever (inertia J) through
the free angle theta_0 to a stop that throws it back with a coefficient of restitution
e; it bounces ever lower until it rests on the stop, which then carries M.

First impact at t_1 = sqrt(2 J theta_0 / M) with speed omega_1 = M t_1 / J, impulse
(1 + e) J omega_1; the bounces (each e times the last) end at
t_1 + 2 e omega_1 J / ((1 - e) M), when all the work M theta_0 has become heat. With
e = 0 (``--param e=0``) the lever rests on the stop from the first impact.
"""
import sympy as sp

import mechdyn as md

theta = md.coordinate("theta")
J, M, theta_0, e = sp.symbols("J M theta_0 e", nonnegative=True)

mechanism = md.Mechanism("Lever against a stop", coordinates=[theta], units={
    J: "kg*m^2", M: "N*m", theta_0: "rad", e: "1"})
mechanism.link("lever", J=J, angle=theta)
mechanism.load("drive", M, along=theta)
mechanism.stop("end stop", along=theta, lower=-theta_0, upper=theta_0, restitution=e)

params = {J: 0.02, M: 4, theta_0: 0.5, e: 0.6}

scenes = {
    "bounce": md.Scene("bounce", initial={theta: 0, md.speed(theta): 0}, t_end=1,
                       outputs=["end stop", "end stop.mode"]),
}

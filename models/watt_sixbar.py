"""Watt II six-bar: two four-bar loops in series, the first one's rocker (a ternary link)
driving the second. Driven by a DC shunt motor with a flywheel on the crank.

Loop 1 (O2 = (0, 0), O4 = (d, 0)): crank a (phi), coupler b (theta_2), rocker c
(theta_3): a = 0.06, b = 0.28, c = 0.12, d = 0.3 m, a crank-rocker (s + l = 0.36 <
p + q = 0.40). The rocker carries a second arm c_2 = 0.16 m opposite its first
(angle theta_3 + pi); loop 2 closes it through the coupler e = 0.25 m (theta_4) to the
output rocker f = 0.12 m (theta_5) pivoted at O6 = (0.1, -0.25):

    a e^(i phi) + b e^(i theta_2) - c e^(i theta_3) - d = 0                (loop 1)
    d + c_2 e^(i (theta_3 + pi)) + e e^(i theta_4) - f e^(i theta_5) - O6 = 0  (loop 2)

Five coordinates, four constraints: one degree of freedom, the crank angle. The
output rocker works against M_out while it swings forward (theta_5 growing). The links
are uniform bars; the ternary rocker is two bars. Gravity is left out (a horizontal
machine).

Scenes: ``startup`` (from rest, 3 s) and ``steady`` (at the running speed, 3 s).
"""
import sympy as sp

import mechdyn as md

phi, theta_2, theta_3, theta_4, theta_5 = md.coordinates("phi theta_2 theta_3 theta_4 theta_5")
a, b, c, d, c_2, e, f, x_6, y_6 = sp.symbols("a b c d c_2 e f x_6 y_6", real=True)
J_1, rho, M_0, omega_0, M_out = sp.symbols("J_1 rho M_0 omega_0 M_out", positive=True)


def bar(name, start, length, angle):
    """A uniform bar of mass rho * length from ``start`` along ``angle``."""
    mass = rho * length
    return mechanism.link(name, m=mass, J=mass * length**2 / 12,
                          x=start[0] + length / 2 * sp.cos(angle),
                          y=start[1] + length / 2 * sp.sin(angle), angle=angle)


mechanism = md.Mechanism("Watt II six-bar", [phi, theta_2, theta_3, theta_4, theta_5],
                         independent=[phi],
                         units={**{s: "m" for s in (a, b, c, d, c_2, e, f, x_6, y_6)},
                                J_1: "kg*m^2", rho: "kg/m", M_0: "N*m", omega_0: "rad/s",
                                M_out: "N*m"})
A = (a * sp.cos(phi), a * sp.sin(phi))
E = (d + c_2 * sp.cos(theta_3 + sp.pi), c_2 * sp.sin(theta_3 + sp.pi))
mechanism.link("crank and flywheel", J=J_1, angle=phi)
bar("coupler", A, b, theta_2)
bar("rocker", (d, 0), c, theta_3)
bar("rocker arm", (d, 0), c_2, theta_3 + sp.pi)
bar("coupler 2", E, e, theta_4)
bar("output", (x_6, y_6), f, theta_5)
mechanism.loop("loop 1", (a, phi), (b, theta_2), (-c, theta_3), (-d, 0))
mechanism.loop("loop 2", (d, 0), (c_2, theta_3 + sp.pi), (e, theta_4), (-f, theta_5),
               (-x_6, 0), (-y_6, sp.pi / 2))
mechanism.joint("O2", ("frame", "crank and flywheel"), at=(0, 0))
mechanism.joint("A", ("crank and flywheel", "coupler"), at=A)
mechanism.joint("B", ("coupler", "rocker"), at=(d + c * sp.cos(theta_3), c * sp.sin(theta_3)))
mechanism.joint("O4", ("frame", "rocker"), at=(d, 0))
mechanism.joint("rocker weld", ("rocker", "rocker arm"), at=(d, 0), kind="weld")
mechanism.joint("E", ("rocker arm", "coupler 2"), at=E)
mechanism.joint("F", ("coupler 2", "output"),
                at=(x_6 + f * sp.cos(theta_5), y_6 + f * sp.sin(theta_5)))
mechanism.joint("O6", ("frame", "output"), at=(x_6, y_6))
mechanism.load("motor", md.motors.dc_shunt(M_0, omega_0)(md.speed(phi)), along=phi)
mechanism.load("work", sp.Piecewise((-M_out, md.speed(theta_5) > 0), (0, True)),
               along=theta_5, tags=["process"])

params = {a: 0.06, b: 0.28, c: 0.12, d: 0.3, c_2: 0.16, e: 0.25, f: 0.12, x_6: 0.1,
          y_6: -0.25, J_1: 0.05, rho: 3.0, M_0: 12.0, omega_0: 30.0, M_out: 6.0}

start = {phi: 0, theta_2: 0.44, theta_3: 1.46, theta_4: 3.11, theta_5: 2.17}
scenes = {
    "startup": md.Scene("startup", initial={**start, md.speed(phi): 0}, t_end=3,
                        outputs=["motor", "work"]),
    "steady": md.Scene("steady", initial={**start, md.speed(phi): 25}, t_end=3,
                       outputs=["motor", "work", "loop 2"]),
}

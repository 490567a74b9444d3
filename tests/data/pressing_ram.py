"""A user's crank press (issue 42): the ram's position x_ram measured down from the
crank's centre, r cos(phi) + sqrt(l^2 - r^2 sin^2 phi), reaches r + l at the bottom; a
workpiece of height h resists with F_p while the ram is within h of the bottom and
moves down: ``x_ram > r + l - h`` and ``x_ram' phidot > 0``, written in the ram's
position and its rate. A motor moment M drives the crank.
"""
import sympy as sp

import mechdyn as md

phi = md.coordinate("phi")
r, l, h, J_c, m_r, F_p, M = sp.symbols("r l h J_c m_r F_p M", positive=True)
x_ram = r * sp.cos(phi) + sp.sqrt(l**2 - r**2 * sp.sin(phi)**2)
moving_down = sp.diff(x_ram, md.t) > 0

mechanism = md.Mechanism("Pressing ram", [phi], units={
    r: "m", l: "m", h: "m", J_c: "kg*m^2", m_r: "kg", F_p: "N", M: "N*m"})
mechanism.link("crank", J=J_c, angle=phi)
mechanism.link("ram", m=m_r, x=x_ram)
mechanism.load("motor", M, along=phi)
mechanism.load("workpiece", sp.Piecewise((-F_p, sp.And(x_ram > r + l - h, moving_down)),
                                         (0, True)), along=x_ram)

params = {r: 0.05, l: 0.25, h: 0.01, J_c: 2.0, m_r: 150.0, F_p: 2000.0, M: 100.0}
scenes = {"stroke": md.Scene("stroke", initial={phi: 0, md.speed(phi): 10}, t_end=1.0)}

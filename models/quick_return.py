"""Crank-shaper quick-return mechanism (slotted lever): a ram cutting one way, returning
fast the other, driven through two closed loops.

The crank O2A (r = 0.1 m, angle phi) turns about O2, d = 0.3 m above the lever's pivot
O4; its pin A slides in the slot of the lever O4B (length R = 0.5 m, angle theta, A at
the distance s from O4). The link BC (l = 0.25 m, angle psi) drives the ram C along a
horizontal guide at the height h = 0.5 m (position x). Loops:

    s e^(i theta) - r e^(i phi) - d e^(i pi/2) = 0                   (slot)
    R e^(i theta) + l e^(i psi) - x - i h = 0                         (drive)

The lever swings between the crank positions where the crank is square to it
(sin = r / d): with the crank turning counterclockwise the ram's cutting stroke (x
falling) takes the crank angle pi + 2 asin(r/d) = 218.9 deg, the return
pi - 2 asin(r/d) = 141.1 deg: a time ratio of 1.55. The ram (m = 8 kg) cuts against
F_c while it moves back; an induction motor (Kloss) drives the crank through a gear of
ratio i with a flywheel on the motor shaft.

Scenes: ``startup`` (from rest, 3 s) and ``steady`` (started at the running speed, 4 s).
"""
import sympy as sp

import mechdyn as md

phi, theta, s, psi, x = md.coordinates("phi theta s psi x")
r, d, R, l, h = sp.symbols("r d R l h", positive=True)
J_c, m_l, m_b, m_r, J_m, i, F_c = sp.symbols("J_c m_l m_b m_r J_m i F_c", positive=True)
M_k, s_k, omega_s = sp.symbols("M_k s_k omega_s", positive=True)

mechanism = md.Mechanism("Crank-shaper quick-return", [phi, theta, s, psi, x],
                         units={s: "m", x: "m", r: "m", d: "m", R: "m", l: "m", h: "m",
                                J_c: "kg*m^2", m_l: "kg", m_b: "kg", m_r: "kg",
                                J_m: "kg*m^2", i: "1", F_c: "N", M_k: "N*m", s_k: "1",
                                omega_s: "rad/s"},
                         independent=[phi])
pin = (r * sp.cos(phi), d + r * sp.sin(phi))               # O4 at the origin
tip = (R * sp.cos(theta), R * sp.sin(theta))
mechanism.link("crank", J=J_c, angle=phi)
mechanism.link("motor and flywheel", J=J_m, angle=i * phi)
mechanism.link("lever", m=m_l, J=m_l * R**2 / 3 - m_l * (R / 2) ** 2,
               x=R / 2 * sp.cos(theta), y=R / 2 * sp.sin(theta), angle=theta)
mechanism.link("block", m=m_b, x=pin[0], y=pin[1], angle=theta)
mechanism.link("link", m=m_b, J=m_b * l**2 / 12, x=tip[0] + l / 2 * sp.cos(psi),
               y=tip[1] + l / 2 * sp.sin(psi), angle=psi)
mechanism.link("ram", m=m_r, x=x, y=h)
mechanism.loop("slot", (s, theta), (-r, phi), (-d, sp.pi / 2))
mechanism.loop("drive", (R, theta), (l, psi), (-x, 0), (-h, sp.pi / 2))
mechanism.joint("O2", ("frame", "crank"), at=(0, d))
mechanism.joint("A", ("crank", "block"), at=pin)
mechanism.joint("slide", ("lever", "block"), at=pin, kind="prismatic", direction=theta)
mechanism.joint("O4", ("frame", "lever"), at=(0, 0))
mechanism.joint("B", ("lever", "link"), at=tip)
mechanism.joint("C", ("link", "ram"), at=(x, h))
mechanism.joint("guide", ("frame", "ram"), at=(x, h), kind="prismatic", direction=0)
mechanism.joint("gear", ("crank", "motor and flywheel"), at=(0, d), kind="weld")
mechanism.load("motor", md.motors.kloss(M_k, s_k, omega_s)(i * md.speed(phi)),
               along=i * phi, on="motor and flywheel")
mechanism.load("cutting", sp.Piecewise((F_c, md.speed(x) < 0), (0, True)), along=x,
               tags=["process"])

params = {r: 0.1, d: 0.3, R: 0.5, l: 0.25, h: 0.5, J_c: 0.05, m_l: 6.0, m_b: 0.5,
          m_r: 8.0, J_m: 0.1, i: 15, F_c: 800.0, M_k: 40.0, s_k: 0.2, omega_s: 157.08}

start = {phi: 0, theta: 1.25, s: 0.32, psi: 0.2, x: 0.4}
scenes = {
    "startup": md.Scene("startup", initial={**start, md.speed(phi): 0}, t_end=3,
                        outputs=["motor", "cutting", "slot", "drive"]),
    "steady": md.Scene("steady", initial={**start, md.speed(phi): 9.8}, t_end=4,
                       outputs=["motor", "cutting"]),
}

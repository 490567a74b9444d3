"""Toggle (knuckle-joint) press: a crank pushes the knee of two toggle links, which
straighten as the ram reaches the bottom, so a small crank moment gives a large press
force there. Two closed loops; an induction motor with a flywheel drives the crank
through a gear.

Upper toggle link O4B (u = 0.3 m, angle theta_u) hangs from the frame at O4 = (0, 0);
the lower link BC (w = 0.3 m, angle theta_w) carries the ram C on a vertical guide,
C = (0, y). The crank O2A (a = 0.06 m, angle phi) turns about O2 = (0.465, -0.29); the
rod AB (l = 0.4 m, angle theta_r) pushes the knee B:

    a e^(i phi) + l e^(i theta_r) - u e^(i theta_u) + O2 = 0            (knee)
    u e^(i theta_u) + w e^(i theta_w) - i y = 0                          (toggle)

The knee swings between about 5 and 125 mm right of the guide: the ram's stroke is about
53 mm and it stops 0.1 mm short of the straight toggle (y = -0.6 m), where
dy/dphi -> 0 and the mechanical advantage grows without bound. Over the last
h_w = 5 mm the workpiece resists the descending ram with a force growing as
k_w (y_c - y) (plastic: nothing comes back on the way up). Gravity acts on the ram.

Scenes: ``startup`` (from rest, 3 s) and ``steady`` (started at the running speed, 4 s).
"""
import sympy as sp

import mechdyn as md

phi, theta_r, theta_u, theta_w, y = md.coordinates("phi theta_r theta_u theta_w y")
a, l, u, w, x_2, y_2, y_c = sp.symbols("a l u w x_2 y_2 y_c", real=True)
J_c, m_l, m_r, J_m, i, k_w = sp.symbols("J_c m_l m_r J_m i k_w", positive=True)
M_k, s_k, omega_s = sp.symbols("M_k s_k omega_s", positive=True)

mechanism = md.Mechanism("Toggle press", [phi, theta_r, theta_u, theta_w, y],
                         units={y: "m", **{s: "m" for s in (a, l, u, w, x_2, y_2, y_c)},
                                J_c: "kg*m^2", m_l: "kg/m", m_r: "kg", J_m: "kg*m^2",
                                i: "1", k_w: "N/m", M_k: "N*m", s_k: "1",
                                omega_s: "rad/s"},
                         independent=[phi])
A = (x_2 + a * sp.cos(phi), y_2 + a * sp.sin(phi))
B = (u * sp.cos(theta_u), u * sp.sin(theta_u))
mechanism.link("crank", J=J_c, angle=phi)
mechanism.link("motor and flywheel", J=J_m, angle=i * phi)
for name, start, length, angle in (("rod", A, l, theta_r), ("upper link", (0, 0), u, theta_u),
                                   ("lower link", B, w, theta_w)):
    mechanism.link(name, m=m_l * length, J=m_l * length**3 / 12, angle=angle,
                   x=start[0] + length / 2 * sp.cos(angle),
                   y=start[1] + length / 2 * sp.sin(angle))
mechanism.link("ram", m=m_r, y=y)
mechanism.loop("knee", (a, phi), (l, theta_r), (-u, theta_u), (x_2, 0), (y_2, sp.pi / 2))
mechanism.loop("toggle", (u, theta_u), (w, theta_w), (-y, sp.pi / 2))
mechanism.joint("O2", ("frame", "crank"), at=(x_2, y_2))
mechanism.joint("gear", ("crank", "motor and flywheel"), at=(x_2, y_2), kind="weld")
mechanism.joint("A", ("crank", "rod"), at=A)
mechanism.joint("B", ("rod", "upper link"), at=B)
mechanism.joint("B'", ("upper link", "lower link"), at=B)
mechanism.joint("O4", ("frame", "upper link"), at=(0, 0))
mechanism.joint("C", ("lower link", "ram"), at=(0, y))
mechanism.joint("guide", ("frame", "ram"), at=(0, y), kind="prismatic", direction=sp.pi / 2)
mechanism.load("motor", md.motors.kloss(M_k, s_k, omega_s)(i * md.speed(phi)),
               along=i * phi, on="motor and flywheel")
pressing = sp.And(y < y_c, md.speed(y) < 0)
mechanism.load("workpiece", sp.Piecewise((k_w * (y_c - y), pressing), (0, True)), along=y,
               tags=["process"])
mechanism.gravity()

params = {a: 0.06, l: 0.4, u: 0.3, w: 0.3, x_2: 0.465, y_2: -0.29, y_c: -0.595,
          J_c: 0.1, m_l: 10.0, m_r: 50.0, J_m: 0.05, i: 20, k_w: 2e6,
          M_k: 60.0, s_k: 0.2, omega_s: 157.08}

start = {phi: 0, theta_r: 3.1, theta_u: -1.4, theta_w: -1.75, y: -0.58}
scenes = {
    "startup": md.Scene("startup", initial={**start, md.speed(phi): 0}, t_end=3,
                        outputs=["motor", "workpiece"]),
    "steady": md.Scene("steady", initial={**start, md.speed(phi): 7.7}, t_end=4,
                       outputs=["motor", "workpiece", "toggle"]),
}

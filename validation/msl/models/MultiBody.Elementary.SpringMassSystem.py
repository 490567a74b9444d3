"""Modelica.Mechanics.MultiBody.Examples.Elementary.SpringMassSystem: two bodies hanging
on vertical prismatic joints, one held by a 1-d translational spring on the joint axis,
one by a 3-d spring; both move alike.

MSL components (Examples/Elementary/SpringMassSystem.mo) and their mechdyn counterparts:

- ``world``: gravity g = g_n = 9.80665 m/s^2 along -y.
- ``p1``/``p2`` (Prismatic, n = {0,-1,0}) at x = 0.3 (``bar1``) and x = 0.6 (``bar2``):
  slides ``s_1``, ``s_2`` downwards; ``body1``/``body2`` (m = 1, r_CM = 0) at
  ``y = -s_i`` (they do not turn).
- ``spring1`` (Translational.Spring, c = 30, s_rel0 = 0.1) between the joint's support
  and axis: ``s_rel = s_1``, stretch ``s_1 - 0.1``.
- ``spring2`` (Forces.Spring, c = 30, s_unstretched = 0.1) from bar2.frame_b to body2:
  length ``|s_2| = s_2`` (positive throughout), stretch ``s_2 - 0.1``.

Start: p1.s = p2.s = 0.1, p1.v = p2.v = 0. Reference signals: p<i>.s = s_i,
p<i>.v = s_i'.
"""
import sympy as sp

import mechdyn as md

s_1, s_2 = md.coordinates("s_1 s_2")
m, c, s_rel0, g = sp.symbols("m c s_rel0 g", positive=True)

mechanism = md.Mechanism("MSL MultiBody.Elementary.SpringMassSystem", coordinates=[s_1, s_2],
                         units={s_1: "m", s_2: "m"})
mechanism.link("body1", m=m, x=0.3, y=-s_1)
mechanism.link("body2", m=m, x=0.6, y=-s_2)
mechanism.gravity(g)
mechanism.spring("spring1", c, stretch=s_1 - s_rel0)
mechanism.spring("spring2", c, stretch=s_2 - s_rel0)

params = {m: 1, c: 30, s_rel0: 0.1, g: 9.80665}

scenes = {
    "reference": md.Scene("reference", t_end=5.0, initial={
        s_1: 0.1, md.speed(s_1): 0, s_2: 0.1, md.speed(s_2): 0}),
}

signals = {"p1.s": s_1, "p1.v": md.speed(s_1), "p2.s": s_2, "p2.v": md.speed(s_2)}

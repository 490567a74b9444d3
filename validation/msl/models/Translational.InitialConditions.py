"""Modelica.Mechanics.Translational.Examples.InitialConditions: two spring-mass chains,
one started at rest in equilibrium (positions given), one started from given spring
lengths, out of equilibrium.

MSL components (Examples/InitialConditions.mo) and their mechdyn counterparts (a Mass's
flanges sit at ``s -+ L/2``; a spring's ``s_rel = flange_b.s - flange_a.s``):

- Chain 1: ``fixed2`` (s0 = 1) - ``s2`` (c = 1e3, s_rel0 = 2) - ``m3`` (m = 1, L = 3,
  centre ``s_3``) - ``sd2`` (c = 111, d = 1, s_rel0 = 4) - ``m4`` (m = 1, L = 5, centre
  ``s_4``). s2.s_rel = (s_3 - 1.5) - 1; sd2.s_rel = (s_4 - 2.5) - (s_3 + 1.5).
- Chain 2: ``fixed1`` (s0 = -1) - ``s1`` (c = 1e3, s_rel0 = 1) - ``m1`` (m = 1, L = 1,
  ``s_1``) - ``sd1`` (c = 111, d = 1, s_rel0 = 1) - ``m2`` (m = 1, L = 2, ``s_2``).
  s1.s_rel = (s_1 - 0.5) + 1; sd1.s_rel = (s_2 - 1) - (s_1 + 0.5).
- Spring-dampers: a spring on ``s_rel - s_rel0`` and a damper on ``s_rel``.

Start: m3.s = 4.5, m4.s = 12.5, both at rest (chain 1 in equilibrium);
s1.s_rel = 0.5 (so s_1 = 0), m1.v = 0, sd1.s_rel = 1 (so s_2 = 2.5), sd1.v_rel = 0.
Reference signals: m1.s/v, m3.s/v, sd1.s_rel/v_rel, sd2.s_rel/v_rel as above.
"""
import sympy as sp

import mechdyn as md

s_1, s_2, s_3, s_4 = md.coordinates("s_1 s_2 s_3 s_4")
c_s, c_sd, d_sd = sp.symbols("c_s c_sd d_sd", positive=True)

s2_rel = (s_3 - 1.5) - 1
sd2_rel = (s_4 - 2.5) - (s_3 + 1.5)
s1_rel = (s_1 - 0.5) - (-1)
sd1_rel = (s_2 - 1) - (s_1 + 0.5)

mechanism = md.Mechanism("MSL Translational.InitialConditions",
                         coordinates=[s_1, s_2, s_3, s_4],
                         units={s_1: "m", s_2: "m", s_3: "m", s_4: "m"})
for name, s in (("m1", s_1), ("m2", s_2), ("m3", s_3), ("m4", s_4)):
    mechanism.link(name, m=1, x=s)
mechanism.spring("s2", c_s, stretch=s2_rel - 2)
mechanism.spring("sd2", c_sd, stretch=sd2_rel - 4)
mechanism.damper("sd2 damping", d_sd, stretch=sd2_rel)
mechanism.spring("s1", c_s, stretch=s1_rel - 1)
mechanism.spring("sd1", c_sd, stretch=sd1_rel - 1)
mechanism.damper("sd1 damping", d_sd, stretch=sd1_rel)

params = {c_s: 1e3, c_sd: 111, d_sd: 1}

scenes = {
    "reference": md.Scene("reference", t_end=5.0, initial={
        s_1: 0, md.speed(s_1): 0, s_2: 2.5, md.speed(s_2): 0,
        s_3: 4.5, md.speed(s_3): 0, s_4: 12.5, md.speed(s_4): 0}),
}

signals = {
    "m1.s": s_1, "m1.v": md.speed(s_1), "m3.s": s_3, "m3.v": md.speed(s_3),
    "sd1.s_rel": sd1_rel, "sd1.v_rel": md.speed(s_2) - md.speed(s_1),
    "sd2.s_rel": sd2_rel, "sd2.v_rel": md.speed(s_4) - md.speed(s_3),
}

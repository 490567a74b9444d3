"""Modelica.Mechanics.Translational.Examples.ElastoGap: a mass between two spring-dampers
and an identical mass between two elasto-gaps (contacts that lift off), both released
2 m from the middle.

MSL components (Examples/ElastoGap.mo, Components/ElastoGap.mo) and their mechdyn
counterparts. ``fixed`` is at 0, ``rod1`` (L = 2) puts its flange_a at -2, ``rod2``
(L = 2) its flange_b at +2; the masses have L = 0, m = 1.

- ``mass1`` at ``s_1`` between ``springDamper1`` (c = 10, d = 1.5, s_rel0 = 1, from -2:
  s_rel = s_1 + 2) and ``springDamper2`` (the same, to +2: s_rel = 2 - s_1).
- ``mass2`` at ``s_2`` between ``elastoGap1`` (c = 10, d = 1.5, s_rel0 = 1.5, n = 1, from
  -2: s_rel = s_2 + 2) and ``elastoGap2`` (the same, to +2: s_rel = 2 - s_2).
  ElastoGap force at flange_b, in contact (``s_rel < s_rel0``):
  ``f_c = -c |s_rel - s_rel0|``, ``f_d2 = d v_rel`` clamped to ``[f_c, -f_c]``,
  ``f = f_c + f_d``; out of contact ``f = 0``. It pushes flange_b with ``-f`` along
  ``s_rel``: mechdyn's ``elasto_gap(name, s_rel, c, d, opening=s_rel0)``.

Start: s_1 = s_2 = 2, at rest. Reference signals: elastoGap1.v_rel = s_2',
elastoGap2.s_rel = 2 - s_2, springDamper1.v_rel = s_1', springDamper2.s_rel = 2 - s_1.
"""
import sympy as sp

import mechdyn as md

s_1, s_2 = md.coordinates("s_1 s_2")
m, c, d, s_rel0_sd, s_rel0_gap, rod = sp.symbols("m c d s_rel0_sd s_rel0_gap rod",
                                                 positive=True)


gap1, gap2 = s_2 + rod, rod - s_2

mechanism = md.Mechanism("MSL Translational.ElastoGap", coordinates=[s_1, s_2],
                         units={s_1: "m", s_2: "m"})
mechanism.link("mass1", m=m, x=s_1)
mechanism.link("mass2", m=m, x=s_2)
for name, s_rel in (("springDamper1", s_1 + rod), ("springDamper2", rod - s_1)):
    mechanism.spring(name, c, stretch=s_rel - s_rel0_sd)
    mechanism.damper(f"{name} damping", d, stretch=s_rel)
mechanism.elasto_gap("elastoGap1", gap1, c, d, opening=s_rel0_gap)
mechanism.elasto_gap("elastoGap2", gap2, c, d, opening=s_rel0_gap)

params = {m: 1, c: 10, d: 1.5, s_rel0_sd: 1, s_rel0_gap: 1.5, rod: 2}

scenes = {
    "reference": md.Scene("reference", t_end=5.0, initial={
        s_1: 2, md.speed(s_1): 0, s_2: 2, md.speed(s_2): 0}),
}

signals = {"elastoGap1.v_rel": md.speed(s_2), "elastoGap2.s_rel": 2 - s_2,
           "springDamper1.v_rel": md.speed(s_1), "springDamper2.s_rel": 2 - s_1}

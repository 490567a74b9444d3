"""Modelica.Mechanics.Translational.Examples.PreLoad: a hydraulic valve spool held in
place by one preloaded spring between two spring plates, with stiff elasto-gap contacts,
pushed by a slow sine force.

MSL components (Examples/PreLoad.mo, Components/ElastoGap.mo) and their mechdyn
counterparts. Positions: ``fixedLe`` at s0 = -0.0955; ``housing`` (rod, L = 0.0305) puts
the right housing wall at -0.065. Masses (flanges at centre -+ L/2):

- ``springPlateA`` (m = 10e-3, L = 0.002), centre ``s_A``; ``springPlateB`` (the same),
  centre ``s_B``; ``spool`` (m = 0.150, L = 0.19), centre ``s_S``.
- ``spring`` (c = 20e3, s_rel0 = 0.025) from plate A's flange_b to plate B's flange_a:
  ``s_rel = (s_B - 0.001) - (s_A + 0.001)``.
- ``outerContactA`` (ElastoGap c = 1e6, d = 250, s_rel0 = 0.0015) from fixedLe to plate
  A's flange_a: ``s_rel = (s_A - 0.001) + 0.0955``.
- ``outerContactB`` (the same) from plate B's flange_b to the housing wall:
  ``s_rel = -0.065 - (s_B + 0.001)``.
- ``innerContactA`` (ElastoGap c = 1e6, d = 250, s_rel0 = 0.001) from ``rod3.flange_a``
  to ``rod1.flange_b``. rod3 (L = 0.00575) ends at the spool's flange_a
  (``s_S - 0.095``), so its flange_a is at ``s_S - 0.10075``; rod1 (L = 0.007) starts at
  plate A's flange_b: ``s_rel = (s_A + 0.008) - (s_S - 0.10075)``.
- ``innerContactB`` (the same) from ``rod2.flange_a`` (rod2, L = 0.007, ends at plate B's
  flange_a: ``s_B - 0.008``) to ``rod4.flange_b`` (rod4, L = 0.00575, starts at the
  spool's flange_a: ``s_S - 0.08925``): ``s_rel = (s_S - 0.08925) - (s_B - 0.008)``.
- ElastoGap force at flange_b, in contact (``s_rel < s_rel0``):
  ``f_c = -c |s_rel - s_rel0|``, ``f_d2 = d v_rel`` clamped to ``[f_c, -f_c]``,
  ``f = f_c + f_d``, else 0; pushing ``-f`` along ``s_rel``: ``elasto_gap(...)``.
- ``friction`` (a Damper, d = 2500) from fixedLe to rod3.flange_a: damps ``s_S``.
- ``sineForce`` (amplitude 150, f = 0.01 Hz) -> ``force`` on the spool: along ``s_S``.

Start: s_S = 0.01475, s_A = -0.093, s_B = -0.06925, all at rest. Reference signals:
friction.v_rel = s_S', innerContactA.s_rel, innerContactB.s_rel, outerContactA.v_rel =
s_A', outerContactB.s_rel, outerContactB.v_rel = -s_B' (as above).
"""
import sympy as sp

import mechdyn as md

slow = True          # 100 s of stiff contacts (1e4 rad/s): tens of seconds

s_A, s_B, s_S = md.coordinates("s_A s_B s_S")
m_plate, m_spool, c_spring, c_gap, d_gap, d_friction, amplitude, f = sp.symbols(
    "m_plate m_spool c_spring c_gap d_gap d_friction amplitude f", positive=True)


gaps = {
    "outerContactA": ((s_A - 0.001) + 0.0955, 0.0015),
    "outerContactB": (-0.065 - (s_B + 0.001), 0.0015),
    "innerContactA": ((s_A + 0.008) - (s_S - 0.10075), 0.001),
    "innerContactB": ((s_S - 0.08925) - (s_B - 0.008), 0.001),
}

mechanism = md.Mechanism("MSL Translational.PreLoad", coordinates=[s_A, s_B, s_S],
                         units={s_A: "m", s_B: "m", s_S: "m"})
mechanism.link("springPlateA", m=m_plate, x=s_A)
mechanism.link("springPlateB", m=m_plate, x=s_B)
mechanism.link("spool", m=m_spool, x=s_S)
mechanism.spring("spring", c_spring, stretch=(s_B - 0.001) - (s_A + 0.001) - 0.025)
for name, (s_rel, s_rel0) in gaps.items():
    mechanism.elasto_gap(name, s_rel, c_gap, d_gap, opening=s_rel0)
mechanism.damper("friction", d_friction, stretch=s_S)
mechanism.load("force", amplitude * sp.sin(2 * sp.pi * f * md.t), along=s_S)

params = {m_plate: 10e-3, m_spool: 0.150, c_spring: 20e3, c_gap: 1000e3, d_gap: 250,
          d_friction: 2500, amplitude: 150, f: 0.01}

scenes = {
    "reference": md.Scene("reference", t_end=100.0, initial={
        s_A: -0.093, md.speed(s_A): 0, s_B: -0.06925, md.speed(s_B): 0,
        s_S: 0.01475, md.speed(s_S): 0}),
}

signals = {
    "friction.v_rel": md.speed(s_S),
    "innerContactA.s_rel": gaps["innerContactA"][0],
    "innerContactB.s_rel": gaps["innerContactB"][0],
    "outerContactA.v_rel": md.speed(s_A),
    "outerContactB.s_rel": gaps["outerContactB"][0],
    "outerContactB.v_rel": -md.speed(s_B),
}

"""Modelica.Mechanics.Translational.Examples.WhyArrows: the same spring-mass system drawn
twice, once with the mass flipped; both move alike (the rods and position sensors of the
upper half measure only).

MSL components (Examples/WhyArrows.mo) and their mechdyn counterparts:

- ``mass1`` and ``inertia2`` (both Translational Mass, m = 1, L = 2), centres ``s_1`` and
  ``s_2``; each spring acts on the mass's flange_b at ``s_i + L/2``.
- ``spring1``/``spring2`` (c = 11, s_rel0 = 2) from ``fixed1``/``fixed2`` (s0 = -1.9) to
  the flange_b: ``s_rel = s_i + 1 + 1.9``, stretch ``s_rel - 2 = s_i + 0.9``.

Start: s = 0, v = 0 for both (the spring is stretched by 0.9 m). Reference signals:
inertia2.s/v = s_2/s_2', mass1.s/v = s_1/s_1'.
"""
import sympy as sp

import mechdyn as md

s_1, s_2 = md.coordinates("s_1 s_2")
m, c, s0, half, s_rel0 = sp.symbols("m c s0 L_half s_rel0")

mechanism = md.Mechanism("MSL Translational.WhyArrows", coordinates=[s_1, s_2],
                         units={s_1: "m", s_2: "m"})
mechanism.link("mass1", m=m, x=s_1)
mechanism.link("inertia2", m=m, x=s_2)
mechanism.spring("spring1", c, stretch=(s_1 + half) - s0 - s_rel0)
mechanism.spring("spring2", c, stretch=(s_2 + half) - s0 - s_rel0)

params = {m: 1, c: 11, s0: -1.9, half: 1, s_rel0: 2}

scenes = {
    "reference": md.Scene("reference", t_end=1.0, initial={
        s_1: 0, md.speed(s_1): 0, s_2: 0, md.speed(s_2): 0}),
}

signals = {"inertia2.s": s_2, "inertia2.v": md.speed(s_2),
           "mass1.s": s_1, "mass1.v": md.speed(s_1)}

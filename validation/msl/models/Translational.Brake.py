"""Modelica.Mechanics.Translational.Examples.Brake: two sliding masses braked to rest by a
brake that engages at 0.1 s, one brake grounded implicitly, one through ``fixed``.

MSL components (Examples/Brake.mo, Components/Brake.mo, Interfaces/PartialFriction.mo)
and their mechdyn counterparts:

- ``mass1``/``mass2`` (m = 1, L = 0), positions ``s_1``/``s_2``.
- ``step`` (Blocks.Sources.Step, height 2, startTime 0.1) -> ``f_normalized`` of both
  brakes.
- ``brake``/``brake1`` (Translational.Components.Brake, fn_max = 1, mu_pos = [0, 0.5]
  (constant), peak = 1, cgeo = 1): normal force ``fn = fn_max f_normalized``, sliding
  force ``cgeo mu fn``, static limit ``peak cgeo mu(0) fn`` (equal here), free while
  ``fn <= 0``. mechdyn: Coulomb friction of magnitude ``0`` for ``t < 0.1`` and
  ``cgeo mu fn_max 2 = 1 N`` after, along ``s_i``.

Start: s = 0, v = 1 for both. Expected: 1 m/s^2 deceleration from 0.1 s, rest at 1.1 s
at s = 0.6 m, held there. Reference signals: mass<i>.s = s_i, mass<i>.v = s_i'.
"""
import sympy as sp

import mechdyn as md

s_1, s_2 = md.coordinates("s_1 s_2")
m, mu, cgeo, fn_max, height, start = sp.symbols("m mu cgeo fn_max height startTime",
                                                positive=True)

f_normalized = sp.Piecewise((0, md.t < start), (height, True))

mechanism = md.Mechanism("MSL Translational.Brake", coordinates=[s_1, s_2],
                         units={s_1: "m", s_2: "m"})
mechanism.link("mass1", m=m, x=s_1)
mechanism.link("mass2", m=m, x=s_2)
mechanism.friction("brake", cgeo * mu * fn_max * f_normalized, along=s_1)
mechanism.friction("brake1", cgeo * mu * fn_max * f_normalized, along=s_2)

params = {m: 1, mu: 0.5, cgeo: 1, fn_max: 1, height: 2, start: 0.1}

scenes = {
    "reference": md.Scene("reference", t_end=2.0, initial={
        s_1: 0, md.speed(s_1): 1, s_2: 0, md.speed(s_2): 1}),
}

signals = {"mass1.s": s_1, "mass1.v": md.speed(s_1), "mass2.s": s_2, "mass2.v": md.speed(s_2)}

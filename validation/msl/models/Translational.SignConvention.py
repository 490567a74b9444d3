"""Modelica.Mechanics.Translational.Examples.SignConvention: a constant force of 1 N on
three masses, pushing at flange_a, pulling at flange_b, and a force source turned around
(its support fixed) at flange_b: all three accelerate forwards at 1 m/s^2.

MSL components (Examples/SignConvention.mo) and their mechdyn counterparts:

- ``mass1``/``mass2``/``mass3`` (m = 1, L = 1), centres ``s_1, s_2, s_3``.
- ``constant1..3`` (k = 1) -> ``force1..3``: the load 1 along each ``s_i`` (the source
  accelerates the flange it is connected to in the positive direction, whichever flange
  and whichever way the icon points).

Start: all at s = 0, v = 0. Reference signals: mass<i>.s = s_i, mass<i>.v = s_i'.
"""
import sympy as sp

import mechdyn as md

s_1, s_2, s_3 = md.coordinates("s_1 s_2 s_3")
m, F = sp.symbols("m F", positive=True)

mechanism = md.Mechanism("MSL Translational.SignConvention", coordinates=[s_1, s_2, s_3],
                         units={s_1: "m", s_2: "m", s_3: "m"})
for i, s in enumerate((s_1, s_2, s_3), start=1):
    mechanism.link(f"mass{i}", m=m, x=s)
    mechanism.load(f"force{i}", F, along=s)

params = {m: 1, F: 1}

scenes = {
    "reference": md.Scene("reference", t_end=1.0, initial={
        s_1: 0, md.speed(s_1): 0, s_2: 0, md.speed(s_2): 0, s_3: 0, md.speed(s_3): 0}),
}

signals = {f"mass{i}.{kind}": (s if kind == "s" else md.speed(s))
           for i, s in enumerate((s_1, s_2, s_3), start=1) for kind in ("s", "v")}

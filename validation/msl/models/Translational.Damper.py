"""Modelica.Mechanics.Translational.Examples.Damper: three masses thrown at a wall, held
by a damper, a damper parallel to a spring, and a spring-damper.

MSL components (Examples/Damper.mo) and their mechdyn counterparts (masses m = 1, L = 1,
centres ``s_1, s_2, s_3``; each ``fixed`` at s0 = 4.5; each element runs from the mass's
flange_b at ``s_i + 0.5`` to the wall, so ``s_rel = 4.5 - (s_i + 0.5) = 4 - s_i``):

- ``damper1`` (d = 25): damps ``s_1``; s_rel = 4 - s_1, v_rel = -s_1'.
- ``damper2`` (d = 25) parallel to ``spring2`` (c = 1, s_rel0 = 1): damps ``s_2``, spring
  stretch ``s_rel - s_rel0 = 3 - s_2``.
- ``springDamper3`` (c = 1, d = 25, s_rel0 = 1): the same on ``s_3``.

Start: every mass at s = 3 with v = 10. Reference signals: damper1.s_rel = 4 - s_1,
damper1.v_rel = -s_1', damper2.s_rel = 4 - s_2, damper2.v_rel = -s_2',
springDamper3.s_rel = 4 - s_3, springDamper3.v_rel = -s_3'.
"""
import sympy as sp

import mechdyn as md

s_1, s_2, s_3 = md.coordinates("s_1 s_2 s_3")
m, d, c, wall, half, s_rel0 = sp.symbols("m d c s0 L_half s_rel0", positive=True)


def s_rel(s):
    """From the mass's flange_b (s + L/2) to the wall."""
    return wall - (s + half)


mechanism = md.Mechanism("MSL Translational.Damper", coordinates=[s_1, s_2, s_3],
                         units={s_1: "m", s_2: "m", s_3: "m"})
for s, i in ((s_1, 1), (s_2, 2), (s_3, 3)):
    mechanism.link(f"mass{i}", m=m, x=s)
mechanism.damper("damper1", d, stretch=s_rel(s_1))
mechanism.damper("damper2", d, stretch=s_rel(s_2))
mechanism.spring("spring2", c, stretch=s_rel(s_2) - s_rel0)
mechanism.damper("springDamper3 damping", d, stretch=s_rel(s_3))
mechanism.spring("springDamper3", c, stretch=s_rel(s_3) - s_rel0)

params = {m: 1, d: 25, c: 1, wall: 4.5, half: 0.5, s_rel0: 1}

scenes = {
    "reference": md.Scene("reference", t_end=1.0, initial={
        s_1: 3, md.speed(s_1): 10, s_2: 3, md.speed(s_2): 10, s_3: 3, md.speed(s_3): 10}),
}

signals = {
    "damper1.s_rel": 4.5 - (s_1 + 0.5), "damper1.v_rel": -md.speed(s_1),
    "damper2.s_rel": 4.5 - (s_2 + 0.5), "damper2.v_rel": -md.speed(s_2),
    "springDamper3.s_rel": 4.5 - (s_3 + 0.5), "springDamper3.v_rel": -md.speed(s_3),
}

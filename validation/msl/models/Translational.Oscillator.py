"""Modelica.Mechanics.Translational.Examples.Oscillator: two spring-mass oscillators
driven at their resonance, one undamped, one with a damper parallel to its spring.

MSL components (Examples/Oscillator.mo) and their mechdyn counterparts (masses m = 1,
L = 1, centres ``s_1, s_2``; each spring from the mass's flange_b at ``s_i + 0.5`` to a
``fixed`` at s0 = 1, so ``s_rel = 1 - (s_i + 0.5) = 0.5 - s_i``):

- ``sine1``/``sine2`` (Blocks.Sources.Sine, amplitude 1, f = 15.9155 Hz exactly as
  written, not 100/(2 pi)) -> ``force1``/``force2`` on the masses: ``sin(2 pi f t)``
  along ``s_i``.
- ``spring1``/``spring2`` (c = 1e4, s_rel0 = 1): stretch ``s_rel - 1 = -0.5 - s_i``.
- ``damper1`` (d = 10) parallel to spring2: damps ``s_2``; its s_rel = 0.5 - s_2.

Start: both masses at s = -0.5, v = 0 (springs relaxed). Reference signals:
damper1.s_rel = 0.5 - s_2, damper1.v_rel = -s_2', mass1.s = s_1, mass1.v = s_1'.
"""
import sympy as sp

import mechdyn as md

s_1, s_2 = md.coordinates("s_1 s_2")
m, c, d, f, amplitude, wall, half, s_rel0 = sp.symbols(
    "m c d f amplitude s0 L_half s_rel0", positive=True)

force = amplitude * sp.sin(2 * sp.pi * f * md.t)

mechanism = md.Mechanism("MSL Translational.Oscillator", coordinates=[s_1, s_2],
                         units={s_1: "m", s_2: "m"})
mechanism.link("mass1", m=m, x=s_1)
mechanism.link("mass2", m=m, x=s_2)
mechanism.load("force1", force, along=s_1)
mechanism.load("force2", force, along=s_2)
mechanism.spring("spring1", c, stretch=wall - (s_1 + half) - s_rel0)
mechanism.spring("spring2", c, stretch=wall - (s_2 + half) - s_rel0)
mechanism.damper("damper1", d, stretch=s_2)

params = {m: 1, c: 1e4, d: 10, f: 15.9155, amplitude: 1, wall: 1, half: 0.5, s_rel0: 1}

scenes = {
    "reference": md.Scene("reference", t_end=1.0, initial={
        s_1: -0.5, md.speed(s_1): 0, s_2: -0.5, md.speed(s_2): 0}),
}

signals = {
    "damper1.s_rel": 1 - (s_2 + 0.5), "damper1.v_rel": -md.speed(s_2),
    "mass1.s": s_1, "mass1.v": md.speed(s_1),
}

"""Modelica.Mechanics.Translational.Examples.Sensors: a sine force accelerates a mass
through ideal force, speed, position and acceleration sensors.

MSL components (Examples/Sensors.mo) and their mechdyn counterparts:

- ``sineForce`` (Blocks.Sources.Sine, amplitude 10, f = 4 Hz) -> ``force`` on the mass
  (through ``forceSensor`` and ``multiSensor``, which are rigid): the load
  ``10 sin(2 pi 4 t)`` along ``s`` (Sources.Force accelerates its flange).
- ``mass`` (m = 1, L = 1), centre ``s``; the sensors do not load it.

Start: mass.s = 0, mass.v = 0. Reference signals: mass.s = s, mass.v = s'.
"""
import sympy as sp

import mechdyn as md

s = md.coordinate("s")
m, amplitude, f = sp.symbols("m amplitude f", positive=True)

mechanism = md.Mechanism("MSL Translational.Sensors", coordinates=[s], units={s: "m"})
mechanism.link("mass", m=m, x=s)
mechanism.load("force", amplitude * sp.sin(2 * sp.pi * f * md.t), along=s)

params = {m: 1, amplitude: 10, f: 4}

scenes = {"reference": md.Scene("reference", t_end=1.0, initial={s: 0, md.speed(s): 0})}

signals = {"mass.s": s, "mass.v": md.speed(s)}

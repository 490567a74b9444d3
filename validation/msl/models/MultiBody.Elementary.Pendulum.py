"""Modelica.Mechanics.MultiBody.Examples.Elementary.Pendulum: a point-like body on a
revolute joint about z, falling from the horizontal, with a damper on the joint axis.

MSL components (Examples/Elementary/Pendulum.mo) and their mechdyn counterparts:

- ``world``: uniform gravity g = Modelica.Constants.g_n = 9.80665 m/s^2 along -y.
- ``rev`` (Revolute, n = {0,0,1}, useAxisFlange): angle ``phi`` about z.
- ``damper`` (Rotational.Damper, d = 0.1) between the joint's support and axis: damps
  ``phi``.
- ``body`` (Parts.Body, m = 1, r_CM = {0.5,0,0}, I_33 = 0.001 by default): centre of mass
  at ``(0.5 cos phi, 0.5 sin phi)``, turning by ``phi``.

Start: rev.phi = 0, rev.w = 0 (horizontal, at rest). Reference signals: rev.phi = phi,
rev.w = phi'.
"""
import sympy as sp

import mechdyn as md

phi = md.coordinate("phi")
m, r_cm, I_33, d, g = sp.symbols("m r_CM I_33 d g", positive=True)

mechanism = md.Mechanism("MSL MultiBody.Elementary.Pendulum", coordinates=[phi])
mechanism.link("body", m=m, J=I_33, x=r_cm * sp.cos(phi), y=r_cm * sp.sin(phi), angle=phi)
mechanism.gravity(g)
mechanism.damper("damper", d, stretch=phi)

params = {m: 1.0, r_cm: 0.5, I_33: 0.001, d: 0.1, g: 9.80665}

scenes = {"reference": md.Scene("reference", t_end=5.0, initial={phi: 0, md.speed(phi): 0})}

signals = {"rev.phi": phi, "rev.w": md.speed(phi)}

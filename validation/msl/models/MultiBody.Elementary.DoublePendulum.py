"""Modelica.Mechanics.MultiBody.Examples.Elementary.DoublePendulum: two steel boxes on
revolute joints about z, released from the horizontal, a damper on the first joint.

MSL components (Examples/Elementary/DoublePendulum.mo, Parts/BodyBox.mo) and their mechdyn
counterparts:

- ``world``: gravity g = g_n = 9.80665 m/s^2 along -y.
- ``revolute1`` (n = {0,0,1} by default, useAxisFlange) with ``damper`` (d = 0.1):
  absolute angle ``phi_1``, damped.
- ``boxBody1``/``boxBody2`` (BodyBox, r = {0.5,0,0}, width = height = 0.06,
  density 7700 kg/m^3 by default): m = 7700 * 0.5 * 0.06 * 0.06 = 13.86 kg, centre of
  mass at r/2, inertia about z (the box's height direction, widthDirection = {0,1,0})
  ``m (length^2 + width^2) / 12``.
- ``revolute2`` (n = {0,0,1}) at the end of box 1: relative angle ``phi_2``; box 2 turns
  by ``phi_1 + phi_2``.

Start: revolute1.phi = revolute1.w = revolute2.phi = revolute2.w = 0. Reference signals:
revolute1.phi/w = phi_1/phi_1', revolute2.phi/w = phi_2/phi_2'.
"""
import sympy as sp

import mechdyn as md

phi_1, phi_2 = md.coordinates("phi_1 phi_2")
length, width, density, d, g = sp.symbols("length width density d g", positive=True)

m_box = density * length * width * width
J_box = m_box * (length**2 + width**2) / 12
theta_2 = phi_1 + phi_2

mechanism = md.Mechanism("MSL MultiBody.Elementary.DoublePendulum", coordinates=[phi_1, phi_2])
mechanism.link("boxBody1", m=m_box, J=J_box, angle=phi_1,
               x=length / 2 * sp.cos(phi_1), y=length / 2 * sp.sin(phi_1))
mechanism.link("boxBody2", m=m_box, J=J_box, angle=theta_2,
               x=length * sp.cos(phi_1) + length / 2 * sp.cos(theta_2),
               y=length * sp.sin(phi_1) + length / 2 * sp.sin(theta_2))
mechanism.gravity(g)
mechanism.damper("damper", d, stretch=phi_1)

params = {length: 0.5, width: 0.06, density: 7700, d: 0.1, g: 9.80665}

scenes = {
    "reference": md.Scene("reference", t_end=3.0, initial={
        phi_1: 0, md.speed(phi_1): 0, phi_2: 0, md.speed(phi_2): 0}),
}

signals = {"revolute1.phi": phi_1, "revolute1.w": md.speed(phi_1),
           "revolute2.phi": phi_2, "revolute2.w": md.speed(phi_2)}

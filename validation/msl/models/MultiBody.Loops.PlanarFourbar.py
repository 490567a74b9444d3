"""The Modelica Standard Library's ``MultiBody.Examples.Loops.PlanarFourbar`` as a mechdyn
loop, the loop declaration (``mech.loop``) closing it, not a hand-solved closed form.

MSL model (``Modelica/Mechanics/MultiBody/Examples/Loops/PlanarFourbar.mo``): four
``BodyBox`` bodies of steel (density 7700 kg/m^3), square section 0.05 m
(``width = 0.5 world.defaultJointLength``, ``defaultJointLength = nominalLength / 10``,
``height = width``): body1 ``r = {0.4, 0, 0}`` on revolute1 at the origin (the crank,
angle phi_1 = revolute1.phi, damped by a rotational damper d = 0.1 N m s/rad between its
support and axis); body2 ``r = {0.1, 1.1, 0}`` on revolute2 at body1's end (absolute
angle theta_2 = phi_1 + revolute2.phi); body3 ``r = {-0.15, 1, 0}`` fixed to the world,
carrying revolute3 (absolute angle theta_4 of body4); body4
``r = body1.r + body2.r - body3.r = {0.65, 0.1, 0}``; the loop is closed by
``RevolutePlanarLoopConstraint`` between body4's and body2's ends. A box's centre of
mass is at ``r / 2``, its mass ``7700 L w h`` and its moment of inertia about the axis
normal to the plane ``m (L^2 + w^2) / 12``. Gravity g_n = 9.80665 m/s^2 along -y.
Start: revolute1.phi = 0, revolute1.w = 0 (fixed), where all joint angles are 0.
"""
import math

import sympy as sp

import mechdyn as md

phi_1, theta_2, theta_4 = md.coordinates("phi_1 theta_2 theta_4")
DENSITY, SIDE, G_N = 7700.0, 0.05, 9.80665


def box(x, y):
    """Length, direction angle, mass and central moment of inertia of a BodyBox r = (x, y)."""
    length = math.hypot(x, y)
    mass = DENSITY * length * SIDE * SIDE
    return length, math.atan2(y, x), mass, mass * (length ** 2 + SIDE ** 2) / 12


L1, _, m1, J1 = box(0.4, 0.0)
L2, alpha_2, m2, J2 = box(0.1, 1.1)
L4, alpha_4, m4, J4 = box(0.65, 0.1)
crank_pin = (L1 * sp.cos(phi_1), L1 * sp.sin(phi_1))

mechanism = md.Mechanism("MSL PlanarFourbar", [phi_1, theta_2, theta_4])
mechanism.link("body1", m=m1, J=J1, x=L1 / 2 * sp.cos(phi_1), y=L1 / 2 * sp.sin(phi_1),
               angle=phi_1)
mechanism.link("body2", m=m2, J=J2, x=crank_pin[0] + L2 / 2 * sp.cos(theta_2 + alpha_2),
               y=crank_pin[1] + L2 / 2 * sp.sin(theta_2 + alpha_2), angle=theta_2)
mechanism.link("body4", m=m4, J=J4, x=-0.15 + L4 / 2 * sp.cos(theta_4 + alpha_4),
               y=1.0 + L4 / 2 * sp.sin(theta_4 + alpha_4), angle=theta_4)
mechanism.loop("revolute4cut", (L1, phi_1), (L2, theta_2 + alpha_2),
               (-L4, theta_4 + alpha_4), (0.15, 0), (-1.0, sp.pi / 2))
mechanism.damper("damper", 0.1, stretch=phi_1)
mechanism.gravity(G_N)

params = {}
scenes = {"reference": md.Scene("reference", initial={phi_1: 0, md.speed(phi_1): 0,
                                                      theta_2: 0, theta_4: 0}, t_end=5)}
signals = {"revolute1.phi": phi_1, "revolute1.w": md.speed(phi_1)}

"""Modelica.Mechanics.MultiBody.Examples.Loops.Engine1b: Engine1a with a rough gas force
in the cylinder (Loops/Utilities/GasForce2.mo), run for 0.5 s. MSL restructures the loop
for the JointRRP assembly; the bodies and their geometry are Engine1a's, so here the
slider-crank kinematics are again written in closed form in the crank angle.

The gas force: ``gasForce`` (GasForce2, L = 0.35, d = 0.1) between the cylinder joint's
support and axis, ``s_rel = s`` (the slide, 0.05 at top dead centre), ``x = 1 - s/L``,
``v_rel = s'``; pressure ``press = 1e5 p(x)`` with the polynomial p chosen by the sign of
v_rel (compression for v_rel < 0) and by x, exactly as written in GasForce2; force on the
piston along +s (away from the head) ``press pi d^2/4``.

MSL components (Loops/Engine1b.mo, Loops/Utilities/Engine1bBase.mo, Engine1Base.mo;
Parts/BodyBox.mo and
Parts/BodyCylinder.mo for the mass data, density 7700 kg/m^3 by default) and their mechdyn
counterparts. All joints turn about x (n = {1,0,0}), so the motion lies in the y-z plane;
mechdyn's (x, y) are MSL's (z, y). Gravity g = g_n = 9.80665 m/s^2 along -y.

- ``bearing`` (Revolute about x, at the origin) with ``inertia`` (J = 1, phi = 0,
  w = 10 at the start) on its axis: crank angle ``phi``. A point (0, r, 0) of the crank
  is at ``(z, y) = (r sin phi, r cos phi)``.
- Crank bodies, turning with ``phi`` (inertia about x, centre-of-mass radius):
  ``crank1`` cylinder r = {0.1,0,0}, d = 0.05: on the axis, ``m r^2/2``;
  ``crank2`` box r = {0,0.1,0}, width 0.02 (along x), height 0.05: ``m (L^2+h^2)/12``
  at radius 0.05; ``crank3`` cylinder r = {0.1,0,0}, d = 0.03 (the pin): ``m r^2/2`` at
  radius 0.1; ``crank4`` box r = {0,-0.1,0} as crank2, at radius 0.05.
- ``mid`` puts the rod's crank pin at radius 0.1: ``(0.1 sin phi, 0.1 cos phi)``.
- ``cylPosition`` {0.15,0.45,0} and ``cylinder`` (Prismatic, n = {0,-1,0}, slide ``s``)
  with ``piston`` (cylinder r = {0,-0.1,0}, d = 0.1) put the wrist pin at
  ``y_w = 0.35 - s``; the rod (length 0.2) gives
  ``y_w = 0.1 cos phi + sqrt(0.2^2 - 0.1^2 sin^2 phi)``. The piston's centre of mass is
  at ``y_w + 0.05``; it only translates.
- ``connectingRod`` (box r = {0,-0.2,0}, width 0.02 along x, height 0.06): centre of mass
  midway between wrist and crank pin, inertia about x ``m (L^2+h^2)/12``, turning by
  ``asin(0.1 sin phi / 0.2)``.

Reference signals: inertia.phi = phi, inertia.w = phi'.
"""
import sympy as sp

import mechdyn as md

phi = md.coordinate("phi")
rho, g, J_inertia, L, d = sp.symbols("rho g J_inertia L d", positive=True)

crank, rod_length = sp.Rational(1, 10), sp.Rational(2, 10)


def box(length, width, height):
    """Mass and inertia about the width axis (x here) of a BodyBox."""
    m = rho * length * width * height
    return m, m * (length**2 + height**2) / 12


def cylinder(length, diameter):
    """Mass and inertia about its own axis of a BodyCylinder."""
    m = rho * sp.pi * length * (diameter / 2)**2
    return m, m * (diameter / 2)**2 / 2


m_c1, J_c1 = cylinder(0.1, 0.05)
m_c2, J_c2 = box(0.1, 0.02, 0.05)
m_c3, J_c3 = cylinder(0.1, 0.03)
m_c4, J_c4 = box(0.1, 0.02, 0.05)
m_piston, _ = cylinder(0.1, 0.1)
m_rod, J_rod = box(0.2, 0.02, 0.06)

pin = (crank * sp.sin(phi), crank * sp.cos(phi))
wrist_y = crank * sp.cos(phi) + sp.sqrt(rod_length**2 - crank**2 * sp.sin(phi)**2)


def on_crank(radius):
    return {"x": radius * sp.sin(phi), "y": radius * sp.cos(phi), "angle": phi}


mechanism = md.Mechanism("MSL MultiBody.Loops.Engine1b", coordinates=[phi])
mechanism.link("inertia", J=J_inertia, angle=phi)
mechanism.link("crank1", m=m_c1, J=J_c1, angle=phi)
mechanism.link("crank2", m=m_c2, J=J_c2, **on_crank(0.05))
mechanism.link("crank3", m=m_c3, J=J_c3, **on_crank(0.1))
mechanism.link("crank4", m=m_c4, J=J_c4, **on_crank(0.05))
mechanism.link("connectingRod", m=m_rod, J=J_rod, x=pin[0] / 2, y=(pin[1] + wrist_y) / 2,
               angle=sp.asin(crank * sp.sin(phi) / rod_length))
mechanism.link("piston", m=m_piston, y=wrist_y + 0.05)
mechanism.gravity(g)

s = 0.35 - wrist_y                                   # cylinder slide = gasForce.s_rel
x = 1 - s / L
v_rel = sp.diff(s, phi) * md.speed(phi)
press = 1e5 * sp.Piecewise(
    (sp.Piecewise((177.4132*x**4 - 287.2189*x**3 + 151.8252*x**2 - 24.9973*x + 2.4,
                   x < 0.986061),
                  (2836360*x**4 - 10569296*x**3 + 14761814*x**2 - 9158505*x + 2129670,
                   True)), v_rel < 0),
    (sp.Piecewise((-3929704*x**4 + 14748765*x**3 - 20747000*x**2 + 12964477*x - 3036495,
                   x > 0.933),
                  (145.930*x**4 - 131.707*x**3 + 17.3438*x**2 + 17.9272*x + 2.4, True)),
     True))
mechanism.load("gasForce", press * sp.pi * d**2 / 4, along=s)

params = {rho: 7700, g: 9.80665, J_inertia: 1, L: 0.35, d: 0.1}

scenes = {"reference": md.Scene("reference", t_end=0.5, initial={phi: 0, md.speed(phi): 10})}

signals = {"inertia.phi": phi, "inertia.w": md.speed(phi)}

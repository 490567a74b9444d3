"""Modelica.Mechanics.Rotational.Examples.ElasticBearing: a ramp torque drives a shaft
through an ideal gear whose housing is an inertia held to the ground by a stiff
spring-damper; the gear output drives a load inertia through a spring.

MSL components (Examples/ElasticBearing.mo) and their mechdyn counterparts:

- ``ramp`` (Blocks.Sources.Ramp, height 100, duration 5, startTime 0) -> ``torque``
  (support fixed) on ``shaft``: the load ``100 min(t/5, 1)`` along ``phi_s``.
- ``shaft`` (J = 1), angle ``phi_s``.
- ``idealGear`` (ratio 3, useSupport, support = ``housing``):
  ``phi_s - phi_h = 3 (phi_out - phi_h)``, so the massless gear output turns by
  ``phi_out = phi_h + (phi_s - phi_h)/3``. Lagrange's equations with this kinematics carry
  the gear's reaction on the housing.
- ``housing`` (J = 5), angle ``phi_h``; ``multiSensor`` is rigid and measures only.
- ``springDamper`` (c = 1e5, d = 5) from ``fixed`` (flange_a) to the housing (flange_b):
  ``phi_rel = phi_h``.
- ``spring`` (c = 1e3) from the gear output to ``load``: stretch ``phi_L - phi_out``.
- ``load`` (J = 50), angle ``phi_L``.

Start: shaft.phi = shaft.w = 0, spring.phi_rel = 0, load.w = 0,
springDamper.phi_rel = springDamper.w_rel = 0: every angle and speed zero.
Reference signals: load.phi/w = phi_L/phi_L', shaft.phi/w = phi_s/phi_s',
springDamper.phi_rel/w_rel = phi_h/phi_h'.
"""
import sympy as sp

import mechdyn as md

phi_s, phi_h, phi_L = md.coordinates("phi_s phi_h phi_L")
J_s, J_h, J_L, ratio, c_b, d_b, c, height, duration = sp.symbols(
    "J_s J_h J_L ratio c_b d_b c height duration", positive=True)

gear_output = phi_h + (phi_s - phi_h) / ratio

mechanism = md.Mechanism("MSL Rotational.ElasticBearing", coordinates=[phi_s, phi_h, phi_L])
mechanism.link("shaft", J=J_s, angle=phi_s)
mechanism.link("housing", J=J_h, angle=phi_h)
mechanism.link("load", J=J_L, angle=phi_L)
mechanism.load("torque", height * sp.Min(md.t / duration, 1), along=phi_s)
mechanism.spring("springDamper", c_b, stretch=phi_h)
mechanism.damper("springDamper damping", d_b, stretch=phi_h)
mechanism.spring("spring", c, stretch=phi_L - gear_output)

params = {J_s: 1, J_h: 5, J_L: 50, ratio: 3, c_b: 1e5, d_b: 5, c: 1e3, height: 100,
          duration: 5}

scenes = {
    "reference": md.Scene("reference", t_end=10.0, initial={
        phi_s: 0, md.speed(phi_s): 0, phi_h: 0, md.speed(phi_h): 0,
        phi_L: 0, md.speed(phi_L): 0}),
}

signals = {
    "load.phi": phi_L, "load.w": md.speed(phi_L),
    "shaft.phi": phi_s, "shaft.w": md.speed(phi_s),
    "springDamper.phi_rel": phi_h, "springDamper.w_rel": md.speed(phi_h),
}

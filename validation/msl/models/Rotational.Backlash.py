"""Modelica.Mechanics.Rotational.Examples.Backlash: an inertia on a spring-damper and an
identical inertia on an elastic backlash (ElastoBacklash), both released from 90 degrees.

MSL components (Examples/Backlash.mo, Components/ElastoBacklash.mo) and their mechdyn
counterparts:

- ``inertia1`` (J = 5), angle ``phi_1``, on ``springDamper`` (c = 20e3, d = 50) from
  ``fixed1``: spring and damper on ``phi_rel = phi_1``.
- ``inertia2`` (J = 5), angle ``phi_2``, on ``elastoBacklash`` (c = 20e3, d = 50,
  b = 0.7853981633974483 (45 deg), phi_rel0 = 0) from ``fixed2``: ``phi_rel = phi_2``,
  ``w_rel = phi_2'``, ``bMax = b/2``, ``bMin = -b/2``. After initialisation
  (ElastoBacklash's ``initial()`` branch only shapes the initial equation system) the
  torque at flange_b is, with ``tau_c = c (phi_rel - bMax)`` above bMax,
  ``c (phi_rel - bMin)`` below bMin, 0 between, and ``tau_d = d w_rel``:
  above bMax ``tau = 0 if tau_c + tau_d <= 0 else tau_c + min(tau_c, tau_d)``; below bMin
  ``tau = 0 if tau_c + tau_d >= 0 else tau_c + max(tau_c, tau_d)``; 0 in the gap (the
  damping is clamped so the contact never pulls). The inertia feels ``-tau``: mechdyn's
  ``backlash(..., c=, d=, gap=)`` (a load ``-tau`` along the stretch ``phi_2``).
- ``inertia3`` on ``elastoBacklash2`` has no reference signal and is not modelled.

Start: phi_1 = phi_2 = 1.570796326794897, at rest. Reference signals:
elastoBacklash.phi_rel/w_rel = phi_2/phi_2', springDamper.phi_rel/w_rel = phi_1/phi_1'.
"""
import sympy as sp

import mechdyn as md

phi_1, phi_2 = md.coordinates("phi_1 phi_2")
J, c, d, b = sp.symbols("J c d b", positive=True)

mechanism = md.Mechanism("MSL Rotational.Backlash", coordinates=[phi_1, phi_2])
mechanism.link("inertia1", J=J, angle=phi_1)
mechanism.link("inertia2", J=J, angle=phi_2)
mechanism.spring("springDamper", c, stretch=phi_1)
mechanism.damper("springDamper damping", d, stretch=phi_1)
mechanism.backlash("elastoBacklash", phi_2, c=c, d=d, gap=b)

params = {J: 5, c: 20e3, d: 50, b: 0.7853981633974483}

scenes = {
    "reference": md.Scene("reference", t_end=1.0, initial={
        phi_1: 1.570796326794897, md.speed(phi_1): 0,
        phi_2: 1.570796326794897, md.speed(phi_2): 0}),
}

signals = {"elastoBacklash.phi_rel": phi_2, "elastoBacklash.w_rel": md.speed(phi_2),
           "springDamper.phi_rel": phi_1, "springDamper.w_rel": md.speed(phi_1)}

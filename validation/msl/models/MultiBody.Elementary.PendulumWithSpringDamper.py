"""Modelica.Mechanics.MultiBody.Examples.Elementary.PendulumWithSpringDamper: a body on a
revolute joint followed by a prismatic joint, pulled back to the pivot by a 3-d spring and
damper.

MSL components (Examples/Elementary/PendulumWithSpringDamper.mo) and their mechdyn
counterparts:

- ``world``: gravity g = g_n = 9.80665 m/s^2 along -y.
- ``bar1`` (FixedTranslation r = {0.3,0,0}): the pivot at (0.3, 0).
- ``revolute`` (n = {0,0,1}): angle ``phi``; ``prismatic`` (n = {1,0,0} in the turned
  frame): slide ``s``; ``body1`` (m = 1, I_11 = I_22 = I_33 = 1, r_CM = 0) at
  ``(0.3 + s cos phi, s sin phi)``, turning by ``phi``.
- ``spring1`` (Forces.Spring, c = 20, s_unstretched = 0.2, massless) and ``damper1``
  (Forces.Damper, d = 1) from bar1.frame_b (the pivot) to the body: their length is
  ``|s| = s`` (s stays positive), so the spring stretch is ``s - 0.2`` and the damper
  damps ``s``.

Start: revolute.phi = revolute.w = 0, prismatic.s = 0.5, prismatic.v = 0. Reference
signals: prismatic.s/v = s/s', revolute.phi/w = phi/phi'.
"""
import sympy as sp

import mechdyn as md

phi, s = md.coordinates("phi s")
m, I_33, bar, c, s_unstretched, d, g = sp.symbols(
    "m I_33 bar c s_unstretched d g", positive=True)

mechanism = md.Mechanism("MSL MultiBody.Elementary.PendulumWithSpringDamper",
                         coordinates=[phi, s], units={s: "m"})
mechanism.link("body1", m=m, J=I_33, angle=phi, x=bar + s * sp.cos(phi), y=s * sp.sin(phi))
mechanism.gravity(g)
mechanism.spring("spring1", c, stretch=s - s_unstretched)
mechanism.damper("damper1", d, stretch=s)

params = {m: 1, I_33: 1, bar: 0.3, c: 20, s_unstretched: 0.2, d: 1, g: 9.80665}

scenes = {
    "reference": md.Scene("reference", t_end=10.0, initial={
        phi: 0, md.speed(phi): 0, s: 0.5, md.speed(s): 0}),
}

signals = {"prismatic.s": s, "prismatic.v": md.speed(s),
           "revolute.phi": phi, "revolute.w": md.speed(phi)}

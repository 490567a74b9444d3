"""Modelica.Mechanics.Translational.Examples.Friction: Stribeck friction three ways: a mass
with stops and friction driven by a sine force, the same mass with a tabulated support
friction, and a mass with stops and friction thrown against a hard stop by a spring.

MSL components (Examples/Friction.mo, Components/MassWithStopAndFriction.mo,
Components/SupportFriction.mo, Examples/Utilities/GenerateStribeckFrictionTable.mo) and
their mechdyn counterparts:

- ``sineForce`` (amplitude 25, f = 0.25 Hz) -> ``force`` on stop1 and ``force2`` on mass.
- ``stop1`` (MassWithStopAndFriction m = 1, L = 1, smin = -25, smax = 25, F_prop = 1,
  F_Coulomb = 5, F_Stribeck = 10, fexp = 2; s = v = 0 at the start), centre ``s_1``:
  sliding force ``F_prop v + sign(v) (F_Coulomb + F_Stribeck exp(-fexp |v|))``, static
  limit ``f0_max = 1.001 (F_Coulomb + F_Stribeck)`` (peak 1.001), hard stops where
  ``s_1 -+ L/2`` reach smin/smax (never reached here).
- ``mass`` (m = 1, L = 1), centre ``s_m``, with ``supportFriction`` (peak = 1) whose
  ``f_pos`` is GenerateStribeckFrictionTable(F_prop = 1, F_Coulomb = 5, F_Stribeck = 10,
  fexp = 2, v_max = 12, nTable = 50): 50 points ``v_i = 12 (i-1)/49``,
  ``f_i = 5 + v_i + 10 exp(-2 v_i)``, interpolated linearly in |v| (extrapolation through
  the last two points); static limit ``f_pos(0) = 15``.
- ``stop2`` (MassWithStopAndFriction m = 1, L = 1, smin = -0.9, smax = 0.9, F_prop = 1,
  F_Coulomb = 3, F_Stribeck = 5, fexp = 2; s = 0, v = -5 at the start), centre ``s_2``,
  on ``spring`` (c = 500, s_rel0 = 1) from ``fixed2`` (s0 = -1.75) to its flange_a:
  ``s_rel = (s_2 - 0.5) + 1.75``, stretch ``s_2 + 0.25``. Hard stops at
  ``s_2 = smin + L/2 = -0.4`` and ``smax - L/2 = 0.4``: on reaching one, MSL reinits
  ``s`` to the limit and ``v`` to 0 (a perfectly plastic impact), and the friction state
  machine lets the mass leave the stop only away from it.

Declared with ``friction(..., peak=1.001)``, ``stop(...)`` and ``bearing_friction`` with
an ``md.table`` (validation/msl/NEEDS.md). The ``mass`` subsystem alone
(parts/Translational.Friction.mass.py) pins issue 14 defect 3: stuck at rest, the sine
force exceeds the holding capacity between two step ends.

Reference signals: mass.s/v, stop1.s/v, stop2.s/v (the centres and their speeds).
"""
import math

import sympy as sp

import mechdyn as md


s_1, s_m, s_2 = md.coordinates("s_1 s_m s_2")
t = md.t
force = 25 * sp.sin(2 * sp.pi * 0.25 * t)


def stribeck(v, F_prop, F_Coulomb, F_Stribeck, fexp):
    """Magnitude of MassWithStopAndFriction's sliding force at speed v (either sign)."""
    return F_prop * sp.Abs(v) + F_Coulomb + F_Stribeck * sp.exp(-fexp * sp.Abs(v))


f_pos = md.table([12 * i / 49 for i in range(50)],
                 [5 + 12 * i / 49 + 10 * math.exp(-2 * 12 * i / 49) for i in range(50)])
v_m = md.speed(s_m)

mechanism = md.Mechanism("MSL Translational.Friction", coordinates=[s_1, s_m, s_2],
                         units={s_1: "m", s_m: "m", s_2: "m"})
mechanism.link("stop1", m=1, x=s_1)
mechanism.load("force", force, along=s_1)
mechanism.friction("stop1 friction", stribeck(md.speed(s_1), 1, 5, 10, 2), along=s_1,
                   peak=1.001)
mechanism.stop("stop1 stops", along=s_1, lower=-25 + 0.5, upper=25 - 0.5)
mechanism.link("mass", m=1, x=s_m)
mechanism.load("force2", force, along=s_m)
mechanism.bearing_friction("supportFriction", f_pos, along=s_m)
mechanism.link("stop2", m=1, x=s_2)
mechanism.spring("spring", 500, stretch=(s_2 - 0.5) + 1.75 - 1)
mechanism.friction("stop2 friction", stribeck(md.speed(s_2), 1, 3, 5, 2), along=s_2,
                   peak=1.001)
mechanism.stop("stop2 stops", along=s_2, lower=-0.9 + 0.5, upper=0.9 - 0.5)

params = {}

scenes = {
    "reference": md.Scene("reference", t_end=5.0, initial={
        s_1: 0, md.speed(s_1): 0, s_m: 0, v_m: 0, s_2: 0, md.speed(s_2): -5}),
}

signals = {"mass.s": s_m, "mass.v": v_m, "stop1.s": s_1, "stop1.v": md.speed(s_1),
           "stop2.s": s_2, "stop2.v": md.speed(s_2)}

"""The ``mass`` subsystem of Modelica.Mechanics.Translational.Examples.Friction alone: a
mass with tabulated Stribeck support friction, driven by a sine force. Expressible today
(plain Coulomb friction whose magnitude depends on the speed); compared with the
reference's mass.s and mass.v only (the whole example also needs a static peak and a hard
stop, see ../Translational.Friction.py).

MSL components (Examples/Friction.mo, Components/SupportFriction.mo,
Examples/Utilities/GenerateStribeckFrictionTable.mo) and their mechdyn counterparts:

- ``sineForce`` (amplitude 25, f = 0.25 Hz) -> ``force2`` on the mass: along ``s``.
- ``mass`` (m = 1, L = 1), centre ``s``, s = v = 0 at the start.
- ``supportFriction`` (peak = 1, support fixed), ``f_pos`` =
  GenerateStribeckFrictionTable(F_prop = 1, F_Coulomb = 5, F_Stribeck = 10, fexp = 2,
  v_max = 12, nTable = 50): rows ``v_i = 12 (i-1)/49``, ``f_i = 5 + v_i + 10 exp(-2 v_i)``,
  interpolated linearly in |v| (extrapolated through the last two rows). Coulomb friction
  of that magnitude along ``s``; the static limit is ``f_pos(0) = 15 N`` (peak 1).

Expected: stuck until the force first exceeds 15 N at t = (2/pi) asin(0.6) = 0.4097 s.
Today the release is missed (issue 14 defect 3): while stuck the solver's steps grow and
the margin is tested only at step ends.

Reference signals: mass.s = s, mass.v = s'.
"""
import math

import sympy as sp

import mechdyn as md

s = md.coordinate("s")
v = md.speed(s)

f_pos = [(12 * i / 49, 5 + 12 * i / 49 + 10 * math.exp(-2 * 12 * i / 49)) for i in range(50)]


def table(points, x):
    """Linear interpolation in ``points`` (x ascending), extrapolated through the last two."""
    pieces = []
    for (x0, y0), (x1, y1) in zip(points[:-1], points[1:]):
        pieces.append((y0 + (y1 - y0) / (x1 - x0) * (x - x0), x < x1))
    pieces[-1] = (pieces[-1][0], True)
    return sp.Piecewise(*pieces)


mechanism = md.Mechanism("MSL Translational.Friction, mass subsystem", coordinates=[s],
                         units={s: "m"})
mechanism.link("mass", m=1, x=s)
mechanism.load("force2", 25 * sp.sin(2 * sp.pi * 0.25 * md.t), along=s)
mechanism.friction("supportFriction",
                   sp.Piecewise((table(f_pos, v), v >= 0), (table(f_pos, -v), True)), along=s)

params = {}

scenes = {"reference": md.Scene("reference", t_end=5.0, initial={s: 0, v: 0})}

signals = {"mass.s": s, "mass.v": v}

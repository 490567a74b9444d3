"""Modelica.Mechanics.Rotational.Examples.OneWayClutch: a driving and a driven inertia
coupled by a one-way clutch (freewheel in parallel with a clutch) engaged periodically.

MSL components (Examples/OneWayClutch.mo, Components/OneWayClutch.mo) and their mechdyn
counterparts:

- ``inertiaIn`` (J = 1, phi = 0, w = -0.5), angle ``phi_in``, driven by ``torque`` =
  ``signalTorque`` (Sine amplitude 10, f = 3 Hz).
- ``inertiaOut`` (J = 1, phi = 0, w = 0), angle ``phi_out``.
- ``oneWayClutch`` (peak = 25, fn_max = 3, mu_pos = [0, 0.5], cgeo = 1) from inertiaIn
  (flange_a) to inertiaOut (flange_b): ``phi_rel = phi_out - phi_in``, ``w_rel >= 0``
  always. Sliding (w_rel > 0): torque ``mu cgeo fn`` (0 while disengaged); at w_rel = 0 it
  locks, holding any torque in the blocking direction, and releases forward when the
  holding torque exceeds ``peak mu cgeo fn`` (``1e-4 mu cgeo fn_max`` while disengaged).
- ``signalEngagement`` (Pulse amplitude 1, width 50 %, period 1.3, startTime 0.3) ->
  ``f_normalized``: engaged on [0.3, 0.95) and [1.6, 2.25).

The clutch: ``one_way_clutch(name, moment, along, peak=, release=)``
(validation/msl/NEEDS.md).

Reference signals: inertiaIn.phi/w, oneWayClutch.phi_rel/w_rel = phi_out - phi_in and its
rate.
"""
import sympy as sp

import mechdyn as md


phi_in, phi_out = md.coordinates("phi_in phi_out")
t = md.t
mu, cgeo, fn_max = 0.5, 1, 3
engaged = sp.Piecewise((0, t < 0.3), (1, t < 0.95), (0, t < 1.6), (1, t < 2.25), (0, True))

mechanism = md.Mechanism("MSL Rotational.OneWayClutch", coordinates=[phi_in, phi_out])
mechanism.link("inertiaIn", J=1, angle=phi_in)
mechanism.link("inertiaOut", J=1, angle=phi_out)
mechanism.load("torque", 10 * sp.sin(2 * sp.pi * 3 * t), along=phi_in)
mechanism.one_way_clutch("oneWayClutch", mu * cgeo * fn_max * engaged, along=phi_out - phi_in,
                         peak=25, release=1e-4 * mu * cgeo * fn_max)

params = {}

scenes = {
    "reference": md.Scene("reference", t_end=2.0, initial={
        phi_in: 0, md.speed(phi_in): -0.5, phi_out: 0, md.speed(phi_out): 0}),
}

signals = {"inertiaIn.phi": phi_in, "inertiaIn.w": md.speed(phi_in),
           "oneWayClutch.phi_rel": phi_out - phi_in,
           "oneWayClutch.w_rel": md.speed(phi_out) - md.speed(phi_in)}

"""Modelica.Mechanics.Rotational.Examples.OneWayClutchDisengaged: the one-way clutch of
Examples.OneWayClutch never engaged: only its freewheel acts, against a constant load.

MSL components (Examples/OneWayClutchDisengaged.mo, Components/OneWayClutch.mo) and their
mechdyn counterparts:

- ``inertiaIn`` (J = 1, phi = 0, w = -0.5), angle ``phi_in``, driven by ``torque`` =
  ``signalTorque`` (Sine amplitude 10, f = 2 Hz, offset 0.3 = -torqueLoad.tau_constant).
- ``inertiaOut`` (J = 1, phi = 0, w = 0), angle ``phi_out``, loaded by ``torqueLoad``
  (ConstantTorque -0.3): ``-0.3`` along ``phi_out``.
- ``oneWayClutch`` (peak = 25, fn_max = 3, mu_pos = [0, 0.5], cgeo = 1), f_normalized = 0
  (``signalEngagement`` Constant k = 0): free, so no sliding torque; at w_rel = 0 the
  freewheel locks and releases forward only when the holding torque exceeds
  ``tau0_max_low = 1e-4 mu cgeo fn_max = 1.5e-4 N m``.

The clutch: ``one_way_clutch`` with no moment (validation/msl/NEEDS.md).

Reference signals: inertiaIn.phi/w, oneWayClutch.phi_rel/w_rel = phi_out - phi_in and its
rate.
"""
import sympy as sp

import mechdyn as md


phi_in, phi_out = md.coordinates("phi_in phi_out")
t = md.t
mu, cgeo, fn_max = 0.5, 1, 3

mechanism = md.Mechanism("MSL Rotational.OneWayClutchDisengaged", coordinates=[phi_in, phi_out])
mechanism.link("inertiaIn", J=1, angle=phi_in)
mechanism.link("inertiaOut", J=1, angle=phi_out)
mechanism.load("torque", 0.3 + 10 * sp.sin(2 * sp.pi * 2 * t), along=phi_in)
mechanism.load("torqueLoad", -0.3, along=phi_out)
mechanism.one_way_clutch("oneWayClutch", 0, along=phi_out - phi_in, peak=25,
                         release=1e-4 * mu * cgeo * fn_max)

params = {}

scenes = {
    "reference": md.Scene("reference", t_end=2.0, initial={
        phi_in: 0, md.speed(phi_in): -0.5, phi_out: 0, md.speed(phi_out): 0}),
}

signals = {"inertiaIn.phi": phi_in, "inertiaIn.w": md.speed(phi_in),
           "oneWayClutch.phi_rel": phi_out - phi_in,
           "oneWayClutch.w_rel": md.speed(phi_out) - md.speed(phi_in)}

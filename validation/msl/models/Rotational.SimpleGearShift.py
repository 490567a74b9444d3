"""Modelica.Mechanics.Rotational.Examples.SimpleGearShift: an automatic gear shift built
from a planetary gear, a brake on the ring and a clutch between sun and ring; the brake
holds first (ratio 1/2.5), at 2 s the clutch takes over within 0.1 s (ratio 1).

MSL components (Examples/SimpleGearShift.mo, Components/IdealPlanetary.mo, Clutch.mo,
Brake.mo, Sources/TorqueStep.mo, Sources/QuadraticSpeedDependentTorque.mo) and their
mechdyn counterparts:

- ``engine`` (J = 1) on the sun, angle ``phi_e``; ``load`` (J = 10) on the carrier, angle
  ``phi_L``; the ring has no inertia. ``idealPlanetary`` (ratio = 75/50):
  ``(1 + ratio) carrier = sun + ratio ring``, so the ring turns by
  ``phi_r = ((1 + ratio) phi_L - phi_e) / ratio``.
- ``torqueStep`` (stepTorque 20, offsetTorque 0, startTime 0.5) on the engine.
- ``quadraticSpeedDependentTorque`` (tau_nominal = -20, w_nominal = 10.471975511966,
  TorqueDirection = true by default) on the load: ``-20 (phi_L'/w_nominal)^2`` along
  ``phi_L`` whatever the direction.
- ``ramp`` (height 1, startTime 2, duration 0.1) -> clutch ``f_normalized``;
  ``feedback`` (1 - ramp) -> brake ``f_normalized``.
- ``clutch`` (cgeo = 2, fn_max = 100, mu_pos = [0, 0.5], peak = 1) between sun
  (flange_a) and ring (flange_b): Coulomb friction of magnitude
  ``cgeo mu fn_max ramp = 100 ramp`` along ``phi_rel = phi_r - phi_e``.
- ``brake`` (cgeo = 2, fn_max = 100, mu_pos = [0, 0.5], peak = 1, support fixed) on the
  ring: magnitude ``100 (1 - ramp)`` along ``phi_r``.

Start: load.phi = load.w = 0, clutch.phi_rel = clutch.w_rel = 0: everything at rest at 0.
Reference signals: clutch.phi_rel/w_rel = phi_r - phi_e and its rate, engine.phi/w,
load.phi/w.
"""
import sympy as sp

import mechdyn as md

phi_e, phi_L = md.coordinates("phi_e phi_L")
J_e, J_L, ratio, step_torque, step_start, tau_nominal, w_nominal = sp.symbols(
    "J_e J_L ratio stepTorque step_start tau_nominal w_nominal")
cgeo, mu, fn_max, ramp_start, duration = sp.symbols("cgeo mu fn_max ramp_start duration",
                                                    positive=True)
t = md.t

phi_r = ((1 + ratio) * phi_L - phi_e) / ratio
ramp = sp.Piecewise((0, t < ramp_start), ((t - ramp_start) / duration, t < ramp_start + duration),
                    (1, True))

mechanism = md.Mechanism("MSL Rotational.SimpleGearShift", coordinates=[phi_e, phi_L])
mechanism.link("engine", J=J_e, angle=phi_e)
mechanism.link("load", J=J_L, angle=phi_L)
mechanism.load("torqueStep", sp.Piecewise((0, t < step_start), (step_torque, True)),
               along=phi_e)
mechanism.load("quadraticSpeedDependentTorque",
               tau_nominal * (md.speed(phi_L) / w_nominal)**2, along=phi_L)
mechanism.friction("clutch", cgeo * mu * fn_max * ramp, along=phi_r - phi_e)
mechanism.friction("brake", cgeo * mu * fn_max * (1 - ramp), along=phi_r)

params = {J_e: 1, J_L: 10, ratio: 75 / 50, step_torque: 20, step_start: 0.5,
          tau_nominal: -20, w_nominal: 10.471975511966, cgeo: 2, mu: 0.5, fn_max: 100,
          ramp_start: 2, duration: 0.1}

scenes = {
    "reference": md.Scene("reference", t_end=5.0, initial={
        phi_e: 0, md.speed(phi_e): 0, phi_L: 0, md.speed(phi_L): 0}),
}

signals = {
    "clutch.phi_rel": phi_r - phi_e,
    "clutch.w_rel": sp.diff(phi_r - phi_e, phi_e) * md.speed(phi_e)
    + sp.diff(phi_r - phi_e, phi_L) * md.speed(phi_L),
    "engine.phi": phi_e, "engine.w": md.speed(phi_e),
    "load.phi": phi_L, "load.w": md.speed(phi_L),
}

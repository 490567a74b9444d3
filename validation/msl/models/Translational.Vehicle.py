"""Modelica.Mechanics.Translational.Examples.Vehicle: a vehicle, and a second vehicle
pulling an identical trailer, driven by a torque from a time table over a road with a
5 % grade between 20 s and 25 s, against drag, rolling and grade resistance.

MSL components (Examples/Vehicle.mo, Components/Vehicle.mo, Components/RollingResistance.mo,
Sources/QuadraticSpeedDependentForce.mo) and their mechdyn counterparts:

- ``vehicle``, ``vehicle1``, ``trailer`` (Components.Vehicle, m = 100, J = 0, R = 0.25,
  A = 1, Cd = 0.5, CrConstant = 0.01, vWindConstant = 0; rho is not passed to them, so
  the component default rho = 1.2 applies; g = g_n = 9.80665). ``vehicle1`` and
  ``trailer`` are coupled rigidly (multiSensor), so they share one slide: coordinates
  ``s_v`` (vehicle) and ``s_1`` (vehicle1 and trailer).
- Each vehicle body, with ``alpha = atan(inclination)``, feels
  drag ``-Cd A rho v |v| / 2`` (QuadraticSpeedDependentForce, f_nominal = -Cd A rho/2,
  ForceDirection = false), rolling ``-Cr m g cos(alpha) sign(v)`` regularised linearly
  to ``... v/vReg`` for ``|v| < vReg = 1e-3`` (RollingResistance, reg = Linear), and
  grade ``-m g sin(alpha)`` (fGrav).
- ``timeTableTorqueInclination`` (CombiTimeTable, linear segments; repeated time points
  are jumps): torque factor 0 on [0, 5), 5.6 on [5, 10.8), 1 on [10.8, 20), 2.8 on
  [20, 25), 1 on [25, 50), -5 on [50, 55), 0 after; inclination 0.05 on [20, 25), else 0.
- ``gain`` k = (fDrag + fRoll + fGrav) R with the example's own fDrag = Cd A rho_ex
  (vNom - vWind)^2/2 (rho_ex = 1.18, vNom = 25/3.5), fRoll = Cr m g_n, fGrav = 0
  (inclination parameter 0); ``torque`` = factor k on ``vehicle.flangeR``,
  ``torque1`` = 2 factor k on ``vehicle1.flangeR``. With J = 0 a wheel torque tau acts
  as the force tau/R: the load tau along ``s/R``.

Start: vehicle.s = vehicle.v = 0, vehicle1.s = vehicle1.v = 0 (trailer follows).
Reference signals: vehicle.s/v = s_v/s_v', vehicle1.s/v and trailer.s/v = s_1/s_1'.
"""
import sympy as sp

import mechdyn as md

s_v, s_1 = md.coordinates("s_v s_1")
m, R, A, Cd, rho, Cr, g, v_reg, rho_ex, v_nom = sp.symbols(
    "m R A Cd rho Cr g vReg rho_ex vNom", positive=True)
t = md.t

factor = sp.Piecewise((0, t < 5), (5.6, t < 10.8), (1, t < 20), (2.8, t < 25), (1, t < 50),
                      (-5, t < 55), (0, True))
inclination = sp.Piecewise((0, t < 20), (0.05, t < 25), (0, True))
alpha = sp.atan(inclination)
k = (Cd * A * rho_ex * v_nom**2 / 2 + Cr * m * g) * R


def resistance(v, mass):
    """Drag, rolling and grade resistance of one Components.Vehicle moving at v."""
    drag = -Cd * A * rho / 2 * sp.Piecewise((v**2, v >= 0), (-v**2, True))
    direction = sp.Piecewise((1, v >= v_reg), (-1, v <= -v_reg), (v / v_reg, True))
    rolling = -Cr * mass * g * sp.cos(alpha) * direction
    return drag + rolling - mass * g * sp.sin(alpha)


mechanism = md.Mechanism("MSL Translational.Vehicle", coordinates=[s_v, s_1],
                         units={s_v: "m", s_1: "m"})
mechanism.link("vehicle", m=m, x=s_v)
mechanism.link("vehicle1", m=m, x=s_1)
mechanism.link("trailer", m=m, x=s_1)
mechanism.load("torque", factor * k, along=s_v / R)
mechanism.load("torque1", 2 * factor * k, along=s_1 / R)
mechanism.load("vehicle resistance", resistance(md.speed(s_v), m), along=s_v)
mechanism.load("vehicle1 resistance", resistance(md.speed(s_1), m), along=s_1)
mechanism.load("trailer resistance", resistance(md.speed(s_1), m), along=s_1)

params = {m: 100, R: 0.25, A: 1, Cd: 0.5, rho: 1.2, Cr: 0.01, g: 9.80665, v_reg: 1e-3,
          rho_ex: 1.18, v_nom: 25 / 3.5}

scenes = {
    "reference": md.Scene("reference", t_end=60.0, initial={
        s_v: 0, md.speed(s_v): 0, s_1: 0, md.speed(s_1): 0}),
}

signals = {"vehicle.s": s_v, "vehicle.v": md.speed(s_v),
           "vehicle1.s": s_1, "vehicle1.v": md.speed(s_1),
           "trailer.s": s_1, "trailer.v": md.speed(s_1)}

"""
7. Reduction of masses, stiffnesses and forces
==============================================

**Problem.** Reduce a hoist's drive train to the motor shaft (the centre of reduction)
by keeping kinetic energy, potential energy and power equal. The train: motor rotor
``J_m = 0.2`` and coupling ``J_c = 0.15 kg m^2`` on the motor shaft; a two-stage
gearbox ``i_1 = 5``, ``i_2 = 8`` with ``J_g = 0.05 kg m^2`` on the intermediate shaft;
a drum ``J_d = 6 kg m^2`` of radius ``r_b = 0.2 m``; a load ``m = 2000 kg`` on a rope of
``E_k = EA = 8e6 N`` over ``l = 20 m``; efficiency ``eta_g = 0.95`` per gear stage and
``eta_b = 0.98`` per bearing, three bearings. Find the reduced inertia, the rope's
reduced stiffness, the moment the load puts on the motor shaft lifting and lowering,
and the train's natural frequency.
"""

# %%
# By hand
# -------
# ``J_red = J / i^2``, ``m_red = m r_b^2 / i^2``, ``c_red = (E_k / l) r_b^2 / i^2``,
# ``M_red = m g r_b / (i eta)`` lifting and ``m g r_b eta / i`` lowering (the load
# drives), ``eta = eta_g^2 eta_b^3``. Rigid, the train is one inertia; with the elastic
# rope it is two (motor side and load) on the spring ``c_red``:
# ``omega = sqrt(c (J_1 + J_2) / (J_1 J_2))``.
import math

import matplotlib.pyplot as plt
import sympy as sp

import mechdyn as md
from mechdyn import reduction

J_m, J_c, J_g, J_d, i_1, i_2, r_b, m, g = 0.2, 0.15, 0.05, 6.0, 5, 8, 0.2, 2000.0, 9.81
E_k, l = 8e6, 20.0
i = i_1 * i_2
parts = {"motor rotor": J_m, "coupling": J_c, "intermediate shaft": J_g / i_1**2,
         "drum": J_d / i**2, "load": m * r_b**2 / i**2}
I_red = sum(parts.values())
c_red = E_k / l * r_b**2 / i**2
eta = 0.95**2 * 0.98**3
M_lift, M_lower = m * g * r_b / (i * eta), m * g * r_b * eta / i
J_motor_side = I_red - parts["load"]
f_hand = math.sqrt(c_red * I_red / (J_motor_side * parts["load"])) / (2 * math.pi)

# %%
# With mechdyn
# ------------
# ``mechdyn.reduction`` has the same formulas for numbers or symbols; the bundled
# ``hoist_drive`` model declares the train link by link, and Lagrange's equations
# reduce it on their own (the rope made rigid) or give its natural frequencies (the
# rope elastic).
eta_api = reduction.efficiency(gear_stages=2, bearings=3)
api = {"I_red": J_m + J_c + reduction.inertia(J_g, i_1) + reduction.inertia(J_d, i)
       + reduction.drum_mass(m, r_b, i),
       "c_red": reduction.rope_stiffness(E_k, l, r_b, i),
       "eta": eta_api,
       "M_lift": reduction.drum_force(m * g, r_b, i, eta_api),
       "M_lower": reduction.drum_force(m * g, r_b, i, eta_api, overhauling=True)}

hoist = md.load_model("hoist_drive")
mech = hoist.mechanism
phi = mech.coordinates[0]
rigid = md.Scene("rigid", effects=["weight", "rope"], rigid=["rope"], t_end=1,
                 initial={phi: 0, md.speed(phi): 1})
derived_inertia = float(mech.reduced_inertia(rigid).subs(hoist.params))
moment = mech.reduced_moment(rigid).subs(hoist.params)
omega = md.plain(md.speed(phi))
modes = md.natural_frequencies(mech, hoist.scenes["lift_start"], params=hoist.params)

print(f"{'':30s}{'by hand':>12s}{'reduction':>12s}{'Lagrange':>12s}")
print(f"{'I_red [kg m^2]':30s}{I_red:12.6f}{api['I_red']:12.6f}{derived_inertia:12.6f}")
print(f"{'c_red rope [N m/rad]':30s}{c_red:12.6f}{api['c_red']:12.6f}")
print(f"{'eta':30s}{eta:12.6f}{api['eta']:12.6f}")
print(f"{'load moment lifting [N m]':30s}{-M_lift:12.4f}{-api['M_lift']:12.4f}"
      f"{float(moment.subs(omega, 1)):12.4f}")
print(f"{'load moment lowering [N m]':30s}{-M_lower:12.4f}{-api['M_lower']:12.4f}"
      f"{float(moment.subs(omega, -1)):12.4f}")
print(f"{'natural frequency [Hz]':30s}{f_hand:12.6f}{'':12s}{modes.hz[-1]:12.6f}")

# %%
# Where the reduced inertia comes from
# ------------------------------------
# The drum's 6 kg m^2 counts for less than 4 g m^2 at the motor: the slow end of a
# train barely matters to the motor's inertia.
fig, ax = plt.subplots(figsize=(6.4, 3.6))
ax.barh(list(parts), list(parts.values()))
ax.axvline(derived_inertia, color="k", ls="--", lw=1,
           label=f"total (Lagrange): {derived_inertia:.4f}")
ax.set_xscale("log")
ax.set_xlabel("inertia reduced to the motor shaft [kg m^2]")
ax.set_title("Worked example 7: the hoist reduced to the motor shaft")
ax.set_xlim(1e-3, 3)
ax.legend(loc="upper right")
fig.tight_layout()
plt.show()

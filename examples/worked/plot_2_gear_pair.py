"""
2. Gear pair
============

**Problem.** Gear 1 (``z_1`` teeth, inertia ``J_1``, driving moment ``M_1``) meshes
with gear 2 (``z_2``, ``J_2``, resisting moment ``M_2``). Reduce the pair to gear 1 and
find its angular acceleration; check it by d'Alembert's method. Data:
``z_1 = 20``, ``z_2 = 50``, ``J_1 = 0.05``, ``J_2 = 0.4 kg m^2``, ``M_1 = 30``,
``M_2 = 40 N m``.
"""

# %%
# By hand
# -------
# ``I_red = J_1 + J_2 (z_1/z_2)^2``, ``M_red = M_1 - M_2 z_1/z_2``,
# ``eps_1 = M_red / I_red``. d'Alembert: gear 1 ``J_1 eps_1 = M_1 - F r_1``, gear 2
# ``J_2 eps_2 = F r_2 - M_2`` with ``eps_2 = eps_1 r_1 / r_2``; eliminate the contact
# force ``F`` (pitch radii in proportion to the teeth, module 1 mm).
import matplotlib.pyplot as plt
import numpy as np
import sympy as sp

import mechdyn as md

z1, z2, J1, J2, M1, M2 = 20, 50, 0.05, 0.4, 30.0, 40.0
I_red = J1 + J2 * (z1 / z2) ** 2
M_red = M1 - M2 * z1 / z2
eps_1 = M_red / I_red
r1, r2 = 0.001 * z1 / 2, 0.001 * z2 / 2
# J_1 e = M_1 - F r_1 and J_2 e r_1/r_2 = F r_2 - M_2  =>  solve the 2 x 2 system for (e, F)
eps_dalembert, F = np.linalg.solve([[J1, r1], [J2 * r1 / r2, -r2]], [M1, -M2])

# %%
# With mechdyn
# ------------
# Gear 2's angle is ``z_1/z_2`` of gear 1's, counted in its own sense of rotation.
phi_1 = md.coordinate("phi_1")
z_1, z_2, J_1, J_2, M_1, M_2 = sp.symbols("z_1 z_2 J_1 J_2 M_1 M_2", positive=True)
pair = md.Mechanism("Gear pair", [phi_1])
pair.link("gear 1", J=J_1, angle=phi_1)
pair.link("gear 2", J=J_2, angle=z_1 / z_2 * phi_1)
pair.load("drive", M_1, along=phi_1)
pair.load("resistance", -M_2, along=z_1 / z_2 * phi_1)
params = {z_1: z1, z_2: z2, J_1: J1, J_2: J2, M_1: M1, M_2: M2}

print("I_red =", pair.reduced_inertia(), "  M_red =", pair.reduced_moment())
(equation,) = pair.equations().eqs
eps_derived = sp.solve(equation, md.plain(md.acceleration(phi_1)))[0]
start = md.Scene("startup", initial={phi_1: 0, md.speed(phi_1): 0}, t_end=2.0)
res = pair.simulate(start, params)

print(f"{'':28s}{'by hand':>12s}{'mechdyn':>12s}")
print(f"{'I_red [kg m^2]':28s}{I_red:12.6f}{float(pair.reduced_inertia().subs(params)):12.6f}")
print(f"{'M_red [N m]':28s}{M_red:12.6f}{float(pair.reduced_moment().subs(params)):12.6f}")
print(f"{'eps_1 [rad/s^2]':28s}{eps_1:12.6f}{float(eps_derived.subs(params)):12.6f}")
print(f"{'eps_1, d Alembert':28s}{eps_dalembert:12.6f}")
print(f"{'speed at 2 s [rad/s]':28s}{eps_1 * 2:12.6f}{res.final(md.speed(phi_1)):12.6f}")
print(f"contact force F = {F:.2f} N")

# %%
# Both gears from rest
# --------------------
times = np.linspace(0, 2, 101)
omega_1 = res.at(times, md.speed(phi_1))
fig, ax = plt.subplots(figsize=(6.4, 3.6))
ax.plot(times, omega_1, label="gear 1 (mechdyn)")
ax.plot(times, omega_1 * z1 / z2, label="gear 2 (z_1/z_2 of gear 1)")
ax.plot(times, eps_1 * times, "k:", label="by hand: eps_1 t")
ax.set_xlabel("time t [s]")
ax.set_ylabel("speed [rad/s]")
ax.set_title("Worked example 2: gear pair from rest")
ax.legend()
fig.tight_layout()
plt.show()

"""
6. Rope hoist with two shafts
=============================

**Problem.** Shaft 1 (``I_1 = m_1 rho_1^2 = 100 * 0.08 = 8 kg m^2``, pulley radius
``R_1 = 0.6 m``) is driven by ``M = 4200 + 200 t N m``. A belt without slip drives
shaft 2: pulley radius ``R_2 = 0.4 m``, own inertia ``m_2 rho_2^2 = 150 * 0.3^2``, drum
radius ``r_2 = 0.2 m`` lifting a load ``m_3 = 400 kg`` (``g = 9.81``); a resisting
moment ``M_c = 2000 N m`` acts on shaft 2. Shaft 1 starts at 2 rad/s. Find shaft 2's
motion (case 2: a moment that depends on time).
"""

# %%
# By hand
# -------
# ``I_red2 = m_2 rho_2^2 + m_3 r_2^2``; ``eps_2 = (M R_1 R_2 - (G_3 r_2 + M_c) R_1^2) /
# (I_1 R_2^2 + I_red2 R_1^2)``, linear in ``t``: ``eps_2 = a t + b``, so
# ``omega_2 = a t^2/2 + b t + omega_2(0)``, ``phi_2 = a t^3/6 + b t^2/2 + omega_2(0) t``.
import matplotlib.pyplot as plt
import numpy as np
import sympy as sp

import mechdyn as md

I1, R1, R2, m2, rho2, r2, m3, Mc, g = 8.0, 0.6, 0.4, 150.0, 0.3, 0.2, 400.0, 2000.0, 9.81
M0, Mt = 4200.0, 200.0
I_red2 = m2 * rho2**2 + m3 * r2**2
denominator = I1 * R2**2 + I_red2 * R1**2
a = Mt * R1 * R2 / denominator
b = (M0 * R1 * R2 - (m3 * g * r2 + Mc) * R1**2) / denominator
omega_20 = 2 * R1 / R2
print(f"by hand: I_red2 = {I_red2:g} kg m^2, eps_2 = {a:.4f} t + {b:.5f} rad/s^2")

# %%
# With mechdyn
# ------------
# The coordinate is shaft 2's angle; shaft 1 turns ``R_2/R_1`` as far, the load rises
# ``r_2 phi_2``.
phi_2 = md.coordinate("phi_2")
I_1, R_1, R_2, m_2, rho_2, r_2, m_3, M_c, g_, M_0, M_t = sp.symbols(
    "I_1 R_1 R_2 m_2 rho_2 r_2 m_3 M_c g M_0 M_t", positive=True)
hoist = md.Mechanism("Rope hoist", [phi_2])
hoist.link("shaft 1", J=I_1, angle=R_2 / R_1 * phi_2)
hoist.link("shaft 2", J=m_2 * rho_2**2, angle=phi_2)
hoist.link("load", m=m_3, y=r_2 * phi_2)
hoist.load("motor", M_0 + M_t * md.t, along=R_2 / R_1 * phi_2)
hoist.load("resistance", -M_c, along=phi_2)
hoist.gravity(g_)
params = {I_1: I1, R_1: R1, R_2: R2, m_2: m2, rho_2: rho2, r_2: r2, m_3: m3, M_c: Mc,
          g_: g, M_0: M0, M_t: Mt}
scene = md.Scene("startup", initial={phi_2: 0, md.speed(phi_2): omega_20}, t_end=3.0)

eps_2 = sp.expand((hoist.reduced_moment() / hoist.reduced_inertia()).subs(params))
print("mechdyn: eps_2 =", sp.N(eps_2, 6))
res = hoist.simulate(scene, params)
sol = md.closed_form(hoist, scene, params)
print(sol)
print(f"{'at t = 3 s':14s}{'by hand':>14s}{'simulated':>14s}")
print(f"{'omega_2 [1/s]':14s}{a * 9 / 2 + b * 3 + omega_20:14.6f}"
      f"{res.final(md.speed(phi_2)):14.6f}")
print(f"{'phi_2 [rad]':14s}{a * 27 / 6 + b * 9 / 2 + omega_20 * 3:14.6f}"
      f"{res.final(phi_2):14.6f}")

# %%
# Shaft 2's speed
# ---------------
times = np.linspace(0, 3, 101)
fig, ax = plt.subplots(figsize=(6.4, 3.6))
ax.plot(times, a * times**2 / 2 + b * times + omega_20, lw=5, alpha=0.35, label="by hand")
ax.plot(times, res.at(times, md.speed(phi_2)), "k--", label="mechdyn")
ax.set_xlabel("time t [s]")
ax.set_ylabel("shaft 2 speed omega_2 [rad/s]")
ax.set_title("Worked example 6: rope hoist start-up")
ax.legend()
fig.tight_layout()
plt.show()

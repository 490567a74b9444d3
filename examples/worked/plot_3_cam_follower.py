"""
3. Cam with a translating follower
==================================

**Problem.** A cam (inertia ``J_1A``, driving moment ``M_1``) lifts a translating
follower (mass ``m_2``, force ``F_2`` against it) by the uniform-velocity law
``s = h phi / Phi``. Reduce to the cam and find its angular acceleration and the time
of the rise from rest. Data: ``J_1A = 0.01 kg m^2``, ``m_2 = 0.5 kg``, ``h = 20 mm``,
``Phi = 90 deg``, ``M_1 = 0.5 N m``, ``F_2 = 20 N``.
"""

# %%
# By hand
# -------
# ``I_red = J_1A + m_2 (h/Phi)^2``, ``M_red = M_1 - F_2 h/Phi``, ``eps_1 = M_red /
# I_red``; uniformly accelerated, the rise ``Phi`` takes ``sqrt(2 Phi / eps_1)``.
import math

import matplotlib.pyplot as plt
import numpy as np
import sympy as sp

import mechdyn as md

J_1A, m_2, h, Phi, M_1, F_2 = 0.01, 0.5, 0.02, math.pi / 2, 0.5, 20.0
I_red = J_1A + m_2 * (h / Phi) ** 2
M_red = M_1 - F_2 * h / Phi
eps_1 = M_red / I_red
t_rise = math.sqrt(2 * Phi / eps_1)

# %%
# With mechdyn
# ------------
phi = md.coordinate("phi")
J, m, h_, Phi_, M, F = sp.symbols("J_1A m_2 h Phi M_1 F_2", positive=True)
rise = h_ * phi / Phi_
cam = md.Mechanism("Cam and follower", [phi])
cam.link("cam", J=J, angle=phi)
cam.link("follower", m=m, y=rise)
cam.load("drive", M, along=phi)
cam.load("follower force", -F, along=rise)
params = {J: J_1A, m: m_2, h_: h, Phi_: sp.pi / 2, M: M_1, F: F_2}
scene = md.Scene("rise", initial={phi: 0, md.speed(phi): 0}, until=md.reaches(phi, Phi_),
                 t_end=1)

print("I_red =", cam.reduced_inertia(), "  M_red =", cam.reduced_moment())
res = cam.simulate(scene, params)
print(f"{'':24s}{'by hand':>12s}{'mechdyn':>12s}")
print(f"{'I_red [kg m^2]':24s}{I_red:12.6f}{float(cam.reduced_inertia().subs(params)):12.6f}")
print(f"{'M_red [N m]':24s}{M_red:12.6f}{float(cam.reduced_moment().subs(params)):12.6f}")
print(f"{'eps_1 [rad/s^2]':24s}{eps_1:12.6f}"
      f"{float((cam.reduced_moment() / cam.reduced_inertia()).subs(params)):12.6f}")
print(f"{'time of the rise [s]':24s}{t_rise:12.6f}{res.t_end:12.6f}")

# %%
# The follower's rise
# -------------------
times = np.linspace(0, res.t_end, 101)
fig, ax = plt.subplots(figsize=(6.4, 3.6))
ax.plot(times, 1e3 * h / Phi * eps_1 * times**2 / 2, lw=5, alpha=0.35, label="by hand")
ax.plot(times, 1e3 * h / Phi * res.at(times, phi), "k--", label="mechdyn")
ax.set_xlabel("time t [s]")
ax.set_ylabel("follower lift s [mm]")
ax.set_title("Worked example 3: the follower's rise from rest")
ax.legend()
fig.tight_layout()
plt.show()

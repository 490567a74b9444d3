"""
5. Planetary gear start-up (2K-H)
=================================

**Problem.** A 2K-H planetary train: sun 1 drives, planets 2 and 3 sit on one planet
shaft, the carrier H carries the load moment ``M_H = 15 N m``. Teeth
``z_1 = z_3 = 20``, ``z_2 = z_4 = 40``; inertias ``J_1 = J_H = 0.18``, ``J_2 = 0.38``,
``J_3 = 0.22 kg m^2`` (planet mass and gravity neglected). a) What least moment
``M_1`` starts the train? b) What moment brings the sun to ``n_1 = 600 rpm`` in 3 s,
uniformly accelerated?
"""

# %%
# By hand
# -------
# Willis: ``i_1H = 1 - z_2 z_4 / (z_1 z_3) = -3``, so ``omega_H / omega_1 = -1/3``, and
# ``(omega_2 - omega_H) / (omega_1 - omega_H) = -z_1/z_2`` gives ``omega_2 / omega_1 =
# -1``. Then ``I_red = J_1 + (J_2 + J_3) (omega_2/omega_1)^2 + J_H (omega_H/omega_1)^2``.
import math

import matplotlib.pyplot as plt
import numpy as np
import sympy as sp

import mechdyn as md

z1, z2, z3, z4 = 20, 40, 20, 40
J1, J2, J3, JH, MH = 0.18, 0.38, 0.22, 0.18, 15.0
i_1H = 1 - z2 * z4 / (z1 * z3)
ratio_H = 1 / i_1H
ratio_2 = ratio_H - z1 / z2 * (1 - ratio_H)
I_red = J1 + (J2 + J3) * ratio_2**2 + JH * ratio_H**2
M1_least = MH * abs(ratio_H)
eps_1 = 600 * 2 * math.pi / 60 / 3
M1_start = M1_least + I_red * eps_1
print(f"i_1H = {i_1H:g}, omega_H/omega_1 = {ratio_H:.4f}, omega_2/omega_1 = {ratio_2:.4f}")

# %%
# With mechdyn
# ------------
# The links' angles are written with Willis' formula; the carrier's load resists the
# carrier's own turning, which is against the sun's.
phi_1 = md.coordinate("phi_1")
J_1, J_2, J_3, J_H, M_1, M_H = sp.symbols("J_1 J_2 J_3 J_H M_1 M_H", positive=True)
phi_H = phi_1 / (1 - sp.Rational(z2 * z4, z1 * z3))
phi_2 = phi_H - sp.Rational(z1, z2) * (phi_1 - phi_H)
train = md.Mechanism("Planetary 2K-H", [phi_1])
train.link("sun 1", J=J_1, angle=phi_1)
train.link("planets 2+3", J=J_2 + J_3, angle=phi_2)
train.link("carrier H", J=J_H, angle=phi_H)
train.load("drive", M_1, along=phi_1)
train.load("carrier load", -M_H, along=-phi_H)
data = {J_1: J1, J_2: J2, J_3: J3, J_H: JH, M_H: MH}

inertia = float(train.reduced_inertia().subs(data))
least = float(sp.solve(train.reduced_moment().subs(data), M_1)[0])
(equation,) = train.equations().eqs
eps = md.plain(md.acceleration(phi_1))
needed = float(sp.solve(equation.subs(data).subs(eps, eps_1), M_1)[0])
res = train.simulate(md.Scene("startup", initial={phi_1: 0, md.speed(phi_1): 0}, t_end=3),
                     {**data, M_1: needed})
n_1 = res.final(md.speed(phi_1)) * 60 / (2 * math.pi)

print("I_red =", train.reduced_inertia(), "  M_red =", train.reduced_moment())
print(f"{'':32s}{'by hand':>10s}{'mechdyn':>10s}")
print(f"{'I_red [kg m^2]':32s}{I_red:10.4f}{inertia:10.4f}")
print(f"{'a) least M_1 [N m]':32s}{M1_least:10.4f}{least:10.4f}")
print(f"{'b) M_1 for 600 rpm in 3 s [N m]':32s}{M1_start:10.4f}{needed:10.4f}")
print(f"{'   speed after 3 s [rpm]':32s}{600:10.4f}{n_1:10.4f}")

# %%
# The start-up
# ------------
times = np.linspace(0, 3, 101)
fig, ax = plt.subplots(figsize=(6.4, 3.6))
ax.plot(times, 200 * times, lw=5, alpha=0.35, label="by hand: 600 rpm in 3 s")
ax.plot(times, res.at(times, md.speed(phi_1)) * 60 / (2 * math.pi), "k--",
        label=f"mechdyn, M_1 = {needed:.2f} N m")
ax.set_xlabel("time t [s]")
ax.set_ylabel("sun speed n_1 [rpm]")
ax.set_title("Worked example 5: planetary train start-up")
ax.legend()
fig.tight_layout()
plt.show()

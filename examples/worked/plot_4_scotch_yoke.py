"""
4. Scotch yoke
==============

**Problem.** In the sine mechanism, crank 1 (inertia ``J_1A``, length ``l``, driving
moment ``M_1``) moves the yoke 3 (mass ``m_3``) by ``s_3 = l cos(phi)``; a force ``F_3``
acts against the yoke. Reduce to the crank and write the full equation of motion

``M_1 - F_3 l sin(phi) = (J_1A + m_3 l^2 sin^2 phi) eps + m_3 l^2 sin(phi) cos(phi)
omega^2``.

Data: ``J_1A = 0.02 kg m^2``, ``m_3 = 2 kg``, ``l = 0.1 m``, ``M_1 = 2 N m``,
``F_3 = 10 N``.
"""

# %%
# By hand
# -------
# The crank's angular acceleration at any angle and speed, solved from the equation
# above.
import matplotlib.pyplot as plt
import numpy as np
import sympy as sp

import mechdyn as md

J_1A, m_3, l, M_1, F_3 = 0.02, 2.0, 0.1, 2.0, 10.0


def eps_by_hand(phi, omega):
    inertia = J_1A + m_3 * l**2 * np.sin(phi) ** 2
    return (M_1 - F_3 * l * np.sin(phi)
            - m_3 * l**2 * np.sin(phi) * np.cos(phi) * omega**2) / inertia


# %%
# With mechdyn
# ------------
# The yoke is a link whose ``x`` is ``l cos(phi)``; the force acts along that
# displacement.
phi = md.coordinate("phi")
J, m, l_, M, F = sp.symbols("J_1A m_3 l M_1 F_3", positive=True)
yoke = md.Mechanism("Scotch yoke", [phi])
yoke.link("crank", J=J, angle=phi)
yoke.link("yoke", m=m, x=l_ * sp.cos(phi))
yoke.load("drive", M, along=phi)
yoke.load("resistance", F, along=l_ * sp.cos(phi))
params = {J: J_1A, m: m_3, l_: l, M: M_1, F: F_3}

print("I_red =", yoke.reduced_inertia())
print("M_red =", yoke.reduced_moment())
print("equation of motion:", yoke.equations().eqs[0])
(equation,) = yoke.equations().eqs
q, u, a = md.plain(phi), md.plain(md.speed(phi)), md.plain(md.acceleration(phi))
eps_mechdyn = sp.lambdify((q, u), sp.solve(equation, a)[0].subs(params))

print(f"{'phi [deg]':>10s}{'omega [rad/s]':>15s}{'eps by hand':>16s}{'eps mechdyn':>16s}")
for angle, omega in ((0, 0), (30, 10), (90, 20), (135, 5), (250, 30)):
    print(f"{angle:10d}{omega:15.1f}{eps_by_hand(np.radians(angle), omega):16.8f}"
          f"{eps_mechdyn(np.radians(angle), omega):16.8f}")

# %%
# Start-up from rest
# ------------------
# The hand equation integrated with scipy beside mechdyn's run.
from scipy.integrate import solve_ivp

start = md.Scene("startup", initial={phi: 0, md.speed(phi): 0}, t_end=1.0)
res = yoke.simulate(start, params)
hand = solve_ivp(lambda t, y: [y[1], eps_by_hand(y[0], y[1])], (0, 1), [0, 0],
                 rtol=1e-10, atol=1e-12, dense_output=True)
times = np.linspace(0, 1, 401)
print(f"speed at 1 s: by hand {hand.sol(1.0)[1]:.8f}, mechdyn {res.final(md.speed(phi)):.8f}")
fig, ax = plt.subplots(figsize=(6.4, 3.6))
ax.plot(times, hand.sol(times)[1], lw=5, alpha=0.35, label="hand equation (scipy)")
ax.plot(times, res.at(times, md.speed(phi)), "k--", label="mechdyn")
ax.set_xlabel("time t [s]")
ax.set_ylabel("crank speed omega [rad/s]")
ax.set_title("Worked example 4: Scotch yoke from rest")
ax.legend()
fig.tight_layout()
plt.show()

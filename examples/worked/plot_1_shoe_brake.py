"""
1. Shoe brake
=============

**Problem.** A disc with ``I_red = 0.4 kg m^2`` turning at ``omega_0 = 100 rad/s`` is
braked by a lever pressing a shoe with ``P = 20 N``; friction coefficient ``f = 0.2``,
disc radius ``R = 0.1 m``. The lever doubles the normal force, so the friction moment is
``M_fr = f 2P R`` and ``M_red = -M_fr``: the textbook's case 1, uniformly decelerated
motion. When and after how many turns does the disc stop?
"""

# %%
# By hand
# -------
# ``omega(t) = omega_0 + (M_red / I_red) t`` and ``phi(t) = omega_0 t + (M_red / I_red)
# t^2 / 2``.
import math

import matplotlib.pyplot as plt
import numpy as np
import sympy as sp

import mechdyn as md

I_red, omega_0, P, f, R = 0.4, 100.0, 20.0, 0.2, 0.1
M_red = -f * 2 * P * R
t_stop = -omega_0 * I_red / M_red
phi_stop = omega_0 * t_stop + M_red / I_red * t_stop**2 / 2

# %%
# With mechdyn
# ------------
# The disc is one link, the shoe a friction element along its angle.
phi = md.coordinate("phi")
I, f_, P_, R_ = sp.symbols("I f P R", positive=True)
brake = md.Mechanism("Shoe brake", [phi], units={I: "kg*m^2", f_: "1", P_: "N", R_: "m"})
brake.link("disc", J=I, angle=phi)
brake.friction("shoe", f_ * 2 * P_ * R_, along=phi)
braking = md.Scene("braking", initial={phi: 0, md.speed(phi): omega_0}, until=md.stopped(phi))
params = {I: I_red, f_: f, P_: P, R_: R}

print("I_red =", brake.reduced_inertia(), "  M_red =", brake.reduced_moment())
res = brake.simulate(braking, params)
sol = md.closed_form(brake, braking, params)

print(f"{'':22s}{'by hand':>12s}{'simulated':>14s}{'closed form':>14s}")
print(f"{'stops at t [s]':22s}{t_stop:12.6f}{res.t_end:14.6f}{float(sol.stop.t):14.6f}")
print(f"{'after phi [rad]':22s}{phi_stop:12.4f}{res.final(phi):14.4f}"
      f"{float(sol.stop.phi):14.4f}")
print(f"{'after [rev]':22s}{phi_stop / (2 * math.pi):12.4f}"
      f"{res.final(phi) / (2 * math.pi):14.4f}{float(sol.stop.phi) / (2 * math.pi):14.4f}")

# %%
# The speed while braking
# -----------------------
times = np.linspace(0, t_stop, 101)
fig, ax = plt.subplots(figsize=(6.4, 3.6))
ax.plot(times, omega_0 + M_red / I_red * times, lw=5, alpha=0.35, label="by hand")
ax.plot(times, res.at(times, md.speed(phi)), "k--", label="mechdyn")
ax.set_xlabel("time t [s]")
ax.set_ylabel("disc speed omega [rad/s]")
ax.set_title("Worked example 1: the shoe brake stops the disc")
ax.legend()
fig.tight_layout()
plt.show()

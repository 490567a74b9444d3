"""
0. The equation of motion of a one-DOF machine
==============================================

**Problem.** Lagrange's equation of the second kind applied to the kinetic energy
``E = I_red(phi) omega^2 / 2`` of a machine with one degree of freedom gives

``I_red(phi) eps + (1/2) dI_red/dphi omega^2 = M_red(phi, omega, t)``

with ``I_red = sum_i [m_i (v_Si/omega)^2 + J_Si (omega_i/omega)^2]``: the reduced
quantities need only the velocity ratios (transmission functions). The source
integrates it step by step: on steps short enough that ``I_red`` and ``M_red`` barely
change, use the formulas of uniformly accelerated motion, update, go on.

Here the machine is the exact slider-crank (crank ``r = 0.1 m``, rod ``L = 0.4 m``,
bundled as ``slider_crank``): crank ``J_1 = 0.01 kg m^2``; rod ``m_2 = 0.5 kg``,
``J_2 = m_2 L^2/12``, its centre halfway; slider ``m_3 = 1 kg``; a DC shunt motor
``M = M_0 (1 - omega/omega_0)``, ``M_0 = 5 N m``, ``omega_0 = 100 rad/s``, started
from rest. Its ``I_red`` depends on ``phi`` and ``M_red`` on ``omega``: the source's
case 5, integrated numerically.
"""

# %%
# By hand
# -------
# The velocity ratios of the rod's centre, the rod and the slider (differentiating
# the slider-crank's positions), the sum above, the slope of ``I_red`` by a central
# difference, and the source's stepping method.
import matplotlib.pyplot as plt
import numpy as np
from scipy.integrate import solve_ivp

import mechdyn as md

r, L, J_1, m_2, m_3, M_0, omega_0 = 0.1, 0.4, 0.01, 0.5, 1.0, 5.0, 100.0
J_2 = m_2 * L**2 / 12


def I_red_by_hand(phi):
    """The sum over the links, with the slider-crank's velocity ratios."""
    run = np.sqrt(L**2 - r**2 * np.sin(phi) ** 2)        # slider beyond the crank pin
    run_ = -r**2 * np.sin(phi) * np.cos(phi) / run         # d(run)/dphi
    x3 = -r * np.sin(phi) + run_                           # slider: v / omega
    x2, y2 = -r * np.sin(phi) + run_ / 2, r * np.cos(phi) / 2   # rod centre
    beta = -r * np.cos(phi) / run                          # rod: omega_2 / omega
    return J_1 + m_2 * (x2**2 + y2**2) + J_2 * beta**2 + m_3 * x3**2


def eps_by_hand(phi, omega):
    """The angular acceleration from the equation of motion."""
    slope = (I_red_by_hand(phi + 1e-4) - I_red_by_hand(phi - 1e-4)) / 2e-4
    return (M_0 * (1 - omega / omega_0) - slope * omega**2 / 2) / I_red_by_hand(phi)


def stepping(dt, t_end=1.0):
    """The source's method: uniformly accelerated motion on each step; the history."""
    history = [(0.0, 0.0)]
    for _ in range(round(t_end / dt)):
        phi, omega = history[-1]
        eps = eps_by_hand(phi, omega)
        history.append((phi + omega * dt + eps * dt**2 / 2, omega + eps * dt))
    return np.array(history)


# Runge-Kutta on the same equation (scipy), for an answer of any accuracy.
hand = solve_ivp(lambda t, y: [y[1], eps_by_hand(y[0], y[1])], (0, 1), [0, 0],
                 method="DOP853", rtol=1e-9, atol=1e-9, dense_output=True)


# %%
# With mechdyn
# ------------
model = md.load_model("slider_crank")
mech = model.mechanism
derivation = mech.derivation()
print("I_red =", derivation.reduced_inertia)
print("M_red =", derivation.reduced_moment)
print(md.classify(mech, model.scenes["startup"]))
phi = mech.coordinates[0]
inertia = mech.reduced_inertia().subs(model.params)
print(f"{'phi [deg]':>10s}{'I_red by hand':>16s}{'I_red mechdyn':>16s}")
for angle in (0, 30, 60, 90, 150, 240):
    value = float(inertia.subs(md.plain(phi), np.radians(angle)))
    print(f"{angle:10d}{I_red_by_hand(np.radians(angle)):16.9f}{value:16.9f}")

res = mech.simulate(model.scenes["startup"], model.params)
print(f"\n{'at t = 1 s':18s}{'phi [rad]':>12s}{'omega [rad/s]':>16s}")
for dt in (1e-2, 1e-3, 1e-4):
    phi_end, omega_end = stepping(dt)[-1]
    print(f"{f'steps of {dt:g} s':18s}{phi_end:12.6f}{omega_end:16.6f}")
print(f"{'Runge-Kutta':18s}{hand.y[0, -1]:12.6f}{hand.y[1, -1]:16.6f}")
print(f"{'mechdyn':18s}{res.final(phi):12.6f}{res.final(md.speed(phi)):16.6f}")

# %%
# The five cases
# --------------
# The source sorts one-DOF machines by what ``I_red`` and ``M_red`` depend on;
# ``md.classify`` names the case of each bundled one-DOF model's first scene.
for name in ("shoe_brake", "gear_pair", "rope_hoist", "motor_startup", "scotch_yoke",
             "slider_crank"):
    bundled = md.load_model(name)
    case = md.classify(bundled.mechanism, next(iter(bundled.scenes.values())))
    print(f"{name:14s} {str(case).splitlines()[0]}")

# %%
# The start-up
# ------------
# The stepping method lags behind as its errors add up; Runge-Kutta on the hand
# equation and mechdyn lie on one another.
times = np.linspace(0, 1, 1001)
steps = stepping(1e-3)
fig, ax = plt.subplots(figsize=(6.4, 3.6))
ax.plot(times, hand.sol(times)[1], lw=5, alpha=0.35, label="by hand, Runge-Kutta")
ax.plot(times, res.at(times, md.speed(phi)), "k--", label="mechdyn")
ax.plot(times, steps[:, 1], lw=1, label="by hand, steps of 1 ms")
ax.set_xlabel("time t [s]")
ax.set_ylabel("crank speed omega [rad/s]")
ax.set_title("Worked example 0: slider-crank start-up")
ax.legend()
fig.tight_layout()
plt.show()

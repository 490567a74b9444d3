"""
8. Elastic mechanism with periodic coefficients (loom sley)
===========================================================

**Problem.** A loom's sley (batten) is driven by two cranks on one crankshaft turning
at 250 rpm (``omega = 26.18 rad/s``). Its two most compliant parts are elastic: the
crankshaft's torsion between the cranks (``phi_2``, stiffness ``k_t``) and the sley
beam's bending between its swords (masses ``m_3 = m_4 = 0.206 kg`` at its thirds,
travels ``x_3``, ``x_4``, stiffness ``k_b`` each). Each sword follows its crank by the
slider-crank law ``s(theta) = -lam cos(theta) + (lam^2/(4 l)) cos(2 theta)``, whose
transmission function is ``lam sin(theta) - (lam^2/(2 l)) sin(2 theta)``. For small
deflections the three coordinates obey a linear system ``Y' = A(t) Y + b(t)``,
``Y = [phi_2, phi_2', x_3, x_3', x_4, x_4']``, with coefficients periodic in ``t``.
Find its steady (periodic) motion.

The source reports a torsion amplitude of 0.0037 rad, a torsion rate up to 0.24 1/s
and an angular acceleration amplitude of 15.4 1/s^2. The values it leaves out are those
of the bundled ``loom_sley`` model: ``lam = 0.08 m``, ``l = 0.25 m``; crank B with its
share of the shaft ``J_2 = 0.01 kg m^2``; sword and rod reduced to the sword end
``m_s = 1.5 kg``; ``k_t = 1450 N m/rad``, ``k_b = 3.25e5 N/m``; dampers ``d_t = 0.5 N m s``
and ``d_b = 26 N s/m``.
"""

# %%
# By hand: the method of initial parameters
# -----------------------------------------
# Crank A turns at ``theta = omega t``, crank B lags by ``phi_2``. The kinetic energy
# ``J_2 theta_B'^2/2 + m_s s'(theta_B)^2 theta_B'^2/2 + m_3 x_3'^2/2 + m_4 x_4'^2/2`` and
# the springs on ``phi_2`` and on the beam's deflections
# ``x_3 - (2 s_A + s_B)/3``, ``x_4 - (s_A + 2 s_B)/3`` give Lagrange's equations; kept
# to first order in the small deflections they are linear, written out in ``rhs``.
# ``Y(t) = K(t) C + Y_p(t)``: the fundamental matrix ``K`` from the six unit initial
# vectors, the particular solution ``Y_p`` from zero; periodicity ``Y(T) = C`` gives
# ``(I - K(T)) C = Y_p(T)``.
import matplotlib.pyplot as plt
import numpy as np
from scipy.integrate import solve_ivp

import mechdyn as md

omega, lam, l = 250 * 2 * np.pi / 60, 0.08, 0.25
J_2, m_s, m_3, m_4 = 0.01, 1.5, 0.206, 0.206
k_t, d_t, k_b, d_b = 1450.0, 0.5, 3.25e5, 26.0
T = 2 * np.pi / omega


def rhs(t, Y):
    """Y' for the linearised equations; Y may hold several solutions as columns."""
    th = omega * t
    s = -lam * np.cos(th) + lam**2 / (4 * l) * np.cos(2 * th)
    s1 = lam * np.sin(th) - lam**2 / (2 * l) * np.sin(2 * th)        # ds/dtheta
    s2 = lam * np.cos(th) - lam**2 / l * np.cos(2 * th)
    s3 = -lam * np.sin(th) + 2 * lam**2 / l * np.sin(2 * th)
    phi, dphi, x3, dx3, x4, dx4 = Y
    dsB = s1 * dphi + s2 * omega * phi                # s_B' - s_A' to first order
    F3 = k_b * (x3 - s - s1 * phi / 3) + d_b * (dx3 - s1 * omega - dsB / 3)
    F4 = k_b * (x4 - s - 2 * s1 * phi / 3) + d_b * (dx4 - s1 * omega - 2 * dsB / 3)
    sword = m_s * omega * (s1 * s2 * omega + (s2**2 + s1 * s3) * omega * phi
                           + 2 * s1 * s2 * dphi)
    ddphi = -(sword + k_t * phi + d_t * dphi - s1 * F3 / 3 - 2 * s1 * F4 / 3) / (
        J_2 + m_s * s1**2)
    return np.array([dphi, ddphi, dx3, -F3 / m_3, dx4, -F4 / m_4])


def fundamental(t, z):
    """K' = A K (six columns) beside Y_p' = A Y_p + b (the seventh)."""
    Z = z.reshape(6, 7)
    out = rhs(t, Z)
    out[:, :6] -= rhs(t, np.zeros(6))[:, None]       # the homogeneous part: no b(t)
    return out.ravel()


start = np.hstack([np.eye(6), np.zeros((6, 1))]).ravel()
end = solve_ivp(fundamental, (0, T), start, method="DOP853", rtol=1e-10,
                atol=1e-12).y[:, -1].reshape(6, 7)
K_T, Yp_T = end[:, :6], end[:, 6]
C = np.linalg.solve(np.eye(6) - K_T, Yp_T)
multipliers = np.linalg.eigvals(K_T)
period = solve_ivp(rhs, (0, T), C, method="DOP853", rtol=1e-10, atol=1e-12,
                   dense_output=True)
times = np.linspace(0, T, 2001)
hand = period.sol(times)
hand_acceleration = np.array([rhs(t, y)[1] for t, y in zip(times, hand.T)])


def half_swing(values):
    return (values.max() - values.min()) / 2


print("Floquet multipliers (eigenvalues of K(T)): max |mu| =", abs(multipliers).max())

# %%
# With mechdyn
# ------------
# The bundled model declares the same mechanism (its equations are not linearised);
# ``md.periodic_steady_state`` finds the periodic motion by shooting.
model = md.load_model("loom_sley")
steady = md.periodic_steady_state(model.mechanism, model.scenes["run"], model.params)
swing = steady.amplitudes()
print(steady)
print(f"{'amplitude':28s}{'source':>10s}{'by hand':>12s}{'mechdyn':>12s}")
print(f"{'torsion phi_2 [rad]':28s}{0.0037:10.4f}{half_swing(hand[0]):12.6f}"
      f"{swing['phi_2']:12.6f}")
print(f"{'torsion rate [1/s]':28s}{0.24:10.2f}{half_swing(hand[1]):12.6f}"
      f"{swing['phidot_2']:12.6f}")
print(f"{'acceleration [1/s^2]':28s}{15.4:10.1f}{half_swing(hand_acceleration):12.6f}"
      f"{swing['phiddot_2']:12.6f}")
print(f"{'mass 3, x_3 [m]':28s}{'':10s}{half_swing(hand[2]):12.6f}{swing['x_3']:12.6f}")

# %%
# One period of the torsion
# -------------------------
fig, ax = plt.subplots(figsize=(6.4, 3.6))
ax.plot(np.degrees(omega * times), 1e3 * hand[0], lw=5, alpha=0.35,
        label="by hand (initial parameters)")
phi_2 = model.mechanism.coordinates[0]
ax.plot(np.degrees(omega * times), 1e3 * steady.result.at(times, phi_2), "k--",
        label="mechdyn (shooting)")
ax.set_xlabel("crank angle omega t [deg]")
ax.set_ylabel("crankshaft torsion phi_2 [mrad]")
ax.set_title("Worked example 8: steady motion of the loom sley")
ax.set_xticks(range(0, 361, 60))
ax.legend(loc="lower left")
fig.tight_layout()
plt.show()

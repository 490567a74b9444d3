"""
Clutch engagement
=================

An engine's flywheel spinning at 100 rad/s is coupled to a load at rest by a dry
clutch whose normal force ramps up over half a second. The clutch slips, braking the
flywheel and speeding up the load, until both turn together; then it locks and holds.
Momentum is kept, so the common speed is ``J_1 omega_0 / (J_1 + J_2)`` and the heat of
the slip is ``J_1 J_2 omega_0^2 / (2 (J_1 + J_2))``.
"""

# %%
# Engaging without a load moment
# ------------------------------
import matplotlib.pyplot as plt
import numpy as np

import mechdyn as md

model = md.load_model("clutch_engagement")
mech = model.mechanism
res = mech.simulate(model.scenes["engage"], model.params)
print(res.summary())
J1, J2, w0 = (float(model.params[model.param_symbol(n)]) for n in ("J_1", "J_2", "omega_0"))
phi_1, phi_2 = mech.coordinates
lock = next(e for e in res.events if e.kind == "stick")
print(f"locked at t = {lock.time:.4f} s at {res.final(md.speed(phi_2)):.4f} rad/s "
      f"(momentum: {J1 * w0 / (J1 + J2):.4f} rad/s)")
heat = J1 * w0**2 / 2 - (J1 + J2) * res.final(md.speed(phi_2)) ** 2 / 2
print(f"heat of the slip {heat:.2f} J, by hand {J1 * J2 * w0**2 / (2 * (J1 + J2)):.2f} J")

times = np.linspace(0, res.t_end, 401)
fig, ax = plt.subplots(figsize=(6.4, 3.6))
ax.plot(times, res.at(times, md.speed(phi_1)), label="flywheel")
ax.plot(times, res.at(times, md.speed(phi_2)), label="load")
ax.axvline(lock.time, color="k", lw=0.8, ls=":", label="clutch locks")
ax.set_xlabel("time t [s]")
ax.set_ylabel("speed [rad/s]")
ax.set_title("Clutch engagement: both sides' speeds")
ax.legend()
fig.tight_layout()

# %%
# With a load moment
# ------------------
# The locked clutch carries the load moment's share ``M_L J_1 / (J_1 + J_2)``.
loaded = mech.simulate(model.scenes["engage_loaded"], model.params)
print(loaded.summary())
loaded.plot()
plt.show()

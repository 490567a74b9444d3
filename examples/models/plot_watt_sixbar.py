"""
Watt II six-bar
===============

Two four-bar loops in series: the rocker of the first (a ternary link) drives the
second, whose output rocker works against a moment while it swings forward. Five
angles, four loop equations, one degree of freedom: the crank angle. A DC shunt motor
with a flywheel drives the crank. The kinematics of the whole chain (both rockers'
swings, the reduced inertia's range) come from ``md.Linkage``.
"""

# %%
# The linkage
# -----------
import matplotlib.pyplot as plt
import numpy as np

import mechdyn as md

model = md.load_model("watt_sixbar")
mech = model.mechanism
linkage = md.Linkage(mech, model.params, scene=model.scenes["steady"])
print(linkage.describe())
linkage.plot()
plt.show()

# %%
# Steady running
# --------------
# The output rocker swings through about 82 degrees; the crank's speed dips while the
# rocker works.
res = mech.simulate(model.scenes["steady"], model.params)
print(res.summary())
phi, theta_5 = mech.coordinates[0], mech.coordinates[4]
fig, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(6.4, 5))
top.plot(res.t, res[md.speed(phi)])
top.set_ylabel("crank speed [rad/s]")
top.set_title("Watt II six-bar: steady running")
bottom.plot(res.t, np.degrees(res[theta_5]))
bottom.set_ylabel("output rocker theta_5 [deg]")
bottom.set_xlabel("time t [s]")
fig.tight_layout()
plt.show()

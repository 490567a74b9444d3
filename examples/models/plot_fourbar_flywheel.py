"""
Crank-rocker four-bar with a flywheel
=====================================

A four-bar linkage (crank 0.1 m, coupler 0.35 m, rocker 0.3 m, frame 0.4 m) declared
with all three of its angles and the vector loop that ties them: a closed loop that
mechdyn keeps closed while it integrates. Grashof's criterion makes the shortest link,
the crank, turn fully. A DC shunt motor drives the crank with a flywheel; the rocker
works against a moment while it swings forward. The linkage's kinematics come first
(class, swing, time ratio, transmission angle), then the motion.
"""

# %%
# The linkage
# -----------
import matplotlib.pyplot as plt

import mechdyn as md

model = md.load_model("fourbar_flywheel")
mech = model.mechanism
linkage = md.Linkage(mech, model.params, scene=model.scenes["steady"])
print(linkage.describe())
linkage.plot(paths=model.points)
plt.show()

# %%
# Start-up
# --------
# The loop's multipliers ``ABCD.x``, ``ABCD.y`` are the force the rocker side exerts
# on the crank side at the loop's closing joint.
res = mech.simulate(model.scenes["startup"], model.params)
print(res.summary())
phi = mech.coordinates[0]
fig, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(6.4, 5))
top.plot(res.t, res[md.speed(phi)])
top.set_ylabel("crank speed [rad/s]")
top.set_title("Four-bar with flywheel: start-up")
bottom.plot(res.t, res["motor"], label="motor moment [N m]")
bottom.plot(res.t, res["ABCD.y"], label="loop force ABCD.y [N]")
bottom.set_ylabel("moment [N m], force [N]")
bottom.set_xlabel("time t [s]")
bottom.legend()
fig.tight_layout()
plt.show()

"""
Toggle press
============

A knuckle-joint press: a crank pushes the knee of two toggle links, which straighten
as the ram reaches the bottom, so a small crank moment gives a large press force
there (``dy/dphi`` tends to zero). Two closed loops, five coordinates, one degree of
freedom. An induction motor with a flywheel drives the crank through a 20 : 1 gear;
over the last 5 mm the workpiece resists the descending ram.
"""

# %%
# The linkage
# -----------
import matplotlib.pyplot as plt

import mechdyn as md

model = md.load_model("toggle_press")
mech = model.mechanism
linkage = md.Linkage(mech, model.params, scene=model.scenes["steady"])
print(linkage.describe())
linkage.plot()
plt.show()

# %%
# Steady running
# --------------
# The press force peaks where the toggle is nearly straight; the flywheel carries the
# crank through it.
res = mech.simulate(model.scenes["steady"], model.params)
print(res.summary(units={"workpiece": "kN"}))
phi, y = mech.coordinates[0], mech.coordinates[4]
fig, (top, middle, bottom) = plt.subplots(3, 1, sharex=True, figsize=(6.4, 6.4))
top.plot(res.t, 1e3 * res[y])
top.set_ylabel("ram y [mm]")
top.set_title("Toggle press: steady running")
middle.plot(res.t, res["workpiece"] / 1e3)
middle.set_ylabel("press force [kN]")
bottom.plot(res.t, res[md.speed(phi)])
bottom.set_ylabel("crank speed [rad/s]")
bottom.set_xlabel("time t [s]")
fig.tight_layout()
plt.show()

"""
Crank-shaper quick-return mechanism
===================================

A slotted-lever shaper: the crank's pin slides in the slot of a swinging lever, whose
tip drives the ram through a short link. The ram's cutting stroke takes the crank
through ``pi + 2 asin(r/d)`` = 218.9 degrees, the return only 141.1 degrees: a time ratio
of 1.55. Two closed loops (the slot and the drive), five coordinates, one degree of
freedom. An induction motor with a flywheel drives the crank through a 15 : 1 gear;
the ram cuts against 800 N while it moves back.
"""

# %%
# The linkage and its time ratio
# ------------------------------
import math

import matplotlib.pyplot as plt

import mechdyn as md

model = md.load_model("quick_return")
mech = model.mechanism
linkage = md.Linkage(mech, model.params, scene=model.scenes["steady"])
print(linkage.describe())
r, d = (float(model.params[model.param_symbol(n)]) for n in ("r", "d"))
cut, back = math.pi + 2 * math.asin(r / d), math.pi - 2 * math.asin(r / d)
print(f"by hand: cutting {math.degrees(cut):.1f} deg, return {math.degrees(back):.1f} deg, "
      f"time ratio {cut / back:.4f}")
linkage.plot()
plt.show()

# %%
# Steady running
# --------------
# The ram's position over time: the slow cutting stroke (falling, against the cutting
# force) and the fast return.
res = mech.simulate(model.scenes["steady"], model.params)
print(res.summary())
x = mech.coordinates[4]
fig, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(6.4, 5))
top.plot(res.t, res[x])
top.set_ylabel("ram position x [m]")
top.set_title("Quick-return shaper: steady running")
bottom.plot(res.t, res["cutting"])
bottom.set_ylabel("cutting force [N]")
bottom.set_xlabel("time t [s]")
fig.tight_layout()
plt.show()

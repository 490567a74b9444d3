"""
Slider-crank
============

The exact slider-crank (crank ``r = 0.1`` m, rod ``L = 0.4`` m), with no small-angle
series: the rod's mass and inertia and the slider's mass make the reduced inertia vary
with the crank angle, and the DC shunt motor's moment falls with the speed, so the
equation has no closed form (the textbook's case 5). The scene ``startup`` runs the
crank up from rest for one second; the speed ripples twice per turn. The links carry
drawing points, so ``md.animate`` can film the motion.
"""

# %%
# What kind of equation
# ---------------------
import matplotlib.pyplot as plt
import numpy as np
import sympy as sp

import mechdyn as md

model = md.load_model("slider_crank")
mech = model.mechanism
print(md.classify(mech, model.scenes["startup"]))
phi = md.plain(mech.coordinates[0])
inertia = sp.lambdify(phi, mech.reduced_inertia().subs(model.params))
angles = np.linspace(0, 2 * np.pi, 361)
values = inertia(angles)
print(f"I_red from {values.min():.5f} to {values.max():.5f} kg m^2 over a turn")

# %%
# Start-up
# --------
res = mech.simulate(model.scenes["startup"], model.params)
print(res.summary())
res.plot()
plt.show()

# %%
# The speed against the crank angle
# ---------------------------------
# Where the reduced inertia is large the crank slows down: plotted over the crank
# angle, each turn of the start-up shows the same two dips.
times = np.linspace(0, res.t_end, 2001)
q = mech.coordinates[0]
fig, ax = plt.subplots(figsize=(6.4, 3.6))
ax.plot(np.degrees(res.at(times, q)) % 360, res.at(times, md.speed(q)), ".", ms=2)
ax.set_xlabel("crank angle phi mod 360 [deg]")
ax.set_ylabel("crank speed [rad/s]")
ax.set_title("Slider-crank start-up: speed over the crank angle")
ax.set_xticks(range(0, 361, 90))
fig.tight_layout()
plt.show()

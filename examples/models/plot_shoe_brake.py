"""
Shoe brake
==========

A disc turning at 100 rad/s is braked by a shoe that a lever presses against its rim.
The lever doubles the shoe force ``P``, so the friction moment is ``f 2P R`` whatever
the speed: the reduced inertia and the reduced moment are both constant, the textbook's
case 1 (uniformly decelerated motion). The scene ``braking`` runs until the disc stops;
mechdyn also integrates this case in closed form.
"""

# %%
# The model and its reduced quantities
# ------------------------------------
import matplotlib.pyplot as plt
import numpy as np

import mechdyn as md

model = md.load_model("shoe_brake")
mech = model.mechanism
print("I_red =", mech.reduced_inertia())
print("M_red =", mech.reduced_moment())
print(mech.equations().textbook_equation)
print(md.classify(mech, model.scenes["braking"]))

# %%
# Braking to rest
# ---------------
# The scene stops when the disc's speed reaches zero; the friction element then
# sticks and holds it.
res = mech.simulate(model.scenes["braking"], model.params)
print(res.summary())
print(res.events)
res.plot()
plt.show()

# %%
# Closed form against the simulation
# ----------------------------------
# ``md.closed_form`` solves the equation exactly: a straight line in time for the
# speed, a parabola for the angle. The simulated angle differs from it by rounding.
sol = md.closed_form(mech, model.scenes["braking"], model.params)
print(sol)
phi = mech.coordinates[0]
times = np.linspace(0, float(sol.stop.t), 201)
fig, ax = plt.subplots(figsize=(6.4, 3.6))
ax.plot(times, res.at(times, phi) - sol.function("phi(t)")(times))
ax.set_xlabel("time t [s]")
ax.set_ylabel("simulated - exact phi [rad]")
ax.set_title("Shoe brake: the simulation against the closed form")
fig.tight_layout()

"""
Hoist drive with an elastic rope
================================

An induction motor lifts a 2 t load through a coupling with a brake pulley, a two-stage
gearbox (``i = 5 * 8 = 40``), a drum and a 20 m rope. Two coordinates, the motor angle
and the load's height; the rope's stretch ties them. Made rigid (the ``*_rigid``
scenes) the rope fixes the height and the drive reduces to the motor shaft as a
textbook does by hand. The scene ``lift_start`` releases the brake at rest with the
motor on: the load lags, the rope force overshoots and rings.
"""

# %%
# Reduced to the motor shaft (rigid rope)
# ---------------------------------------
import matplotlib.pyplot as plt

import mechdyn as md

model = md.load_model("hoist_drive")
mech = model.mechanism
rigid = model.scenes["lift_start_rigid"]
print("I_red =", mech.reduced_inertia(rigid))
print(f"I_red = {float(mech.reduced_inertia(rigid).subs(model.params)):.5f} kg m^2")
modes = md.natural_frequencies(mech, model.scenes["lift_start"], params=model.params)
print("natural frequencies of the elastic drive [Hz]:", modes.hz)

# %%
# Lifting from rest: elastic and rigid rope
# -----------------------------------------
elastic = mech.simulate(model.scenes["lift_start"], model.params)
stiff = mech.simulate(rigid, model.params)
print(elastic.summary(units={"speed": "rpm", "rope": "kN"}))
elastic.plot(units={"speed": "rpm", "rope": "kN"})

phi = mech.coordinates[0]
fig, ax = plt.subplots(figsize=(6.4, 3.4))
ax.plot(elastic.t, elastic[md.speed(phi)], label="elastic rope")
ax.plot(stiff.t, stiff[md.speed(phi)], "--", label="rigid rope")
ax.set_xlabel("time t [s]")
ax.set_ylabel("motor speed [rad/s]")
ax.set_title("Hoist drive: lifting from rest")
ax.legend()
fig.tight_layout()
plt.show()

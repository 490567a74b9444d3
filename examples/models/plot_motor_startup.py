"""
Induction motor start-up
========================

An induction motor with Kloss's characteristic drives a flywheel against a constant
load moment. One mechanism, two scenes with different effects: ``startup`` (motor and
load, from rest until 95 % of the steady speed) and ``braking`` (motor off, a shoe brake
on, from the steady speed to rest). The motor's characteristic against the load's
gives the steady operating point before anything is simulated.
"""

# %%
# The operating point
# -------------------
import matplotlib.pyplot as plt

import mechdyn as md

model = md.load_model("motor_startup")
mech = model.mechanism
curves = md.characteristic(mech, model.scenes["startup"], model.params)
print(curves.summary(units={"speed": "rpm"}))
curves.plot(units={"speed": "rpm"})
plt.show()

# %%
# Start-up
# --------
# The speed climbs slowly while the motor is far from its breakdown slip, then fast.
res = mech.simulate(model.scenes["startup"], model.params)
print(res.summary(units={"speed": "rpm", "power": "kW"}))
res.plot(units={"speed": "rpm", "power": "kW"})
plt.show()

# %%
# Braking
# -------
# The brake's moment ``M_b`` and the load's ``M_L`` are constant, so the drive stops
# in ``I_red omega / (M_b + M_L)``.
braking = mech.simulate(model.scenes["braking"], model.params)
print(braking.summary(units={"speed": "rpm"}))
inertia = float(mech.reduced_inertia().subs(model.params))
M_b, M_L = (float(model.params[model.param_symbol(name)]) for name in ("M_b", "M_L"))
omega = braking.at([0.0], md.speed(mech.coordinates[0]))[0]
print(f"time to rest: {braking.t_end:.4f} s, by hand {inertia * omega / (M_b + M_L):.4f} s")
plt.show()

"""
Lever against a hard stop
=========================

A constant moment swings a lever through a free angle onto an end stop that throws it
back with a coefficient of restitution ``e = 0.6``. It bounces ever lower, the bounces
a geometric series, until it rests on the stop, which then carries the moment. Each
impact is an event with its impulse and the kinetic energy it took.
"""

# %%
# Bouncing to rest
# ----------------
import math

import matplotlib.pyplot as plt

import mechdyn as md

model = md.load_model("hard_stop")
mech = model.mechanism
res = mech.simulate(model.scenes["bounce"], model.params)
print(res.summary())
J, M, theta_0, e = (float(model.params[model.param_symbol(n)]) for n in ("J", "M", "theta_0", "e"))
t_1 = math.sqrt(2 * J * theta_0 / M)
omega_1 = M * t_1 / J
impacts = [event for event in res.events if event.kind == "impact"]
print(f"first impact at t = {impacts[0].time:.6f} s (by hand {t_1:.6f} s), "
      f"impulse {impacts[0].value:.6f} (by hand {(1 + e) * J * omega_1:.6f})")
rest = next(event for event in res.events if event.kind == "contact")
print(f"{len(impacts)} impacts; resting on the stop from t = {rest.time:.6f} s "
      f"(by hand {t_1 + 2 * e * omega_1 * J / ((1 - e) * M):.6f} s)")
res.plot()
plt.show()

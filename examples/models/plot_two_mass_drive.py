"""
Two-mass drive
==============

A motor (``J_1``) drives a load (``J_2``) through an elastic shaft of stiffness ``k``
with a little damping ``c``. Switched on suddenly, the drive accelerates as one body
and the shaft rings at its natural frequency
``sqrt(k (J_1 + J_2) / (J_1 J_2))``; undamped, the shaft moment swings up to twice the
rigid value ``M J_2 / (J_1 + J_2)``. The scenes ``start``, ``start_undamped`` and
``start_rigid`` (the shaft made rigid) come from one declaration.
"""

# %%
# Natural frequencies
# -------------------
import math

import matplotlib.pyplot as plt

import mechdyn as md

model = md.load_model("two_mass_drive")
mech = model.mechanism
for equation in mech.equations().eqs:
    print(equation)
modes = md.natural_frequencies(mech, model.scenes["start"], params=model.params)
J1, J2, k = (float(model.params[model.param_symbol(n)]) for n in ("J_1", "J_2", "k"))
print("natural frequencies [Hz]:", modes.hz)
print(f"by hand: {math.sqrt(k * (J1 + J2) / (J1 * J2)) / (2 * math.pi):.4f} Hz")
print("damping ratios:", modes.damping_ratios)

# %%
# Start-up: elastic, undamped and rigid
# -------------------------------------
M = float(model.params[model.param_symbol("M")])
rigid_moment = M * J2 / (J1 + J2)
fig, ax = plt.subplots(figsize=(6.4, 3.6))
for scene, label in (("start", "elastic, damped"), ("start_undamped", "elastic, undamped")):
    res = mech.simulate(model.scenes[scene], model.params)
    print(f"{scene}: peak shaft moment {max(res['shaft']):.3f} N m")
    ax.plot(res.t, res["shaft"], label=label)
ax.axhline(rigid_moment, color="k", ls="--", label="rigid: M J_2 / (J_1 + J_2)")
ax.set_xlabel("time t [s]")
ax.set_ylabel("shaft moment [N m]")
ax.set_title("Two-mass drive: shaft moment after switching on")
ax.legend(loc="lower right")
fig.tight_layout()
rigid = mech.simulate(model.scenes["start_rigid"], model.params)
print(f"rigid: speed after {rigid.t_end:g} s {rigid.final(md.speed(mech.coordinates[0])):.4f}"
      f" rad/s, by hand {M / (J1 + J2) * rigid.t_end:.4f} rad/s")
plt.show()

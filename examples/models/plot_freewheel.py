"""
Freewheel
=========

A bicycle hub's overrunning clutch: the pedals drive the wheel through a freewheel
that lets the wheel run ahead but never behind. Pedalling for two seconds locks it,
and both accelerate together against the rolling resistance; then the rider stops
and the legs brake the pedals to a stop (in ``J_h omega_p / M_b``) while the
wheel overruns the freewheel and coasts, slowed by the rolling resistance alone.
"""

# %%
# A ride
# ------
import matplotlib.pyplot as plt

import mechdyn as md

model = md.load_model("freewheel")
mech = model.mechanism
res = mech.simulate(model.scenes["ride"], model.params)
print(res.summary())
for event in res.events:
    print(event)
p = {name: float(model.params[model.param_symbol(name)])
     for name in ("J_h", "J_w", "M_p", "t_p", "M_r")}
omega_p = (p["M_p"] - p["M_r"]) / (p["J_h"] + p["J_w"]) * p["t_p"]
phi_h, phi_w = mech.coordinates
coasting = omega_p - p["M_r"] / p["J_w"] * (res.t_end - p["t_p"])
print(f"speed when pedalling stops: {res.at([p['t_p']], md.speed(phi_w))[0]:.4f} rad/s, "
      f"by hand {omega_p:.4f} rad/s")
print(f"wheel at t = {res.t_end:g} s: {res.final(md.speed(phi_w)):.4f} rad/s, "
      f"by hand {coasting:.4f} rad/s")

res.plot()
plt.show()

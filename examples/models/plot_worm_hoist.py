"""
Worm hoist
==========

A motor turns a worm, the worm wheel turns a drum carrying a 200 kg load. The gear is
self-locking: its backward efficiency is zero, so the load can never drive the worm.
In the scene ``lift`` the motor lifts for one second and is switched off: the drive
coasts up, stops and stays locked, the gear holding the load. In ``lower`` the motor
must drive the worm backward, at its own pace whatever the load.
"""

# %%
# Lifting, coasting, holding
# --------------------------
import matplotlib.pyplot as plt

import mechdyn as md

model = md.load_model("worm_hoist")
mech = model.mechanism
res = mech.simulate(model.scenes["lift"], model.params)
print(res.summary())
print([(event.kind, round(event.time, 4)) for event in res.events])
print(f"held by the gear: loss moment {res.final('worm gear.loss'):.4f} N m")
res.plot()
plt.show()

# %%
# Lowering
# --------
# The load would overhaul the gear but cannot drive the worm: the motor's angle
# follows ``phi_m'' = -M_low / J_m``.
lower = mech.simulate(model.scenes["lower"], model.params)
phi_m = mech.coordinates[0]
J_m, M_low = (float(model.params[model.param_symbol(n)]) for n in ("J_m", "M_low"))
print(f"motor speed after {lower.t_end:g} s: {lower.final(md.speed(phi_m)):.4f} rad/s, "
      f"by hand {-M_low / J_m * lower.t_end:.4f} rad/s")
plt.show()

"""
Gear pair
=========

Gear 1 (``z_1`` teeth, inertia ``J_1``) is driven by the moment ``M_1`` and meshes with
gear 2 (``z_2``, ``J_2``), which a moment ``M_2`` resists. Reduced to gear 1 the pair is
one wheel of inertia ``J_1 + J_2 (z_1/z_2)^2`` under ``M_1 - M_2 z_1/z_2``: both
constant, so the scene ``startup`` accelerates uniformly from rest.
"""

# %%
# The derivation
# --------------
import matplotlib.pyplot as plt

import mechdyn as md

model = md.load_model("gear_pair")
mech = model.mechanism
print("I_red =", mech.reduced_inertia())
print("M_red =", mech.reduced_moment())
inertia = float(mech.reduced_inertia().subs(model.params))
moment = float(mech.reduced_moment().subs(model.params))
print(f"with the default values: I_red = {inertia:g} kg m^2, M_red = {moment:g} N m, "
      f"eps_1 = {moment / inertia:g} rad/s^2")

# %%
# Start-up
# --------
res = mech.simulate(model.scenes["startup"], model.params)
print(res.summary())
phi_1 = mech.coordinates[0]
print(f"speed after {res.t_end:g} s: {res.final(md.speed(phi_1)):.6g} rad/s "
      f"(eps_1 t = {moment / inertia * res.t_end:.6g})")
res.plot()
plt.show()

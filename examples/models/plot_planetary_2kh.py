"""
Planetary 2K-H train
====================

A planetary train with sun 1 driving, planets 2 and 3 on one shaft and the carrier H
carrying the load moment ``M_H``. Willis' formula gives the speed ratios
(``omega_H / omega_1 = -1/3``, ``omega_2 / omega_1 = -1``), which the declaration writes
as the links' angles; mechdyn reduces the train to the sun. The default drive moment is
the textbook's 21.76 N m, which brings the sun to 600 rpm in 3 s.
"""

# %%
# Reduced to the sun
# ------------------
import matplotlib.pyplot as plt
import sympy as sp

import mechdyn as md

model = md.load_model("planetary_2kh")
mech = model.mechanism
print("I_red =", mech.reduced_inertia())
print("M_red =", mech.reduced_moment())
M_1 = model.param_symbol("M_1")
others = {s: v for s, v in model.params.items() if s != M_1}
print(f"I_red = {float(mech.reduced_inertia().subs(others)):.4g} kg m^2")
least = sp.solve(mech.reduced_moment().subs(others), M_1)[0]
print(f"least moment that starts the train: M_1 = {float(least):.4g} N m")

# %%
# Start-up
# --------
res = mech.simulate(model.scenes["startup"], model.params)
print(res.summary(units={"speed": "rpm"}))
res.plot(units={"speed": "rpm"})
plt.show()

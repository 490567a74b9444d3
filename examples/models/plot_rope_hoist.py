"""
Rope hoist with two shafts
==========================

A motor moment that grows with time, ``M = 4200 + 200 t`` N m, turns shaft 1, which
drives shaft 2 through a belt without slip; the drum on shaft 2 lifts a 400 kg load
against a resisting moment. With the coordinate on shaft 2, the reduced inertia is
constant and the reduced moment a function of time (the textbook's case 2): the
angular acceleration is linear in ``t``.
"""

# %%
# Reduced to shaft 2
# ------------------
import matplotlib.pyplot as plt
import sympy as sp

import mechdyn as md

model = md.load_model("rope_hoist")
mech = model.mechanism
print("I_red =", mech.reduced_inertia())
print("M_red =", mech.reduced_moment())
eps = sp.expand((mech.reduced_moment() / mech.reduced_inertia()).subs(model.params))
print("eps_2(t) =", sp.N(eps, 6), "rad/s^2")

# %%
# Start-up
# --------
# Shaft 2 starts at 3 rad/s; the load rises by ``r_2 phi_2``.
res = mech.simulate(model.scenes["startup"], model.params)
print(res.summary())
res.plot()
plt.show()

"""
Cam with a translating follower
===============================

A cam (inertia ``J_1A``) lifts a follower (mass ``m_2``) by the uniform-velocity law
``s = h phi / Phi``: the follower rises ``h`` while the cam turns ``Phi``. A constant
transmission function ``h / Phi`` makes the reduced inertia and moment constant. The
scene ``rise`` starts the cam from rest under the moment ``M_1`` against the follower
force ``F_2`` and stops at the end of the rise.
"""

# %%
# The derivation
# --------------
import matplotlib.pyplot as plt

import mechdyn as md

model = md.load_model("cam_follower")
mech = model.mechanism
derivation = mech.derivation()
for name, definition in derivation.quantities.items():
    print(f"{name} = {definition}")
print("I_red =", derivation.reduced_inertia)
print("M_red =", derivation.reduced_moment)
print("equation of motion:", mech.equations().eqs[0])

# %%
# The rise
# --------
# Uniformly accelerated: the rise of ``Phi = pi/2`` takes ``sqrt(2 Phi I_red / M_red)``.
inertia = float(mech.reduced_inertia().subs(model.params))
moment = float(mech.reduced_moment().subs(model.params))
res = mech.simulate(model.scenes["rise"], model.params)
print(res.summary())
print(f"time of the rise: simulated {res.t_end:.6f} s, "
      f"by hand {(2 * 3.141592653589793 / 2 * inertia / moment) ** 0.5:.6f} s")
res.plot()
plt.show()

"""
Scotch yoke
===========

The sine mechanism: a crank of length ``l`` drives a slotted yoke whose position is
``x = l cos(phi)``. The yoke's mass enters the reduced inertia with the square of the
transmission function, ``J_1A + m_3 l^2 sin^2(phi)``, so the inertia and the moment of
the resisting force both vary with the crank angle (the textbook's case 3 without the
drive's moment depending on speed). The scene ``startup`` runs the crank up from rest
under a constant moment and records the drive's power.
"""

# %%
# The derivation, as a textbook writes it
# ---------------------------------------
import matplotlib.pyplot as plt
import numpy as np
import sympy as sp

import mechdyn as md

model = md.load_model("scotch_yoke")
mech = model.mechanism
derivation = mech.derivation()
for name, definition in derivation.quantities.items():
    print(f"{name} = {definition}")
print("I_red =", derivation.reduced_inertia)
print("dI_red/dphi =", derivation.reduced_inertia_slope)
print("M_red =", derivation.reduced_moment)
print("in the crank angle:", mech.equations().textbook_equation)

# %%
# The reduced inertia over a turn
# -------------------------------
phi = md.plain(mech.coordinates[0])
inertia = sp.lambdify(phi, mech.reduced_inertia().subs(model.params))
angles = np.linspace(0, 2 * np.pi, 361)
fig, ax = plt.subplots(figsize=(6.4, 3.4))
ax.plot(np.degrees(angles), inertia(angles))
ax.set_xlabel("crank angle phi [deg]")
ax.set_ylabel("I_red [kg m^2]")
ax.set_title("Scotch yoke: reduced inertia")
ax.set_xticks(range(0, 361, 90))
fig.tight_layout()

# %%
# Start-up from rest
# ------------------
res = mech.simulate(model.scenes["startup"], model.params)
print(res.summary())
res.plot()
plt.show()

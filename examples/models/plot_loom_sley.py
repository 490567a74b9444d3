"""
Loom sley drive
===============

The sley (batten) of a loom, driven by two cranks on one crankshaft, with its two
most compliant parts elastic: the crankshaft's torsion between the cranks (``phi_2``)
and the sley beam's bending between its swords (masses 3 and 4, ``x_3``, ``x_4``). The
crank turns at an imposed 250 rpm, so the three coordinates obey a linear system with
coefficients periodic in time. Its periodic steady state is found directly, by
shooting, and checked with its Floquet multipliers.
"""

# %%
# The periodic steady state
# -------------------------
import matplotlib.pyplot as plt

import mechdyn as md

model = md.load_model("loom_sley")
mech = model.mechanism
steady = md.periodic_steady_state(mech, model.scenes["run"], model.params)
print(steady)
print("Floquet:", steady.floquet.verdict)
amplitudes = steady.amplitudes()
print(f"torsion amplitude {amplitudes['phi_2']:.4f} rad (reported 0.0037), "
      f"its rate {amplitudes['phidot_2']:.3f} 1/s (0.24), "
      f"acceleration {amplitudes['phiddot_2']:.1f} 1/s^2 (15.4)")
print(f"masses 3 and 4: amplitudes {amplitudes['x_3']:.4f} m, {amplitudes['x_4']:.4f} m "
      "(the crank radius, 0.08 m: they follow the rigid law)")
steady.result.plot()
plt.show()

# %%
# The run from rest
# -----------------
# Ten turns started at the back dead centre, at rest: the start-up transient dies out
# within a few turns, leaving the periodic motion above.
res = mech.simulate(model.scenes["run"], model.params)
print(res.summary())
phi_2 = mech.coordinates[0]
fig, ax = plt.subplots(figsize=(6.4, 3.4))
ax.plot(res.t, 1e3 * res[phi_2])
ax.set_xlabel("time t [s]")
ax.set_ylabel("crankshaft torsion phi_2 [mrad]")
ax.set_title("Loom sley: torsion of the crankshaft from rest")
fig.tight_layout()
plt.show()

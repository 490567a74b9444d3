"""
Crank press duty cycle
======================

The press of the flywheel example with a shoe brake on the flywheel shaft, run through
a whole duty cycle: ``startup`` from rest to 95 rpm, ten seconds of ``steady`` working
strokes, ``braking`` to rest and two seconds of ``hold`` against the ram's weight. Each
phase starts where the one before ended; the cycle's summary keeps the energy books
of every phase.
"""

# %%
# The cycle
# ---------
import matplotlib.pyplot as plt

import mechdyn as md

model = md.load_model("press_cycle")
cycle = md.duty_cycle(model, "startup+steady+braking+hold")
print(cycle.summary(units={"speed": "rpm", "power": "kW"}))

# %%
# Braking
# -------
# Hand estimate: ``I_red`` is about 344 kg m^2, so the brake's 15 * 80 N m stops the
# crank from 10 rad/s in about 2.9 s.
braking = cycle.phase("braking")
print(f"braking: {braking.end - braking.start:.3f} s, "
      f"brake work {braking.energy.work['brake'] / 1e3:.2f} kJ")
cycle.plot(units={"speed": "rpm", "power": "kW", "workpiece": "kN"})
plt.show()

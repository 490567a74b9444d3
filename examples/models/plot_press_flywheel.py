"""
Crank press with a flywheel
===========================

An induction motor and a flywheel on a fast shaft, geared 15 : 1 to the crankshaft of
a slider-crank press. Over 60 degrees before the bottom dead centre the workpiece
resists with up to 60 kN, so the crank slows during each stroke and the motor and the
flywheel make it up between strokes. The questions of a designer: the steady cycle,
its coefficient of speed fluctuation, and the flywheel that keeps it to 1/50.
"""

# %%
# The reduced inertia and moment
# ------------------------------
import matplotlib.pyplot as plt

import mechdyn as md

model = md.load_model("press_flywheel")
mech = model.mechanism
derivation = mech.derivation()
print("I_red =", derivation.reduced_inertia)
print("M_red =", derivation.reduced_moment)

# %%
# Steady running
# --------------
# A periodic solution in the crank angle: the speed at the top dead centre that
# comes back after a turn, and its stability.
running = md.steady_running(mech, model.scenes["steady"], model.params)
print(running.summary())
running.plot()
plt.show()

# %%
# The flywheel for delta = 1/50
# -----------------------------
# ``md.flywheel`` solves delta(J_f) = 1/50 and gives the textbook's
# ``J = Delta E_max / (delta omega_mean^2)`` beside it.
sized = md.flywheel(mech, model.scenes["steady"], model.params, delta=1 / 50,
                    inertia=model.param_symbol("J_f"))
print(sized)

# %%
# Twenty seconds of working strokes
# ---------------------------------
res = mech.simulate(model.scenes["steady"], model.params)
print(res.summary(units={"speed": "rpm", "workpiece": "kN"}))
res.plot(units={"speed": "rpm", "workpiece": "kN"})
plt.show()

"""
Shoe brake
==========

A disc braked to rest by a shoe (worked example 1): 50 s, 2500 rad.
"""
# %%
import mechdyn as md

brake = md.load_model("shoe_brake")
res = brake.mechanism.simulate(brake.scenes["braking"], brake.params)
print(res.summary())
res.plot()

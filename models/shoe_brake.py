"""Shoe brake (worked example 1): a disc braked by a lever-pressed shoe.

The lever doubles the shoe force P, so the friction moment is f * 2P * R.
Braking from 100 rad/s stops the disc after 50 s and 2500 rad.
"""
import sympy as sp

import mechdyn as md

phi = md.coordinate("phi")
I, f, P, R = sp.symbols("I f P R", positive=True)

mechanism = md.Mechanism("Shoe brake", coordinates=[phi],
                         units={I: "kg*m^2", f: "1", P: "N", R: "m"})
mechanism.link("disc", J=I, angle=phi)
mechanism.friction("shoe", f * 2 * P * R, along=phi, tags=["brake"])

params = {I: 0.4, f: 0.2, P: 20, R: 0.1}

scenes = {
    "braking": md.Scene("braking", effects=["shoe"], initial={phi: 0, md.speed(phi): 100},
                        until=md.stopped(phi)),
}

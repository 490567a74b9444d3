"""Long tables: a lookup node against the Piecewise of one line per segment.

    python benchmarks/tables.py [--points 50 200 500] [--lookup-only 2000 20000]

A motor curve ``M(omega)`` of n measured points drives a rotor (J = 0.1 kg m^2, the
curve 10 - 0.04 omega, so omega(5 s) = 250 (1 - e^-2) exactly). For each n: the time to
build the moment expression, to derive, generate and run the scene (scipy backend, no
disk cache), and the final speed's error, for the lookup mechdyn uses beyond 16 points
and for the Piecewise it uses for short tables (the obvious alternative, and what every
table was before). Larger n run only as lookups (the Piecewise takes minutes there).
"""
from __future__ import annotations

import argparse
import math
import os
import time

os.environ.setdefault("MECHDYN_CACHE", "off")

import numpy as np  # noqa: E402

import mechdyn as md  # noqa: E402


def measure(points, piecewise):
    speeds = np.linspace(0, 400, points)
    curve = md.table(speeds, 10 - 0.04 * speeds, name=f"curve{points}{piecewise}")
    if piecewise:
        curve.points = None                       # force the per-segment Piecewise
    phi = md.coordinate("phi")
    started = time.perf_counter()
    moment = curve(md.speed(phi))
    built = time.perf_counter() - started
    mech = md.Mechanism(f"motor {points} {piecewise}", [phi])
    mech.link("rotor", J=0.1, angle=phi)
    mech.load("motor", moment, along=phi)
    scene = md.Scene("startup", initial={phi: 0, md.speed(phi): 0}, t_end=5,
                     backend="scipy")
    started = time.perf_counter()
    result = mech.simulate(scene, {})
    ran = time.perf_counter() - started
    error = abs(result.final(md.speed(phi)) / (250 * (1 - math.exp(-2))) - 1)
    return built, ran, error


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, nargs="*", default=[50, 200, 500])
    parser.add_argument("--lookup-only", type=int, nargs="*", default=[2000, 20000])
    args = parser.parse_args()
    measure(20, False)                            # imports and first calls, not shown
    print(f"{'points':>7} {'kind':>9} {'build s':>9} {'derive+run s':>13} {'rel. error':>11}")
    for points in args.points + args.lookup_only:
        kinds = ["lookup"] + (["Piecewise"] if points in args.points else [])
        for kind in kinds:
            built, ran, error = measure(points, kind == "Piecewise")
            print(f"{points:>7} {kind:>9} {built:>9.3f} {ran:>13.2f} {error:>11.1e}")


if __name__ == "__main__":
    main()

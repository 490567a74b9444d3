"""Cost of exact sensitivities for 10 parameters against finite differences.

    python benchmarks/sensitivities.py [--repeats 3]

Two cases on the crank press (models/press_flywheel.py), 10 parameters:

* a run: the scene ``steady`` cut to 2 s, measures ``final:phi`` and ``final:phidot``.
  ``md.sensitivities`` (one integration of the state with its 10 x 2 sensitivities: the
  kernels' DOP853 on the generated numba functions; ``backend="scipy"``: scipy's DOP853
  on lambdified functions) against one ``simulate`` (compiled kernels; scipy backend)
  and central differences (21 simulate runs on the compiled kernels);
* steady running: ``mean_speed`` and ``fluctuation``. ``md.sensitivities`` (steady
  running, a polish of its speed and one cycle with the sensitivities) against one
  ``md.steady_running`` and central differences (21 steady_running solves).

Wall time, the shortest of ``--repeats`` (the machine is shared); everything is derived
and compiled before the first timing (the sensitivities' lambdified functions are kept
in the mechanism's memo, as in a loop of an optimiser). The last column is the largest
difference between the exact derivatives and the central differences (step 1e-4
relative, 1e-3 for steady running), relative to the measure's largest derivative: a
check, not an accuracy figure (the differences carry the solvers' tolerance divided by
the step: steady running's d mean_speed / d J_m and d J_f, equal by I_red = J_c + (J_m +
J_f) i^2, come out 9 % apart by differences, identical exactly).
"""
from __future__ import annotations

import argparse
import dataclasses
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

import mechdyn as md  # noqa: E402
from peer_models import timed  # noqa: E402  (benchmarks/: the best of repeated calls)

WRT = ["r", "l", "m_r", "J_c", "J_m", "J_f", "M_k", "s_k", "omega_s", "F_p"]


def central(measure, params, h=1e-4):
    """Central differences of ``measure(params) -> array`` in every parameter of WRT."""
    columns = []
    for name in WRT:
        step = h * params[name]
        up = measure({**params, name: params[name] + step})
        down = measure({**params, name: params[name] - step})
        columns.append((up - down) / (2 * step))
    return np.array(columns).T


def row(case, exact_time, one_time, one_label, fd_time, exact, fd):
    scale = np.max(np.abs(fd), axis=1, keepdims=True)      # per measure
    worst = float(np.max(np.abs(exact - fd) / scale))
    print(f"| {case} | {exact_time * 1e3:.1f} | {one_label} {one_time * 1e3:.1f} | "
          f"{exact_time / one_time:.1f}x | {fd_time * 1e3:.1f} ({fd_time / exact_time:.1f}x "
          f"the exact) | {worst:.1e} |")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    repeats = parser.parse_args().repeats
    press = md.load_model(ROOT / "models" / "press_flywheel.py")
    mech = press.mechanism
    params = {str(k): float(v) for k, v in press.params.items()}
    run = dataclasses.replace(press.scenes["steady"], t_end=2.0)
    steady = press.scenes["steady"]
    measures = ["final:phi", "final:phidot"]

    def simulate(values, backend="auto"):
        result = mech.simulate(dataclasses.replace(run, backend=backend), values)
        return np.array([result.final("phi"), result.final("phidot")])

    def running(values):
        found = md.steady_running(mech, steady, values)
        return np.array([found.omega_mean, found.delta])

    print("| case (10 parameters) | exact sensitivities ms | one run ms | exact / one run "
          "| central differences ms | largest difference (of the largest derivative) |")
    print("|---|---|---|---|---|---|")
    md.sensitivities(mech, run, params, WRT, measures)          # derived and lambdified
    simulate(params), simulate(params, "scipy")                  # compiled
    exact_time, exact = timed(lambda: md.sensitivities(mech, run, params, WRT, measures),
                              repeats)
    compiled_time, _ = timed(lambda: simulate(params), repeats)
    scipy_time, _ = timed(lambda: simulate(params, "scipy"), repeats)
    fd_time, fd = timed(lambda: central(simulate, params), 1)
    row("run, 2 s", exact_time, compiled_time, "compiled", fd_time, exact.gradients, fd)
    md.sensitivities(mech, run, params, WRT, measures, backend="scipy")
    lambdified_time, lambdified = timed(
        lambda: md.sensitivities(mech, run, params, WRT, measures, backend="scipy"), repeats)
    row("run, 2 s, backend='scipy'", lambdified_time, scipy_time, "scipy", fd_time,
        lambdified.gradients, fd)
    cycle_measures = ["mean_speed", "fluctuation"]
    md.sensitivities(mech, steady, params, WRT, cycle_measures)
    exact_time, exact = timed(
        lambda: md.sensitivities(mech, steady, params, WRT, cycle_measures), repeats)
    one_time, _ = timed(lambda: running(params), repeats)
    fd_time, fd = timed(lambda: central(running, params, h=1e-3), 1)
    row("steady running", exact_time, one_time, "steady_running", fd_time, exact.gradients,
        fd)


if __name__ == "__main__":
    main()

"""The accuracy asked for is the accuracy delivered (issue 27 item 4).

The slider-crank of models/slider_crank.py run 0-5 s from rest, at the defaults (method
"auto"), is compared at rtol 1e-8 with the same run at rtol 1e-12; every bundled scene's
global error (largest deviation of any state over the run, relative to that state's
largest size) falls as the tolerance tightens from 1e-4 to 1e-10. The reference of a
scipy run is the compiled kernels' DOP853 at rtol 1e-12 and the reference of a compiled
run is scipy's, two implementations checked against each other by the test; both were
checked once against Radau at rtol 1e-12 (agreement 6e-13 ... 4e-11 on the slider-crank,
the flywheel press, the loom, the Watt six-bar, the hoist and the toggle press).
"""
import dataclasses
import glob
import math
from pathlib import Path

import numpy as np
import pytest
import sympy as sp
from scipy.special import ellipk

import mechdyn as md

ROOT = Path(__file__).resolve().parents[1]
BACKENDS = ["scipy", "compiled"]
ROUNDING = 1e-12        # a global error this small is exact to rounding: nothing to gain


def crank_speed_at_5_s(rtol, backend):
    model = md.load_model(ROOT / "models" / "slider_crank.py")
    phi = model.mechanism.coordinates[0]
    scene = md.Scene("from rest", initial={phi: 0, md.speed(phi): 0}, t_end=5.0, rtol=rtol,
                     atol=rtol * 1e-2)
    return model.mechanism.simulate(scene, model.params, backend=backend).final(
        md.speed(phi))


@pytest.mark.slow
@pytest.mark.parametrize("backend", BACKENDS)
def test_slider_crank_from_rest_at_rtol_1e_8_is_within_1e_5_of_the_tight_run(backend):
    # The crank angle grows to 456 rad; it was weighed relative to its size (80 times
    # the phase error allowed per step) and DOP853's blended estimate accepted steps 10
    # times over the tolerance: the speed was off by 6.8e-4 on scipy.
    tight = crank_speed_at_5_s(1e-12, backend)
    assert 100 < tight < 103                       # near omega_0 = 100 rad/s, rippling
    assert crank_speed_at_5_s(1e-8, backend) == pytest.approx(tight, rel=1e-5)


@pytest.mark.parametrize("backend", BACKENDS)
def test_whirling_pendulum_makes_its_revolutions_in_the_time_the_quadrature_gives(backend):
    # A pendulum (l = 1, g = 9.81) swung over the top (phi' = w0 = 7 at phi = 0) keeps
    # w^2 = w0^2 - 4 g sin^2(phi/2); one revolution takes T = int_0^2pi dphi / w =
    # (4 / w0) K(m), m = 4 g / w0^2 (complete elliptic integral, scipy's ellipk(m)). Its
    # angle grows to 628 rad in 100 revolutions: the time it reaches them is 100 T to
    # the tolerance asked for, and closer the tighter it is.
    phi = md.coordinate("phi")
    mech = md.Mechanism("pendulum", [phi])
    mech.link("bob", m=1, x=sp.sin(phi), y=-sp.cos(phi))
    mech.gravity(9.81)
    period = 4 / 7.0 * ellipk(4 * 9.81 / 7.0 ** 2)
    errors = []
    for rtol in (1e-6, 1e-8, 1e-10):
        scene = md.Scene("whirl", initial={phi: 0, md.speed(phi): 7.0}, t_end=300 * period,
                         until=md.reaches(phi, 200 * math.pi), rtol=rtol, atol=rtol * 1e-2)
        errors.append(abs(mech.simulate(scene, {}, backend=backend).t_end / (100 * period)
                          - 1))
    assert errors[0] > errors[1] > errors[2], errors
    assert errors[2] < 1e-10, errors


def _scenes():
    for path in sorted(glob.glob(str(ROOT / "models" / "*.py"))):
        model = md.load_model(path)
        for name, scene in model.scenes.items():
            if scene.initial:                      # later phases of a duty cycle need one
                yield pytest.param(path, name, id=f"{Path(path).stem}:{name}")


def _global_error(run, reference, times):
    values = np.array(list(run.at(times).values()))
    exact = np.array(list(reference.at(times).values()))
    scale = np.maximum(np.abs(exact).max(axis=1, keepdims=True), 1e-3)
    return float(np.max(np.abs(values - exact) / scale))


@pytest.mark.slow
@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("path, name", list(_scenes()))
def test_global_error_falls_as_the_tolerance_tightens(path, name, backend):
    model = md.load_model(path)
    scene = model.scenes[name]

    def run(rtol, on, method=None):
        options = {"rtol": rtol, "atol": rtol * 1e-2} | ({"method": method} if method else {})
        return model.mechanism.simulate(dataclasses.replace(scene, **options), model.params,
                                        backend=on)
    other = "compiled" if backend == "scipy" else "scipy"
    reference = run(1e-12, other, "DOP853")
    times = np.linspace(reference.t[0], reference.t_end, 201)
    assert _global_error(run(1e-12, backend, "DOP853"), reference, times) < 1e-9
    errors = []
    span = reference.t_end - reference.t[0]
    for rtol in (1e-4, 1e-6, 1e-8, 1e-10):
        result = run(rtol, backend)                # a stop condition's time is a result
        common = times[times <= min(result.t_end, reference.t_end)]
        errors.append(max(_global_error(result, reference, common),
                          abs(result.t_end - reference.t_end) / span))
    for looser, tighter in zip(errors, errors[1:]):
        assert tighter < looser or tighter < ROUNDING, errors
    assert errors[-1] < 1e-6, errors

"""Differential tests on generated planar mechanisms (issue 38): each drawn mechanism
(tests/mechanisms_strategies.py) is compared with an independent route on the same
declaration — its equations with sympy.physics.mechanics' ``LagrangesMethod``, its
trajectory on both backends with ``LagrangesMethod`` lambdified and integrated by
``solve_ivp``, the reduced quantities of one-DOF ones with the kinetic energy and the
loads' power written out here, a sweep with a loop over ``simulate``, and
``MECHDYN_CACHE=off`` with the cache on. A mechanism either runs or is refused with a
named :class:`md.MechdynError`; a bare TypeError fails.

Hypothesis profiles (tests/conftest.py): ``ci``, the default, runs a fixed set of
examples (derandomized: a failure reproduces) in well under a minute; ``deep`` runs
2000 examples of the symbolic comparisons and 200 of the trajectories:

    python -m pytest -q tests/test_differential.py --hypothesis-profile=deep
"""
import os
import pickle
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import sympy as sp
from hypothesis import HealthCheck, assume, event, given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp

import mechdyn as md
from mechanisms_strategies import (G, Z, build, kloss, lagranges, mechanisms, reference_rhs,
                                   states)

DEEP = settings.default.max_examples >= 1000


def examples(ci, deep):
    return settings(max_examples=deep if DEEP else ci,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large,
                                           HealthCheck.filter_too_much])


def _numeric(matrix, symbols, values, params):
    f = sp.lambdify(symbols, sp.Matrix(matrix).xreplace(params), "numpy")
    return np.array(f(*values), dtype=float)


def _sizes(matrix, symbols, values, params):
    """The sum of the absolute values of each entry's terms: the scale its rounding
    and any cancellation between terms are measured against."""
    matrix = sp.Matrix(matrix).xreplace(params)
    sums = matrix.applyfunc(lambda e: sum(abs(a) for a in sp.Add.make_args(e)))
    return _numeric(sums, symbols, values, {})


@examples(ci=20, deep=2000)
@given(mechanisms(), st.data())
def test_equations_equal_lagranges_method(spec, data):
    position, speed = data.draw(states(spec.n))
    mech, _ = build(spec)
    mass_ref, forcing_ref, W = lagranges(spec)
    ref_args, values = list(Z[:spec.n]) + list(W), position + speed
    try:
        eqs = mech.equations()
    except md.DerivationError as error:       # refused: singular at every state
        event("refused: " + str(error).split(":")[1].strip()[:40])
        assert "singular" in str(error) or "no inertia" in str(error)
        assert abs(np.linalg.det(_numeric(mass_ref, ref_args, values, {}))) < 1e-9
        return
    args = list(eqs.q) + list(eqs.u)
    for ours, theirs in ((eqs.mass_matrix, mass_ref), (eqs.forcing, forcing_ref)):
        got, want = _numeric(ours, args, values, spec.params), _numeric(theirs, ref_args,
                                                                        values, {})
        # 1e-10 of the terms' size: the routes sum different terms, which may cancel
        scale = np.maximum(_sizes(theirs, ref_args, values, {}), 1.0)
        assert np.all(np.abs(got - want) <= 1e-10 * scale), (got, want)


@examples(ci=15, deep=2000)
@given(mechanisms(max_dof=1), st.floats(-1.0, 1.0), st.floats(-2.0, 2.0))
def test_reduced_quantities_equal_energy_and_power(spec, angle, omega):
    mech, _ = build(spec)
    try:
        eqs = mech.equations()
    except md.DerivationError:
        return                                # a bare slider may move no inertia
    z, (q, u) = Z[0], (eqs.q[0], eqs.u[0])
    inertia = sum(sp.sympify(m) * (sp.diff(x, z) ** 2 + sp.diff(y, z) ** 2)
                  + sp.sympify(J) * sp.diff(a, z) ** 2 for _, m, J, x, y, a in spec.links)
    power = sum(value * sp.diff(along, z) * omega for value, along in spec.loads)
    power -= sum(k * s * sp.diff(s, z) * omega for k, s in spec.springs)
    power -= sum(c * (sp.diff(s, z) * omega) ** 2 for c, s in spec.dampers)
    if spec.gravity:
        power -= sum(G * sp.sympify(m) * sp.diff(y, z) * omega for _, m, _, _, y, _ in spec.links)
    if spec.motor is not None:
        power += kloss(*spec.motor, omega) * omega
    at = {z: angle} | spec.params
    want_inertia = float(sp.sympify(inertia).xreplace(at))
    want_power = float(sp.sympify(power).xreplace(at))
    ours = {q: angle, u: omega} | spec.params
    assert float(mech.reduced_inertia().xreplace(ours)) == pytest.approx(want_inertia,
                                                                         rel=1e-10)
    kinetic = float(eqs.kinetic_energy.xreplace(ours))
    assert kinetic == pytest.approx(want_inertia * omega ** 2 / 2, rel=1e-10, abs=1e-12)
    moment = float(mech.reduced_moment().xreplace(ours))
    scale = abs(want_power) + abs(moment * omega) + 1e-9
    assert abs(moment * omega - want_power) <= 1e-10 * scale


def _derives(mech) -> bool:
    try:
        mech.equations()
    except md.DerivationError:          # no inertia in a coordinate: refused, named
        return False
    return True


def _run(mech, coords, spec, y0, backend, t_end, rtol):
    initial = dict(zip(coords, y0[:spec.n])) | {md.speed(q): v for q, v
                                                in zip(coords, y0[spec.n:])}
    scene = md.Scene("run", initial=initial, t_end=t_end, rtol=rtol, atol=rtol,
                     backend=backend)
    try:
        return mech.simulate(scene, spec.params).y[:, -1]
    except md.SimulationError as error:       # named: its class is the outcome
        return type(error).__name__


@examples(ci=3, deep=200)
@given(mechanisms(), st.data())
def test_trajectories_of_both_backends_equal_lagranges_method(spec, data):
    position, speed = data.draw(states(spec.n))
    mech, coords = build(spec)
    try:
        mech.equations()
    except md.DerivationError:
        return
    y0, t_end, rtol = np.array(position + speed), 0.5, 1e-10
    reference = solve_ivp(reference_rhs(spec), (0, t_end), y0, method="DOP853",
                          rtol=1e-13, atol=1e-13)
    outcomes = [_run(mech, coords, spec, y0, backend, t_end, rtol)
                for backend in ("compiled", "scipy")]
    event(f"{spec.n} DOF: " + " / ".join(o if isinstance(o, str) else "ran" for o in outcomes))
    if any(isinstance(o, str) for o in outcomes):
        assert outcomes[0] == outcomes[1], outcomes    # both refuse, for the same reason
        return
    assert reference.status == 0, "mechdyn ran where the reference failed"
    want = reference.y[:, -1]
    # a global error of a few hundred times the local tolerance over half a second
    for got in outcomes:
        assert np.allclose(got, want, rtol=1e-7, atol=1e-7), (got, want)


@examples(ci=1, deep=20)
@given(mechanisms(max_dof=2, motor=False))
def test_sweep_equals_a_loop_over_simulate_with_a_dependent_parameter(spec):
    mech, coords = build(spec)
    assume(_derives(mech))
    assume(len(spec.params) >= 2)
    swept, dependent = sorted(spec.params, key=str)[:2]
    params = dict(spec.params) | {dependent: swept / 2}
    initial = {q: 0.2 for q in coords} | {md.speed(q): 0.5 for q in coords}
    scene = md.Scene("run", initial=initial, t_end=0.3)
    values = [0.5, 1.5]
    table = md.sweep(mech, scene, params, {swept: values}, progress=False)
    for row, value in enumerate(values):
        looped = mech.simulate(scene, params | {swept: value, dependent: value / 2})
        for q in coords:
            assert table[f"final:{q.func.__name__}"][row] == looped.final(q)


_CHILD = """
import pickle, sys
sys.path.insert(0, sys.argv[1])
from mechanisms_strategies import build
import mechdyn as md
spec, y0 = pickle.load(open(sys.argv[2], "rb"))
mech, coords = build(spec)
initial = dict(zip(coords, y0[:spec.n])) | {md.speed(q): v for q, v in zip(coords, y0[spec.n:])}
res = mech.simulate(md.Scene("run", initial=initial, t_end=0.5, backend="scipy"), spec.params)
print(repr(res.y[:, -1].tolist()))
"""


@examples(ci=1, deep=20)
@given(spec=mechanisms(max_dof=2))
def test_cache_off_in_a_fresh_process_equals_the_cache_on(spec, tmp_path_factory):
    mech, coords = build(spec)
    assume(_derives(mech))
    y0 = [0.1] * spec.n + [0.3] * spec.n
    initial = dict(zip(coords, y0[:spec.n])) | {md.speed(q): v for q, v
                                                in zip(coords, y0[spec.n:])}
    here = mech.simulate(md.Scene("run", initial=initial, t_end=0.5, backend="scipy"),
                         spec.params).y[:, -1]
    path = tmp_path_factory.mktemp("spec") / "spec.pkl"
    path.write_bytes(pickle.dumps((spec, y0)))
    child = subprocess.run([sys.executable, "-c", _CHILD, str(Path(__file__).parent),
                            str(path)], capture_output=True, text=True, timeout=120,
                           env=os.environ | {"MECHDYN_CACHE": "off"})
    assert child.returncode == 0, child.stderr
    assert eval(child.stdout.strip().splitlines()[-1]) == here.tolist()

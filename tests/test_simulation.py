"""Simulation of the worked examples against their hand-worked closed forms, compiled
code against exact sympy evaluation, and effect selection."""
import dataclasses
import math

import numpy as np
import pytest
import sympy as sp

import mechdyn as md


def load(name):
    return md.load_model(f"models/{name}.py")


def test_shoe_brake_stops_at_50_s_after_2500_rad():
    # omega(t) = omega0 - (f 2P R / I) t: stops at I omega0 / (2 f P R) = 0.4*100/0.8 = 50 s,
    # phi_stop = omega0^2 I / (2 * 0.8) = 2500 rad.
    model = load("shoe_brake")
    phi = model.mechanism.coordinates[0]
    res = model.mechanism.simulate(model.scenes["braking"], model.params)
    assert res.t_end == pytest.approx(50.0, rel=1e-9)
    assert res.final(phi) == pytest.approx(2500.0, rel=1e-9)
    assert res.final(md.speed(phi)) == 0.0
    assert res.reason == "stopped(phi)"
    assert res.final(phi) / (2 * math.pi) == pytest.approx(397.9, abs=0.05)


def test_rope_hoist_follows_the_closed_form_polynomials():
    # Worked example 6: eps2 = (M R1 R2 - (G3 r2 + Mc) R1^2) / (I1 R2^2 + I_red2 R1^2)
    # with M = 4200 + 200 t, integrated twice from omega2(0) = 3, phi2(0) = 0.
    R1, R2, r2, I1, I2 = 0.6, 0.4, 0.2, 8.0, 150 * 0.3**2 + 400 * 0.2**2
    G3, Mc = 400 * 9.81, 2000.0
    den = I1 * R2**2 + I2 * R1**2
    b = (4200 * R1 * R2 - (G3 * r2 + Mc) * R1**2) / den     # constant part of eps2
    a = 200 * R1 * R2 / den                                 # slope of eps2 in t
    assert a == pytest.approx(4.0336, abs=1e-4) and b == pytest.approx(0.45983, abs=1e-5)
    model = load("rope_hoist")
    phi2 = model.mechanism.coordinates[0]
    res = model.mechanism.simulate(model.scenes["startup"], model.params)
    for t in (1.0, 2.0, 3.0):
        assert res.at(t, phi2) == pytest.approx(a * t**3 / 6 + b * t**2 / 2 + 3 * t, rel=1e-9)
        assert res.at(t, md.speed(phi2)) == pytest.approx(a * t**2 / 2 + b * t + 3, rel=1e-9)


def test_planetary_train_reaches_600_rpm_in_3_s():
    model = load("planetary_2kh")
    phi1 = model.mechanism.coordinates[0]
    res = model.mechanism.simulate(model.scenes["startup"], model.params)
    assert res.final(md.speed(phi1)) == pytest.approx(20 * math.pi, rel=1e-6)


def test_dense_output_and_accelerations_of_the_hoist():
    model = load("rope_hoist")
    phi2 = model.mechanism.coordinates[0]
    res = model.mechanism.simulate(model.scenes["startup"], model.params)
    den = 8.0 * 0.16 + 29.5 * 0.36
    eps = (48 * res.t + 4200 * 0.24 - (400 * 9.81 * 0.2 + 2000) * 0.36) / den
    assert np.allclose(res[md.acceleration(phi2)], eps, rtol=1e-9)
    times = np.linspace(0, 3, 7)
    assert np.allclose(res.at(times, phi2), [res.at(t, phi2) for t in times], rtol=1e-14)
    # ... and the dense output is the motion: phi2 = 3 t + b t^2/2 + a t^3/6 with
    # eps = a t + b above (worked example 6), between the solver's steps too.
    slope, offset = 48 / den, (4200 * 0.24 - (400 * 9.81 * 0.2 + 2000) * 0.36) / den
    exact = 3 * times + offset * times**2 / 2 + slope * times**3 / 6
    assert np.allclose(res.at(times, phi2), exact, rtol=1e-9)


def test_compiled_rhs_equals_exact_sympy_evaluation():
    model = load("scotch_yoke")
    mech, scene = model.mechanism, model.scenes["startup"]
    compiled = mech.compile(scene)
    eqs = mech.equations(scene)
    p = compiled.parameter_vector(model.params)
    rng = np.random.default_rng(1)
    values = {s: sp.Float(v, 30) for s, v in model.params.items()}
    for _ in range(5):
        q, u = rng.uniform(-4, 4), rng.uniform(-50, 50)
        subs = {eqs.q[0]: sp.Float(q, 30), eqs.u[0]: sp.Float(u, 30), **values}
        exact = (eqs.forcing[0] / eqs.mass_matrix[0, 0]).evalf(30, subs=subs)
        assert compiled.rhs(0.0, [q, u], p) == pytest.approx([u, float(exact)], rel=1e-12)


def test_compiled_jacobian_equals_the_exact_derivative_for_two_dof():
    theta, x = md.coordinates("theta x")
    k, c, m, J, l = sp.symbols("k c m J l", positive=True)
    pendulum = md.Mechanism("pendulum on a spring", [theta, x])
    pendulum.link("cart", m=m, x=x)
    pendulum.link("bob", m=m, J=J, x=x + l * sp.sin(theta), y=-l * sp.cos(theta))
    pendulum.spring("spring", k, stretch=x)
    pendulum.damper("damper", c, stretch=x)
    pendulum.gravity()
    scene = md.Scene("swing", initial={theta: 1, x: 0, md.speed(theta): 0, md.speed(x): 0},
                     t_end=1)
    compiled = pendulum.compile(scene)
    params = {k: 50.0, c: 0.3, m: 1.2, J: 0.01, l: 0.5}
    eqs = pendulum.equations(scene)
    states = sp.Matrix(list(eqs.q) + list(eqs.u))
    accel = eqs.mass_matrix.LUsolve(eqs.forcing)
    exact = sp.Matrix(list(eqs.u) + list(accel)).jacobian(states)
    p = compiled.parameter_vector(params)
    y = [0.7, 0.1, -1.3, 0.4]
    subs = dict(zip(states, y)) | params
    expected = np.array(exact.evalf(subs=subs), dtype=float)
    assert np.allclose(compiled.jac(0.0, y, p), expected, rtol=1e-10, atol=1e-12)
    rhs_exact = np.array(sp.Matrix(list(eqs.u) + list(accel)).evalf(subs=subs), dtype=float)
    assert np.allclose(compiled.rhs(0.0, y, p), rhs_exact.ravel(), rtol=1e-12)


def test_excluded_effect_is_not_compiled_and_needs_no_parameter():
    model = load("motor_startup")
    mech = model.mechanism
    startup = mech.compile(model.scenes["startup"])
    braking = mech.compile(model.scenes["braking"])
    assert "M_b" not in startup.param_names and "M_b" not in startup.source
    assert "M_k" not in braking.param_names and "s_k" not in braking.param_names
    assert "brake" in braking.frictions and not startup.frictions
    params = {str(s): v for s, v in model.params.items() if str(s) != "M_b"}
    res = mech.simulate(model.scenes["startup"], params)
    assert res.reason == "95 % of steady speed"
    assert "brake" in mech.equations(model.scenes["startup"]).excluded


def test_motor_startup_ends_at_95_percent_of_steady_speed():
    model = load("motor_startup")
    phi = model.mechanism.coordinates[0]
    p = {str(s): float(v) for s, v in model.params.items()}
    # Kloss: 2 Mk s sk / (s^2 + sk^2) = M_L, small-slip root s = sk (Mk - sqrt(Mk^2-ML^2))/ML
    s = p["s_k"] * (p["M_k"] - math.sqrt(p["M_k"] ** 2 - p["M_L"] ** 2)) / p["M_L"]
    res = model.mechanism.simulate(model.scenes["startup"], model.params)
    assert res.final(md.speed(phi)) == pytest.approx(0.95 * p["omega_s"] * (1 - s), rel=1e-9)


def _work_of(res, labels):
    """Work of the recorded powers: 8-point Gauss on every step of the dense output."""
    nodes, weights = np.polynomial.legendre.leggauss(8)
    total = 0.0
    for a, b in zip(res.t[:-1], res.t[1:]):
        if b <= a:
            continue
        times = (a + b) / 2 + (b - a) / 2 * nodes
        powers = res.outputs_at(times)
        total += (b - a) / 2 * sum(weights @ powers[label] for label in labels)
    return total


BUNDLED = [("shoe_brake", "braking"), ("gear_pair", "startup"), ("cam_follower", "rise"),
           ("scotch_yoke", "startup"), ("planetary_2kh", "startup"),
           ("rope_hoist", "startup"), ("motor_startup", "startup"),
           ("motor_startup", "braking")]


@pytest.mark.parametrize("name, scene_name", BUNDLED)
def test_energy_balance_on_bundled_scenes(name, scene_name):
    """T + V changes by the work of the non-conservative loads (loads, dampers, friction)."""
    model = load(name)
    mech = model.mechanism
    scene = model.scenes[scene_name]
    eqs = mech.equations(scene)
    conservative = (md.Spring, md.Gravity)
    labels = [f"power:{n}" for n in eqs.elements
              if not isinstance(mech.elements[n], conservative)]
    scene = dataclasses.replace(scene, outputs=labels, rtol=1e-10, atol=1e-12)
    res = mech.simulate(scene, model.params)
    kinetic, potential = res.energy()
    change = kinetic[-1] + potential[-1] - kinetic[0] - potential[0]
    work = _work_of(res, labels)
    scale = max(abs(kinetic).max(), abs(work), 1.0)
    assert change == pytest.approx(work, abs=1e-7 * scale)


def test_per_state_absolute_tolerances():
    model = load("rope_hoist")
    phi2 = model.mechanism.coordinates[0]
    scene = dataclasses.replace(model.scenes["startup"], method="RK45",
                                atol={phi2: 1e-9, md.speed(phi2): 1e-11, "default": 1e-10})
    res = model.mechanism.simulate(scene, model.params)
    assert res.final(md.speed(phi2)) == pytest.approx(3 + (5.472 * 3 + 24 * 9) / 11.9, rel=1e-9)
    with pytest.raises(md.SceneError, match="atol"):
        md.Scene("bad", initial={}, t_end=1, atol={phi2: -1.0})


def test_acceleration_columns_use_the_plain_symbol_names():
    model = load("rope_hoist")
    phi2 = model.mechanism.coordinates[0]
    res = model.mechanism.simulate(model.scenes["startup"], model.params)
    name = str(md.plain(md.acceleration(phi2)))                 # "phiddot_2"
    assert name in res.columns()
    assert np.array_equal(res[name], res[md.acceleration(phi2)])

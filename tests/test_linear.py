"""Linearisation: state-space matrices against closed forms, the generated right-hand
side and the natural frequencies."""
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

import mechdyn as md

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def two_mass():
    return md.load_model(ROOT / "models" / "two_mass_drive.py")


def _values(model):
    return {str(k): float(v) for k, v in model.params.items()}


def test_the_two_mass_drive_against_its_closed_form(two_mass):
    """J1 phi1'' = M - k (phi1 - phi2) - c (phi1' - phi2'), J2 phi2'' = k (...) + c (...):
    the shaft moment k theta answers M with k / J1 / (s^2 + (c s + k)(J1 + J2)/(J1 J2))."""
    v = _values(two_mass)
    J1, J2, k, c = v["J_1"], v["J_2"], v["k"], v["c"]
    M = two_mass.param_symbol("M")
    system = two_mass.mechanism.linearize(two_mass.scenes["start"], params=two_mass.params,
                                          inputs=[M], outputs=["shaft"])
    expected_A = np.array([[0, 0, 1, 0], [0, 0, 0, 1],
                           [-k / J1, k / J1, -c / J1, c / J1],
                           [k / J2, -k / J2, c / J2, -c / J2]])
    assert system.A == pytest.approx(expected_A, rel=1e-14)
    assert system.B.ravel() == pytest.approx([0, 0, 1 / J1, 0], rel=1e-14)
    assert system.C.ravel() == pytest.approx([k, -k, 0, 0], rel=1e-14)
    assert system.D.ravel() == pytest.approx([0])
    assert system.states == ("phi_1", "phi_2", "phidot_1", "phidot_2")
    assert system.inputs == ("M",) and system.outputs == ("shaft",)
    omega = np.array([1.0, 50.0, 209.8, 400.0])
    s = 1j * omega
    closed = k / J1 / (s**2 + (c * s + k) * (J1 + J2) / (J1 * J2))
    assert system.frequency_response(omega)[:, 0, 0] == pytest.approx(closed, rel=1e-10)


def test_the_poles_are_those_of_natural_frequencies(two_mass):
    for name in ("start", "start_undamped"):
        scene = two_mass.scenes[name]
        system = two_mass.mechanism.linearize(scene, params=two_mass.params)
        modes = md.natural_frequencies(two_mass.mechanism, scene, two_mass.params)
        assert np.sort_complex(system.poles) == pytest.approx(np.sort_complex(modes.poles),
                                                             abs=1e-9)
        assert system.C == pytest.approx(np.eye(4)) and system.B.shape == (4, 0)


def test_away_from_equilibrium_a_is_the_jacobian_of_the_generated_equations():
    """The slider-crank's mass varies with phi: at a running point A must match a finite
    difference of the compiled right-hand side (independent generated code)."""
    model = md.load_model(ROOT / "models" / "slider_crank.py")
    mech, scene = model.mechanism, model.scenes["startup"]
    phi = mech.coordinates[0]
    at = {phi: 0.7, md.speed(phi): 30.0}
    system = mech.linearize(scene, at=at, params=model.params)
    compiled = mech.compile(scene)
    p = compiled.parameter_vector(model.params)
    y0, h = np.array([0.7, 30.0]), np.array([1e-6, 1e-5])
    columns = []
    for i in range(2):
        step = np.zeros(2)
        step[i] = h[i]
        columns.append((np.array(compiled.rhs(0.0, y0 + step, p))
                        - np.array(compiled.rhs(0.0, y0 - step, p))) / (2 * h[i]))
    assert system.A == pytest.approx(np.array(columns).T, rel=1e-6, abs=1e-6)
    assert system.x0.tolist() == [0.7, 30.0]


def test_an_inverted_pendulum_has_a_pole_at_plus_sqrt_g_over_l():
    theta = md.coordinate("theta")
    m, l, g = sp.symbols("m l g", positive=True)
    pendulum = md.Mechanism("pendulum", [theta])
    pendulum.link("bob", m=m, x=l * sp.sin(theta), y=-l * sp.cos(theta))
    pendulum.gravity(g)
    params = {m: 1.5, l: 0.5, g: 9.81}
    down = pendulum.linearize(params=params)
    up = pendulum.linearize(params=params, at={theta: np.pi})
    rate = np.sqrt(9.81 / 0.5)
    assert np.sort(down.poles.imag) == pytest.approx([-rate, rate])
    assert np.sort(up.poles.real) == pytest.approx([-rate, rate])


def test_python_control_state_space(two_mass):
    control = pytest.importorskip("control")
    system = two_mass.mechanism.linearize(two_mass.scenes["start"], params=two_mass.params,
                                          inputs=["M"], outputs=["shaft"])
    converted = system.to_control()
    assert isinstance(converted, control.StateSpace)
    assert np.sort_complex(converted.poles()) == pytest.approx(np.sort_complex(system.poles))


def test_errors_name_the_culprit(two_mass):
    mech, scene = two_mass.mechanism, two_mass.scenes["start"]
    with pytest.raises(md.ParameterError, match="input 'P' is not a parameter"):
        mech.linearize(scene, params=two_mass.params, inputs=["P"])
    with pytest.raises(md.ParameterError, match="give values for"):
        mech.linearize(scene, params={})
    with pytest.raises(md.MechdynError, match="not an element"):
        mech.linearize(scene, params=two_mass.params, outputs=["rope"])
    missing = {k: v for k, v in two_mass.params.items() if str(k) != "M"}
    with pytest.raises(md.ParameterError, match="operating value of input 'M'"):
        mech.linearize(scene, params=missing, inputs=["M"])

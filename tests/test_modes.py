"""Natural frequencies, mode shapes, matrices and damping ratios against hand results for
small systems (two masses on a spring, oscillators), and the errors that name what is
missing. Complements tests/test_drive_trains.py (drive trains and the loom)."""
import math

import numpy as np
import pytest
import sympy as sp

import mechdyn as md

x, y = md.coordinates("x y")
k, c, m, F = sp.symbols("k c m F", positive=True)


def pair(k_value=8.0, c_value=0.0):
    """Masses 2 and 1 on a spring k between them, free otherwise; a damper c from the
    second mass to the ground."""
    mech = md.Mechanism("free pair", [x, y])
    mech.link("heavy", m=2, x=x)
    mech.link("light", m=1, x=y)
    mech.spring("spring", k_value, stretch=x - y)
    if c_value:
        mech.damper("damper", c_value, stretch=y)
    return mech


def test_free_pair_has_a_rigid_mode_and_the_hand_frequency_and_shapes():
    # omega^2 = k (1/m1 + 1/m2) = 8 * 1.5 = 12. Elastic shape: m1 x + m2 y = 0, so
    # y = -2 x, scaled to largest component +1: (-0.5, 1). Rigid shape (1, 1).
    modes = md.natural_frequencies(pair())
    assert modes.omega[0] == 0.0 and modes.rigid_body_modes == 1
    assert modes.omega[1] == pytest.approx(math.sqrt(12.0), rel=1e-12)
    assert modes.shapes[:, 0] == pytest.approx([1.0, 1.0], rel=1e-12)
    assert modes.shapes[:, 1] == pytest.approx([-0.5, 1.0], rel=1e-12)
    assert modes.hz[1] == pytest.approx(math.sqrt(12.0) / (2 * math.pi), rel=1e-12)


def test_the_matrices_are_the_mass_stiffness_and_damping_of_the_declaration():
    modes = md.natural_frequencies(pair(c_value=0.5))
    assert modes.mass == pytest.approx(np.diag([2.0, 1.0]))
    assert modes.stiffness == pytest.approx(np.array([[8.0, -8.0], [-8.0, 8.0]]))
    assert modes.damping == pytest.approx(np.array([[0.0, 0.0], [0.0, 0.5]]))
    assert modes.coordinates == ("x", "y")


def test_a_stiff_free_pair_still_has_an_exact_rigid_mode():
    modes = md.natural_frequencies(pair(k_value=1e9))
    assert modes.omega[0] == 0.0
    assert modes.omega[1] == pytest.approx(math.sqrt(1.5e9), rel=1e-12)


def oscillator(stiffness, damping=0, mass=1):
    mech = md.Mechanism("oscillator", [x])
    mech.link("mass", m=mass, x=x)
    mech.spring("spring", stiffness, stretch=x)
    if damping:
        mech.damper("damper", damping, stretch=x)
    return mech


def test_a_very_soft_spring_is_not_a_rigid_body_mode():
    # omega = sqrt(k/m) = 1e-6: small, but the only mode, so not zero.
    modes = md.natural_frequencies(oscillator(1e-12))
    assert modes.omega[0] == pytest.approx(1e-6, rel=1e-9)


def test_slow_damped_mode_gets_its_damping_ratio():
    # m = 1, k = 0.25, c = 0.1: omega = 0.5, zeta = c / (2 sqrt(k m)) = 0.1.
    modes = md.natural_frequencies(oscillator(0.25, 0.1))
    assert modes.omega[0] == pytest.approx(0.5, rel=1e-12)
    assert modes.damping_ratios[0] == pytest.approx(0.1, rel=1e-10)


def test_overdamped_mode_has_no_damping_ratio_beside_an_underdamped_one():
    # Two uncoupled oscillators: omega 1, zeta 0.1; omega 10, zeta = 40 / (2 * 10) = 2
    # (overdamped: real poles, so NaN by the documented convention).
    mech = md.Mechanism("two oscillators", [x, y])
    mech.link("a", m=1, x=x)
    mech.link("b", m=1, x=y)
    mech.spring("ka", 1, stretch=x)
    mech.damper("ca", 0.2, stretch=x)
    mech.spring("kb", 100, stretch=y)
    mech.damper("cb", 40, stretch=y)
    modes = md.natural_frequencies(mech)
    assert modes.omega == pytest.approx([1.0, 10.0], rel=1e-12)
    assert modes.damping_ratios[0] == pytest.approx(0.1, rel=1e-10)
    assert math.isnan(modes.damping_ratios[1])


def test_unstable_operating_point_is_refused():
    # An inverted pendulum (bob above the pivot): negative stiffness -m g l.
    mech = md.Mechanism("inverted pendulum", [x])
    mech.link("bob", m=1, x=sp.sin(x), y=sp.cos(x))
    mech.gravity(9.81)
    with pytest.raises(md.DerivationError, match="unstable"):
        md.natural_frequencies(mech)


def test_operating_time_defaults_to_zero_and_can_be_given():
    # k(t) = 4 + 5 t on a unit mass: omega = 2 at t = 0, 3 at t = 1.
    mech = oscillator(4 + 5 * md.t)
    assert md.natural_frequencies(mech).omega[0] == pytest.approx(2.0, rel=1e-12)
    assert md.natural_frequencies(mech, at={md.t: 1}).omega[0] == pytest.approx(3.0,
                                                                                rel=1e-12)


def test_a_parameter_given_as_an_expression_of_another_is_evaluated():
    # k = 4 m with m = 1: omega = sqrt(k/m) = 2.
    modes = md.natural_frequencies(oscillator(k, mass=m), params={k: 4 * m, m: 1})
    assert modes.omega[0] == pytest.approx(2.0, rel=1e-12)


@pytest.mark.parametrize("mech, params, matrix", [
    (lambda: oscillator(1, mass=m), {}, "mass"),
    (lambda: oscillator(k), {}, "stiffness"),
    (lambda: oscillator(1, damping=c), {}, "damping"),
], ids=["mass", "stiffness", "damping"])
def test_a_missing_parameter_is_named_with_the_matrix_and_mechanism(mech, params, matrix):
    with pytest.raises(md.ParameterError,
                       match=rf"^'oscillator': give values for \w+ \(needed by the {matrix} "):
        md.natural_frequencies(mech(), params=params)


def test_a_missing_parameter_of_a_position_dependent_load_names_the_jacobian():
    mech = oscillator(1)
    mech.load("pull", -F * x, along=x)
    with pytest.raises(md.ParameterError, match=r"^'oscillator': .*F .*jacobian matrix"):
        md.natural_frequencies(mech)


def test_bad_values_name_the_parameter_or_the_operating_point():
    # The message names the culprit and its value (its wording is ParameterSet's).
    with pytest.raises(md.ParameterError, match=r"^parameter.*\bk = nan$"):
        md.natural_frequencies(oscillator(k), params={k: float("nan")})
    with pytest.raises(md.ParameterError, match=r"^operating point x\(t\): "):
        md.natural_frequencies(oscillator(1), at={x: float("inf")})


def test_fixed_free_chain_of_three_has_the_closed_form_frequencies_and_shapes():
    # N equal masses m in a chain, the first tied to the ground, springs k: omega_j =
    # 2 sqrt(k/m) sin((2j - 1) pi / (2 (2N + 1))), shape x_n ~ sin(n (2j - 1) pi /
    # (2N + 1)) (the standard fixed-free chain). N = 3, k = m = 1.
    a, b, d = md.coordinates("a b d")
    chain = md.Mechanism("chain", [a, b, d])
    for name, q in (("m1", a), ("m2", b), ("m3", d)):
        chain.link(name, m=1, x=q)
    chain.spring("k1", 1, stretch=a)
    chain.spring("k2", 1, stretch=b - a)
    chain.spring("k3", 1, stretch=d - b)
    modes = md.natural_frequencies(chain)
    # A symmetric eigenproblem: each omega^2 is off by a few eps omega_max^2, 16 times
    # the smallest here (~1e-14 relative); the shapes by eps over the gaps (~1e-15).
    expected = [2 * math.sin((2 * j - 1) * math.pi / 14) for j in (1, 2, 3)]
    assert modes.omega == pytest.approx(expected, rel=1e-12)
    shapes = np.array([[math.sin(n * (2 * j - 1) * math.pi / 7) for j in (1, 2, 3)]
                       for n in (1, 2, 3)])
    shapes /= shapes[np.argmax(np.abs(shapes), axis=0), range(3)]   # largest +1
    assert modes.shapes == pytest.approx(shapes, rel=1e-10, abs=1e-12)

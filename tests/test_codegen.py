"""Generated code as a user reaches it, ``mech.compile(scene)``: one coordinate's
``rhs`` and ``jac`` against the closed form, Python floats from a numpy state (so a
division by zero raises instead of giving inf), and a start where the equations divide
by zero. Expected values: m x'' = k sin(x)^2 and m x'' = k / x, differentiated by hand."""
import math

import numpy as np
import pytest
import sympy as sp

import mechdyn as md

x = md.coordinate("x")
m, k = sp.symbols("m k", positive=True)
VALUES = {"m": 2.0, "k": 8.0}


def pushed_mass(load):
    mech = md.Mechanism("pushed mass", [x])
    mech.link("mass", m=m, x=x)
    mech.load("push", load, along=x)
    return mech


def compiled(load):
    return pushed_mass(load).compile(md.Scene("s", initial={x: 1, md.speed(x): 0}, t_end=1))


def test_one_coordinate_rhs_and_jacobian_are_the_closed_form():
    # x'' = (k/m) sin(x)^2 = 4 sin(x)^2; d/dx = 8 sin x cos x.
    c = compiled(k * sp.sin(x) ** 2)
    assert c.state_names == ["x", "xdot"] and c.param_names == ["k", "m"]
    p = c.parameter_vector(VALUES)
    assert list(p) == [8.0, 2.0]
    y = np.array([0.5, -3.0])
    assert c.rhs(0.0, y, p) == pytest.approx([-3.0, 4 * math.sin(0.5) ** 2], rel=1e-15)
    assert np.allclose(c.jac(0.0, y, p), [[0.0, 1.0], [8 * math.sin(0.5) * math.cos(0.5), 0.0]],
                       rtol=1e-14, atol=0)


def test_state_from_a_numpy_array_gives_python_floats():
    c = compiled(k / x)
    out = c.rhs(0.0, np.array([4.0, 3.0]), c.parameter_vector(VALUES))
    assert out == [3.0, 1.0]                   # x'' = (8 / 4) / 2
    assert all(type(value) is float for value in out)


def test_a_division_by_zero_raises_instead_of_giving_inf():
    c = compiled(k / x)
    with pytest.raises(ZeroDivisionError):
        c.rhs(0.0, np.array([0.0, 1.0]), c.parameter_vector(VALUES))


def test_a_start_where_the_equations_divide_by_zero_is_a_named_error():
    scene = md.Scene("s", initial={x: 0, md.speed(x): 0}, t_end=1)
    with pytest.raises(md.MechdynError, match="x = 0"):
        pushed_mass(k / x).simulate(scene, VALUES)


@pytest.mark.parametrize("backend", ["compiled", "scipy"])
def test_a_switch_between_parameters_only_drives_with_the_larger_one(backend):
    """A moment Max(M1, M2) of parameters alone (its switch involves no coordinate, so
    no event watches it): a disc of J = 2 turns phi = M t^2 / (2 J) with M the larger,
    0.75 rad after 1 s for (2, 3) and for (3, 2)."""
    phi = md.coordinate("phi")
    M1, M2 = sp.symbols("M1 M2", positive=True)
    mech = md.Mechanism("larger drive", [phi])
    mech.link("disc", J=2, angle=phi)
    mech.load("drive", sp.Max(M1, M2), along=phi)
    scene = md.Scene("spin", initial={phi: 0, md.speed(phi): 0}, t_end=1, backend=backend)
    for values in ({M1: 2, M2: 3}, {M1: 3, M2: 2}):
        assert mech.simulate(scene, values).final(phi) == pytest.approx(0.75, rel=1e-9)

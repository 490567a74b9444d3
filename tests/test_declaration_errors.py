"""Bad input gives a clear error that names the culprit.

Each case asserts the exception type (a ``md.MechdynError`` subclass) and that the
message names the element, parameter, coordinate or expression at fault.
"""
import re

import pytest
import sympy as sp

import mechdyn as md

phi, psi = md.coordinates("phi psi")
m1, J1, l, k, c, M1 = sp.symbols("m_1 J_1 l k c M_1", positive=True)


def rig(*coordinates):
    return md.Mechanism("test rig", list(coordinates) or [phi])


def raises(kind, *fragments):
    """pytest.raises for ``kind``, checking that the message holds every fragment."""
    assert issubclass(kind, md.MechdynError)
    return pytest.raises(kind, match="".join(f"(?=[\\s\\S]*{re.escape(f)})" for f in fragments))


# ---------------------------------------------------------------------- names
def test_duplicate_element_name():
    mech = rig()
    mech.link("crank", J=J1, angle=phi)
    with raises(md.DeclarationError, "'crank'", "unique"):
        mech.load("crank", M1, along=phi)
    assert list(mech.elements) == ["crank"]          # the mechanism is unchanged


def test_duplicate_name_across_element_kinds():
    mech = rig()
    mech.link("disc", J=J1, angle=phi)
    mech.spring("shaft", k, stretch=phi)
    with raises(md.DeclarationError, "'shaft'"):
        mech.damper("shaft", c, stretch=phi)


def test_gravity_declared_twice():
    mech = rig()
    mech.gravity()
    with raises(md.DeclarationError, "'gravity'"):
        mech.gravity(9.81)


def test_duplicate_coordinate():
    with raises(md.DeclarationError, "'phi'", "twice"):
        md.Mechanism("test rig", [phi, md.coordinate("phi")])


# --------------------------------------------------------- undeclared functions of t
def test_position_depends_on_undeclared_function_of_time():
    theta = sp.Function("theta")(md.t)
    with raises(md.DeclarationError, "'rod'", "theta", "not a declared coordinate", "[phi]"):
        rig().link("rod", m=m1, x=l * sp.cos(theta))


def test_position_depends_on_coordinate_of_another_mechanism():
    with raises(md.DeclarationError, "'rod'", "psi", "not a declared coordinate"):
        rig(phi).link("rod", m=m1, y=l * sp.sin(phi + psi))


def test_position_depends_on_derivative_of_undeclared_function():
    theta = sp.Function("theta")(md.t)
    with raises(md.DeclarationError, "'rod'", "theta"):
        rig().link("rod", m=m1, x=l * sp.cos(phi) + sp.Derivative(theta, md.t))


def test_load_value_depends_on_undeclared_function_of_time():
    omega = sp.Function("omega")(md.t)
    with raises(md.DeclarationError, "'drive'", "omega"):
        rig().load("drive", M1 * omega, along=phi)


# --------------------------------------------------------- expressions that never move
def test_load_along_expression_without_coordinates():
    with raises(md.DeclarationError, "'push'", "along", "does not depend on the coordinates"):
        rig().load("push", M1, along=l)


def test_load_along_time_only():
    with raises(md.DeclarationError, "'push'", "along"):
        rig().load("push", M1, along=l * md.t)


def test_spring_stretch_without_coordinates():
    with raises(md.DeclarationError, "'shaft'", "stretch", "does not depend on the coordinates"):
        rig().spring("shaft", k, stretch=l)


def test_damper_stretch_without_coordinates():
    with raises(md.DeclarationError, "'dashpot'", "stretch"):
        rig().damper("dashpot", c, stretch=2 * l)


def test_friction_along_without_coordinates():
    with raises(md.DeclarationError, "'brake'", "along"):
        rig().friction("brake", M1, along=l)


# ---------------------------------------------------------------- negative values
@pytest.mark.parametrize("value", [-2, -0.5, sp.Rational(-1, 3), sp.Float(-1e-3)])
def test_negative_numeric_mass(value):
    with raises(md.DeclarationError, "'slider'", "m must not be negative"):
        rig().link("slider", m=value, x=phi)


@pytest.mark.parametrize("value", [-1, -0.25])
def test_negative_numeric_inertia(value):
    with raises(md.DeclarationError, "'flywheel'", "J must not be negative"):
        rig().link("flywheel", J=value, angle=phi)


def test_negative_stiffness_and_damping():
    with raises(md.DeclarationError, "'shaft'", "k"):
        rig().spring("shaft", -3, stretch=phi)
    with raises(md.DeclarationError, "'dashpot'", "c"):
        rig().damper("dashpot", -3, stretch=phi)


# ---------------------------------------------------------------- inertia / DOF
def test_no_inertia_in_a_coordinate():
    mech = rig(phi, psi)
    mech.link("disc", J=J1, angle=phi)
    mech.spring("shaft", k, stretch=psi - phi)
    with raises(md.DerivationError, "'test rig'", "no inertia in coordinate psi"):
        mech.equations()


def test_no_inertia_at_all_in_one_dof():
    mech = rig()
    mech.load("drive", M1, along=phi)
    with raises(md.DerivationError, "no inertia in coordinate phi"):
        mech.reduced_inertia()


def test_massless_link_gives_no_inertia():
    mech = rig()
    mech.link("rod", x=l * sp.cos(phi))                 # no m, no J
    with raises(md.DerivationError, "phi"):
        mech.equations()


def test_reduced_quantities_of_multi_dof_mechanism():
    mech = rig(phi, psi)
    mech.link("disc 1", J=J1, angle=phi)
    mech.link("disc 2", J=J1, angle=psi)
    with raises(md.DerivationError, "reduced_inertia", "'test rig'", "2 coordinates", "phi, psi"):
        mech.reduced_inertia()
    with raises(md.DerivationError, "reduced_moment", "'test rig'"):
        mech.reduced_moment()
    # ... while the multi-DOF equations themselves are fine
    assert mech.equations().mass_matrix == sp.diag(J1, J1)


# ------------------------------------------------------------------------ strings
@pytest.mark.parametrize("declare, culprit", [
    (lambda m: m.link("crank", J=J1, x="l*cos(phi)"), "link 'crank': x"),
    (lambda m: m.link("crank", m="m_1", x=phi), "link 'crank': m"),
    (lambda m: m.load("drive", "M_1", along=phi), "load 'drive': value"),
    (lambda m: m.load("drive", M1, along="phi"), "load 'drive': along"),
    (lambda m: m.spring("shaft", "k", stretch=phi), "spring 'shaft': k"),
    (lambda m: m.damper("dashpot", c, stretch="phi"), "damper 'dashpot': stretch"),
    (lambda m: m.load("drive", M1, along=phi, efficiency="0.9"), "load 'drive': efficiency"),
])
def test_strings_are_refused(declare, culprit):
    mech = rig()
    with raises(md.DeclarationError, culprit, "string"):
        declare(mech)
    assert not mech.elements


# --------------------------------------------------------------------- efficiency
@pytest.mark.parametrize("eta", [0, -0.5, 1.5, sp.Rational(11, 10)])
def test_efficiency_outside_unit_interval(eta):
    with raises(md.DeclarationError, "'hoist'", "efficiency", "(0, 1]"):
        rig().load("hoist", M1, along=phi, efficiency=eta)


@pytest.mark.parametrize("eta", [1, 0.95, sp.Rational(1, 2)])
def test_efficiency_inside_unit_interval_is_accepted(eta):
    assert rig().load("hoist", M1, along=phi, efficiency=eta).efficiency == eta


# ---------------------------------------------------------------- other misuse
def test_not_a_coordinate():
    with raises(md.DeclarationError, "'test rig'", "phi", "md.coordinate"):
        md.Mechanism("test rig", [sp.Symbol("phi")])


def test_mass_may_not_depend_on_the_motion():
    with raises(md.DeclarationError, "'crank'", "m = phi(t)"):
        rig().link("crank", m=phi, x=phi)
    with raises(md.DeclarationError, "'crank'", "time"):
        rig().link("crank", m=m1 * md.t, x=phi)


def test_position_may_not_depend_on_speed():
    with raises(md.DeclarationError, "'crank'", "speeds"):
        rig().link("crank", m=m1, x=md.speed(phi))


def test_all_errors_are_mechdyn_errors():
    for kind in (md.DeclarationError, md.DerivationError, md.SceneError,
                 md.ParameterError, md.SimulationError):
        assert issubclass(kind, md.MechdynError)

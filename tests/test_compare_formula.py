"""Comparing derived results with hand formulas as users write them (issue 27 item 2):
``md.same`` / ``md.difference`` match symbols by name, whatever their assumptions, and
read coordinates and speeds as the plain symbols results are written in.

The formulas are the textbook ones: the Scotch yoke's reduced inertia
J_1 + m_3 l^2 sin^2(phi) and moment M_1 - F_3 l sin(phi) (the yoke's x = l cos(phi)).
"""
import re
from pathlib import Path

import sympy as sp

import mechdyn as md

DECLARE = Path(__file__).resolve().parents[1] / "docs" / "guide" / "declare.md"


def guide_yoke():
    """The user guide's Scotch yoke (docs/guide/declare.md), run as written: its names."""
    blocks = re.findall(r"```python\n(.*?)```", DECLARE.read_text(), re.S)
    block = next((block for block in blocks if "Scotch yoke" in block), "")
    assert "Scotch yoke" in block
    names = {}
    exec(compile(block, "docs/guide/declare.md", "exec"), names)
    return names


def test_the_guides_scotch_yoke_equals_the_formula_written_with_plain_symbols():
    names = guide_yoke()
    yoke, J1, m3, l = names["yoke"], names["J1"], names["m3"], names["l"]
    formula = J1 + m3 * l ** 2 * sp.sin(sp.Symbol("phi")) ** 2
    # sympy alone keeps the two phi apart (the derived one is real): the natural
    # comparison is md.difference
    assert sp.simplify(yoke.reduced_inertia() - formula) != 0
    assert md.difference(yoke.reduced_inertia(), formula) == 0
    assert md.same(yoke.reduced_inertia(), formula)


def test_formula_in_the_declared_coordinate_and_in_symbols_without_assumptions():
    names = guide_yoke()
    yoke, phi = names["yoke"], names["phi"]                  # phi = md.coordinate("phi")
    J1, m3, l, M1, F3 = sp.symbols("J_1 m_3 l M_1 F_3")      # no assumptions
    assert md.same(yoke.reduced_inertia(), J1 + m3 * l ** 2 * sp.sin(phi) ** 2)
    assert md.same(yoke.reduced_moment(), M1 - F3 * l * sp.sin(sp.Symbol("phi")))


def test_a_wrong_formula_reports_what_is_off():
    names = guide_yoke()
    yoke, l, F3, M1 = names["yoke"], names["l"], names["F3"], names["M1"]
    phi = sp.Symbol("phi")
    left = md.difference(yoke.reduced_moment(), M1 - F3 * l * sp.sin(phi) / 2)
    assert not md.same(yoke.reduced_moment(), M1 - F3 * l * sp.sin(phi) / 2)
    # what is left is the missing half of the resistance, in the user's symbols by name
    assert md.difference(left, -F3 * l * sp.sin(phi) / 2) == 0


def test_speed_dependent_load_with_abs_compares_by_name():
    # A fan: M = -k |omega| omega. Derived in the real phidot, |phidot| stays an Abs;
    # the user's sp.Symbol("phidot") (not real) and md.speed(phi) both compare equal.
    phi = md.coordinate("phi")
    k, J = sp.symbols("k J", positive=True)
    fan = md.Mechanism("fan", [phi])
    fan.link("rotor", J=J, angle=phi)
    fan.load("air", -k * sp.Abs(md.speed(phi)) * md.speed(phi), along=phi)
    omega = sp.Symbol("phidot")
    assert md.same(fan.reduced_moment(), -k * sp.Abs(omega) * omega)
    assert md.same(fan.reduced_moment(), -k * sp.Abs(md.speed(phi)) * md.speed(phi))
    assert not md.same(fan.reduced_moment(), -k * omega ** 2)


def test_mass_matrix_of_two_coordinates_against_a_hand_matrix():
    # Disc 2 turns by phi_1 + phi_2 (phi_2 relative to disc 1): T = J1 w1^2/2 +
    # J2 (w1 + w2)^2/2, so M = [[J1 + J2, J2], [J2, J2]], written in plain symbols.
    p1, p2 = md.coordinates("phi_1 phi_2")
    J1, J2 = sp.symbols("J_1 J_2", positive=True)
    mech = md.Mechanism("two discs", [p1, p2])
    mech.link("disc 1", J=J1, angle=p1)
    mech.link("disc 2", J=J2, angle=p1 + p2)
    hand = sp.Matrix([[sp.Symbol("J_1") + sp.Symbol("J_2"), sp.Symbol("J_2")],
                      [sp.Symbol("J_2"), sp.Symbol("J_2")]])
    assert md.same(mech.equations().mass_matrix, hand)
    assert md.difference(mech.equations().mass_matrix, sp.zeros(2)) == \
        sp.Matrix([[J1 + J2, J2], [J2, J2]])


def _hoist_by_hand(lifting_factor):
    """The hoist drive's reduced moment as a textbook writes it (models/hoist_drive.py's
    docstring): Kloss's motor moment, the weight through the gearbox with 1/eta while
    the motor lifts (phidot > 0) and eta while the load drives (phidot < 0)."""
    M_k, s_k, omega_0, g, m, r_b, eta, i_1, i_2 = sp.symbols(
        "M_k s_k omega_0 g m r_b eta i_1 i_2")
    w = sp.Symbol("phidot")
    slip = 1 - w / omega_0
    motor = 2 * M_k / (slip / s_k + s_k / slip)
    weight = m * g * r_b / (i_1 * i_2)
    return motor - weight * sp.Piecewise((eta, w < 0), (lifting_factor(eta), True)), weight


def test_a_reduced_moment_with_efficiency_equals_its_textbook_form_branch_by_branch():
    hoist = md.load_model("models/hoist_drive.py")
    derived = hoist.mechanism.reduced_moment(hoist.scenes["lift_start_rigid"])
    formula, _ = _hoist_by_hand(lambda eta: 1 / eta)
    # the derived branch reads "g m r_b phidot / (i_1 i_2) < 0", the textbook "phidot < 0"
    assert md.same(derived, formula)


def test_the_difference_names_the_branch_that_differs():
    hoist = md.load_model("models/hoist_drive.py")
    derived = hoist.mechanism.reduced_moment(hoist.scenes["lift_start_rigid"])
    formula, weight = _hoist_by_hand(lambda eta: eta)        # eta where 1/eta belongs
    left = md.difference(derived, formula)
    assert isinstance(left, sp.Piecewise)
    (lowering, when_lowering), (lifting, _) = left.args
    assert lowering == 0 and str(when_lowering) == "phidot < 0"
    eta = sp.Symbol("eta")
    assert md.same(lifting, -weight * (1 / eta - eta))

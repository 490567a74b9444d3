"""A newcomer's first hour (issue 29, items 2-8): motor characteristics given to a load
directly, the bundled models found by name from any folder, usage errors before work with
suggestions, short reprs of results."""
import sympy as sp
import pytest

import mechdyn as md


# ------------------------------------------------------- 2. motor characteristics
def test_a_motor_characteristic_is_accepted_by_a_load_at_the_speed_of_its_along():
    phi = md.coordinate("phi")
    i = sp.Symbol("i", positive=True)
    direct = md.Mechanism("direct", [phi])
    direct.link("rotor", J=2, angle=phi)
    direct.load("motor", md.motors.kloss(60, 0.2, 157), along=i * phi)
    called = md.Mechanism("called", [phi])
    called.link("rotor", J=2, angle=phi)
    called.load("motor", md.motors.kloss(60, 0.2, 157)(i * md.speed(phi)), along=i * phi)
    assert sp.simplify(direct.reduced_moment() - called.reduced_moment()) == 0
    w = md.plain(md.speed(phi))
    # the motor turns at i*omega: at slip s_k = 0.2 it gives its breakdown moment 60
    at_breakdown = direct.reduced_moment().subs({w: 0.8 * 157 / 3, i: 3})
    assert float(at_breakdown) == pytest.approx(3 * 60, rel=1e-12)


def test_a_plain_function_as_a_load_value_is_refused_naming_md_motors():
    phi = md.coordinate("phi")
    m = md.Mechanism("m", [phi])
    with pytest.raises(md.DeclarationError, match=r"load 'motor'.*is a function.*md\.motors"):
        m.load("motor", lambda speed: 60 - speed, along=phi)
    assert repr(md.motors.kloss(60, 0.2, 157)) == "kloss(M_k=60, s_k=0.2, omega_sync=157)"

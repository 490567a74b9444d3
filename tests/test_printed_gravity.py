"""``mech.gravity()`` prints as a textbook writes it, ``g`` (issue 42): the printed
derivation names standard gravity ``g`` and gives its value, 9.81 m/s^2, while the
equations the numerics use hold the number as before."""
import numpy as np
import pytest
import sympy as sp

import mechdyn as md



def _pendulum(gravity=None, extra_g=None):
    phi = md.coordinate("phi")
    m, l = sp.symbols("m l", positive=True)
    symbols = [g for g in (gravity, extra_g) if isinstance(g, sp.Symbol)]
    pendulum = md.Mechanism("pendulum", [phi], units={m: "kg", l: "m",
                                                      **dict.fromkeys(symbols, "m/s^2")})
    pendulum.link("bob", m=m, x=l * sp.sin(phi), y=-l * sp.cos(phi))
    if extra_g is not None:
        pendulum.load("push", extra_g * m, along=l * phi)
    if gravity is None:
        pendulum.gravity()
    else:
        pendulum.gravity(gravity)
    return pendulum, phi, {m: 2.0, l: 0.5}


def _rows(latex):
    return {row.split("&=")[0].strip(): row.split("&=")[1].strip(" \\")
            for row in latex.splitlines() if "&=" in row}


def test_standard_gravity_prints_as_g_with_its_value():
    pendulum, _, _ = _pendulum()
    rows = _rows(pendulum.latex())
    assert rows["g"] == "9.81"
    assert rows["V"] == "g m y_{\\text{bob}}"
    assert rows["M_{\\mathrm{red}}"] == "- g m y_{\\text{bob}}^{\\prime}"
    assert "9.81" not in "".join(v for k, v in rows.items() if k != "g")
    expanded = _rows(pendulum.latex(expanded=True))
    assert expanded["g"] == "9.81" and "g" in expanded["V"] and "9.81" not in expanded["V"]


def test_the_command_line_prints_g_for_a_bundled_press(capsys):
    from mechdyn.cli import main
    assert main(["equations", "models/press_flywheel.py", "--format", "text"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert "  gravity (m/s^2):       g = 9.81" in lines
    assert "  potential energy:      V = g*m_r*y_ram" in lines
    moment = next(line for line in lines if "reduced moment:" in line)
    assert moment.endswith("- g*m_r*y_ram'") and "9.81" not in moment


def test_the_numbers_are_those_of_9_81():
    """The equations and a run are the same, to the bit, as with g = 9.81 written out;
    the printed derivation written back in the coordinates is the derived one."""
    standard, phi, params = _pendulum()
    written, _, _ = _pendulum(9.81)
    eqs = standard.equations()
    assert eqs.potential_energy == written.equations().potential_energy
    assert eqs.forcing == written.equations().forcing
    assert sp.Symbol("g", positive=True) not in eqs.forcing.free_symbols
    scene = md.Scene("swing", initial={phi: 1.0, md.speed(phi): 0.0}, t_end=1.0)
    a, b = standard.simulate(scene, params), written.simulate(scene, params)
    assert np.array_equal(a.t, b.t) and np.array_equal(a.y, b.y)
    book = standard.derivation()
    assert book.quantities[sp.Symbol("g", positive=True)] == pytest.approx(9.81, abs=0)
    assert sp.expand(book.expand(book.reduced_moment) - eqs.reduced_moment) == 0


def test_a_number_given_prints_as_given_and_a_symbol_g_is_the_users():
    written, _, _ = _pendulum(9.81)
    rows = _rows(written.latex())
    assert "g" not in rows and rows["V"] == "9.81 m y_{\\text{bob}}"
    g = sp.Symbol("g", positive=True)
    users, phi, params = _pendulum(g)
    rows = _rows(users.latex())
    assert "g" not in rows and rows["V"] == "g m y_{\\text{bob}}"
    scene = md.Scene("swing", initial={phi: 0.1, md.speed(phi): 0.0}, t_end=0.2)
    light = users.simulate(scene, {**params, "g": 1.62})        # the moon: overridable
    # small swing: phi'' = -(g/l) phi, so phi(0.2) = 0.1 cos(sqrt(1.62/0.5) 0.2)
    assert light[phi][-1] == pytest.approx(0.1 * np.cos(np.sqrt(1.62 / 0.5) * 0.2), rel=2e-3)


def test_a_parameter_of_the_users_named_g_keeps_standard_gravity_a_number():
    """No two g in one printout: with a parameter of its own named g (here another
    symbol), standard gravity prints as 9.81."""
    theirs = sp.Symbol("g")
    pendulum, _, _ = _pendulum(extra_g=theirs)
    rows = _rows(pendulum.latex())
    assert "g" not in rows and "9.81" in rows["V"]

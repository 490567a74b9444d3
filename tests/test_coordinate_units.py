"""A coordinate's declared unit is the unit of its values: coordinates are computed in
SI, so a unit of another scale (deg, mm) is refused by name instead of labelling radians
as degrees; degrees are a display unit of the result."""
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

import mechdyn as md

ROOT = Path(__file__).resolve().parents[1]

phi, x = md.coordinate("phi"), md.coordinate("x")


@pytest.mark.parametrize("q, unit", [(phi, "deg"), (x, "mm"), (phi, "rev")])
def test_a_coordinate_in_a_unit_other_than_si_is_refused_by_name(q, unit):
    name = q.func.__name__
    with pytest.raises(md.DeclarationError, match=rf"mechanism 'disc': coordinate {name} "
                                                  rf"declared in '{unit}'.*SI"):
        md.Mechanism("disc", [q], units={q: unit})


def test_radians_are_shown_in_degrees_only_when_converted():
    """I phi'' = M: phi(1) = M / (2 I) = 1.11072 rad = 63.64 deg; the summary in
    degrees shows the converted value."""
    I, M = sp.symbols("I M", positive=True)
    disc = md.Mechanism("disc", [phi], units={phi: "rad", I: "kg*m^2", M: "N*m"})
    disc.link("disc", J=I, angle=phi)
    disc.load("drive", M, along=phi)
    scene = md.Scene("push", initial={phi: 0, md.speed(phi): 0}, t_end=1.0, backend="scipy")
    res = disc.simulate(scene, params={I: 1.0, M: 2.22144})
    assert res.final(phi) == pytest.approx(2.22144 / 2, abs=1e-9)
    assert res.units["phi"] == "rad"
    shown = res.summary(units={"phi": "deg"})
    assert f"phi: final {np.degrees(2.22144 / 2):.6g} deg" in shown


def test_a_result_holds_each_coordinates_unit_rad_where_none_is_declared():
    """The hoist's drum angle (no unit declared: rad) and its load's height (m), beside
    the rope force's N, in ``res.units`` as the README says."""
    model = md.load_model(ROOT / "models" / "hoist_drive.py")
    res = model.mechanism.simulate(model.scenes["lift_start"], model.params)
    assert res.units == {"phi": "rad", "h": "m", "rope": "N"}


def test_a_closed_loops_multipliers_are_forces_where_the_loop_equations_are_lengths():
    """A loop of link lengths (m) closes with a force: energy per metre, N."""
    model = md.load_model(ROOT / "models" / "fourbar_flywheel.py")
    scene = md.Scene("short", initial=model.scenes["startup"].initial, t_end=0.01)
    res = model.mechanism.simulate(scene, model.params)
    assert res.units["ABCD.x"] == res.units["ABCD.y"] == "N"

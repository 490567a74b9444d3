"""Dead centres: a slider-crank started at a dead centre, and a coordinate whose reduced
inertia vanishes (reported where it fails, never integrated into NaN)."""
import math

import numpy as np
import pytest
import sympy as sp

import mechdyn as md

phi = md.coordinate("phi")
r, l, J, m, M = sp.symbols("r l J m M", positive=True)


def slider_crank():
    """Exact slider-crank: crank (J, radius r), massless rod l, slider m."""
    x = r * sp.cos(phi) + sp.sqrt(l**2 - r**2 * sp.sin(phi) ** 2)
    mech = md.Mechanism("slider-crank", [phi])
    mech.link("crank", J=J, angle=phi)
    mech.link("slider", m=m, x=x)
    mech.load("drive", M, along=phi)
    return mech, x


PARAMS = {r: 0.1, l: 0.4, J: 0.05, m: 2.0, M: 3.0}


def test_start_from_rest_at_the_dead_centre_follows_the_energy_integral():
    mech, x = slider_crank()
    res = mech.simulate(md.Scene("start", initial={phi: 0, md.speed(phi): 0}, t_end=1.5),
                        PARAMS)
    # Energy integral with I_red = J + m (dx/dphi)^2:  I_red(phi) omega^2 / 2 = M phi.
    dx = sp.lambdify(phi, sp.diff(x, phi).subs(PARAMS))
    for angle, omega in zip(res[phi][1:], res[md.speed(phi)][1:]):
        inertia = 0.05 + 2.0 * dx(angle) ** 2
        assert omega == pytest.approx(math.sqrt(2 * 3.0 * angle / inertia), rel=1e-6)
    assert res.final(phi) > 2 * math.pi               # it passed the next dead centre too


def test_vanishing_reduced_inertia_is_reported_at_its_configuration():
    # Only the yoke has mass: I_red = m l^2 sin^2(phi) vanishes at phi = pi. The crank
    # speed of the energy integral grows without bound there.
    yoke = md.Mechanism("yoke driven through its crank angle", [phi])
    yoke.link("yoke", m=m, x=l * sp.cos(phi))
    yoke.load("drive", M, along=phi)
    scene = md.Scene("to the dead centre", initial={phi: 0.5, md.speed(phi): 0}, t_end=5)
    with pytest.raises(md.SimulationError) as error:
        yoke.simulate(scene, {m: 1.0, l: 0.1, M: 1.0})
    message = str(error.value)
    assert "phi = 3.14" in message and "t = " in message and "dead centre" in message
    partial = error.value.partial
    assert np.all(np.isfinite(partial.y)) and partial[phi][-1] == pytest.approx(math.pi, abs=1e-2)

"""Defects the first differential run on generated mechanisms found (issue 38): a valid
mechanism derives and runs or is refused with a named error; a mass matrix that turns
singular along the path never yields a number past it, on either backend."""
import math

import numpy as np
import pytest
import sympy as sp

import mechdyn as md

q1, q2 = md.coordinates("q1 q2")
m, r, l, J, c, F, a, k = sp.symbols("m r l J c F a k", positive=True)


def test_regularity_check_of_a_root_complex_at_sampled_parameters_derives():
    # y = q1 + sqrt(l^2 - r^2 sin^2 q1): the check drew r > l, a complex root (TypeError)
    slider = md.Mechanism("slider", [q1, q2])
    slider.link("slider", m=m, y=q1 + sp.sqrt(l**2 - r**2 * sp.sin(q1)**2))
    slider.link("disc", J=J, angle=q2)
    mass = slider.equations().mass_matrix
    assert mass[1, 1] == J and mass[0, 1] == 0
    res = slider.simulate(md.Scene("s", initial={q1: 0.3, q2: 0, md.speed(q1): 1,
                                                 md.speed(q2): 0}, t_end=0.5),
                          {m: 1, r: 0.5, l: 1, J: 1})
    assert res.final(md.speed(q2)) == 0.0


def test_regularity_check_still_refuses_a_matrix_singular_everywhere():
    together = md.Mechanism("together", [q1, q2])
    together.link("disc", J=J, angle=q1 + q2 + sp.sqrt(l**2 - r**2 * sp.sin(q1)**2))
    with pytest.raises(md.DerivationError, match="moves no mass or inertia"):
        together.equations()


@pytest.mark.parametrize("backend", ["scipy", "compiled"])
def test_parameter_only_in_an_expression_without_effect_is_not_named_in_code(backend):
    # the angle of a link without inertia: 'a' is not in p and must not be in the code
    q = md.coordinate("q")
    mech = md.Mechanism("massless angle", [q])
    mech.link("L", m=m, x=q, angle=sp.sqrt(a - sp.sin(q)**2))
    mech.spring("s", k, stretch=q)
    scene = md.Scene("s", initial={q: 0.1, md.speed(q): 0}, t_end=1, backend=backend)
    res = mech.simulate(scene, {m: 1, a: 2, k: 1})
    assert res.final(q) == pytest.approx(0.1 * math.cos(1.0), rel=1e-8)
    assert mech.simulate(scene, {m: 1, k: 1}).final(q) == pytest.approx(res.final(q))


def _slider_and_disc():
    """det M = m J x'(q1)^2: singular at q1 = pi/2, reached at t = 0.6145 s."""
    mech = md.Mechanism("slider and disc", [q1, q2])
    mech.link("slider", m=m, x=sp.sqrt(l**2 - r**2 * sp.sin(q1)**2))
    mech.link("disc", J=J, angle=q1 + q2)
    mech.damper("damper", c, stretch=sp.sin(2 * q2))
    mech.load("drive", F, along=q1)
    return mech


@pytest.mark.parametrize("backend", ["scipy", "compiled"])
@pytest.mark.parametrize("rtol", [1e-6, 1e-10])
def test_mass_matrix_singular_along_the_path_is_named_on_both_backends(backend, rtol):
    scene = md.Scene("to the singular position", t_end=1, backend=backend, rtol=rtol,
                     atol=rtol, initial={q1: 0.4176, q2: 0.4466, md.speed(q1): -1.4228,
                                         md.speed(q2): 1.2719})
    with pytest.raises(md.SingularMassError, match="q1") as error:
        _slider_and_disc().simulate(scene, {m: 0.894, r: 0.805, l: 1.009, J: 0.889,
                                            c: 1.499, F: 4.269})
    assert error.value.time == pytest.approx(0.6145, abs=1e-3)
    partial = error.value.partial
    assert np.all(np.isfinite(partial.y)) and partial.t_end == pytest.approx(0.6145, abs=1e-3)
    assert partial[q1].max() <= math.pi / 2 + 1e-6     # nothing past the singular position

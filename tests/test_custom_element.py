"""A new element is one class, declared outside the package through the public API:
a torsional spring with preload, ``M = -(k (q - q0) + M0)``, potential
``k (q - q0)^2 / 2 + M0 q``. Every stage asks the element (its work, units, output);
nothing in mechdyn is told about the new type. The class is the user guide's
(docs/guide/architecture.md, "Adding an element"), word for word."""
from dataclasses import dataclass

import numpy as np
import pytest
import sympy as sp

import mechdyn as md


@dataclass(frozen=True)
class PreloadedSpring(md.Element):
    """Relaxed at q0, preloaded with M0: the moment -(k (along - q0) + M0) on along."""
    k: object = 0
    q0: object = 0
    M0: object = 0
    along: object = None
    DEPENDS = {"k": "", "q0": "", "M0": ""}   # constants; unlisted: "qt" (coordinates, time)
    MOVING = ("along",)                       # must move with a coordinate
    RULES = {"k": ("nonnegative", "a stiffness must not be negative")}   # of its values

    def __post_init__(self):
        super().__post_init__()
        for attribute in ("k", "q0", "M0", "along"):
            self.convert(attribute)           # numbers and sympy expressions, never text

    def expressions(self):                    # checked for dependencies, parameters, units
        return {"k": self.k, "q0": self.q0, "M0": self.M0, "along": self.along}

    def work(self, motion):
        angle = motion.position(self.along, self.name)
        k, q0, M0 = (motion.plain(value) for value in (self.k, self.q0, self.M0))
        return md.Work(potential=k * (angle - q0) ** 2 / 2 + M0 * angle,
                       forces=((-(k * (angle - q0) + M0), angle),))

    def check_units(self, units):
        units.same("q0", "along")
        units.work("M0 * d(along)/d{q}", "along", "M0")
        units.work("k * along * d(along)/d{q}", "along", "k", "along")


phi = md.coordinate("phi")
I, k, q0, M0 = sp.symbols("I k q_0 M_0", positive=True)
VALUES = {I: 2.0, k: 8.0, q0: 0.5, M0: 2.0}      # omega = sqrt(k/I) = 2, rest at 0.25


def _disc(units=None):
    disc = md.Mechanism("preloaded disc", [phi], units=units)
    disc.link("disc", J=I, angle=phi)
    disc.add(PreloadedSpring("torsion", k=k, q0=q0, M0=M0, along=phi))
    return disc


def test_the_equation_and_reduced_moment_are_the_closed_form():
    disc = _disc()
    q = sp.Symbol("phi")
    assert md.same(disc.reduced_moment(), -(k * (q - q0) + M0))
    assert md.same(disc.reduced_inertia(), I)
    eqs = disc.equations()
    (equation,) = eqs.eqs
    assert md.same(equation.lhs - equation.rhs, I * sp.Symbol("phiddot") + k * (q - q0) + M0)
    assert md.same(eqs.potential_energy, k * (q - q0) ** 2 / 2 + M0 * q)


def test_it_oscillates_about_the_shifted_rest_with_the_period_of_its_stiffness():
    """phi(t) = rest + (phi0 - rest) cos(w t), rest = q0 - M0/k, w = sqrt(k/I): from
    I phi'' = -k (phi - rest); the output is the spring's moment along the run."""
    rest, w, phi0 = 0.5 - 2.0 / 8.0, np.sqrt(8.0 / 2.0), 1.0
    period = 2 * np.pi * np.sqrt(2.0 / 8.0)
    scene = md.Scene("swing", initial={phi: phi0, md.speed(phi): 0}, t_end=period,
                     outputs=["torsion"], backend="scipy")
    res = _disc().simulate(scene, params=VALUES)
    expected = rest + (phi0 - rest) * np.cos(w * res.t)
    assert np.max(np.abs(res[phi] - expected)) < 1e-7
    assert abs(res.final(phi) - phi0) < 1e-7                       # one whole period
    moment = -(8.0 * (res[phi] - 0.5) + 2.0)
    assert np.max(np.abs(res["torsion"] - moment)) < 1e-9
    assert res["torsion"][0] == pytest.approx(-(8.0 * 0.5 + 2.0), abs=1e-12)


def test_its_units_are_checked_and_its_output_has_the_unit_of_a_moment():
    right = {I: "kg*m^2", k: "N*m", q0: "rad", M0: "N*m"}
    disc = _disc(right)
    disc.check_dimensions()
    scene = md.Scene("swing", initial={phi: 1, md.speed(phi): 0}, t_end=0.1,
                     outputs=["torsion"], backend="scipy")
    assert disc.simulate(scene, params=VALUES).units["torsion"] == "N*m"
    with pytest.raises(md.DeclarationError, match=r"preloadedspring 'torsion': M0 \* "
                       r"d\(along\)/dphi has dimension N \(a force\)"):
        _disc({**right, M0: "N"}).check_dimensions()
    with pytest.raises(md.DeclarationError, match=r"preloadedspring 'torsion': q0 = q_0 "
                       "has dimension m but along has dimensionless"):
        _disc({**right, q0: "m"}).check_dimensions()


def test_what_it_may_depend_on_is_its_own():
    with pytest.raises(md.DeclarationError, match="torsion.*must be constant"):
        _disc().add(PreloadedSpring("torsion 2", k=k * phi, along=phi))
    with pytest.raises(md.DeclarationError, match="never moves"):
        _disc().add(PreloadedSpring("torsion 2", k=k, along=sp.Integer(1)))
    with pytest.raises(md.DeclarationError, match="string"):
        PreloadedSpring("torsion", k="k", along=phi)


def test_the_printed_derivation_writes_its_energy_and_moment():
    latex = _disc().latex()
    potential = next(line for line in latex.splitlines() if line.startswith("V &="))
    assert "M_{0} \\phi" in potential and "q_{0}" in potential
    moment = next(line for line in latex.splitlines()
                  if line.startswith("M_{\\mathrm{red}} &="))
    assert moment.endswith("- M_{0} - k \\left(\\phi - q_{0}\\right) \\\\")


def test_kinetostatics_balances_its_moment_and_the_weight_of_the_disc():
    """A disc of 3 kg turning about its centre O, driven through phi at omega = 3,
    eps = 4: the drive balances I eps and the spring, M = I eps + k (phi - q0) + M0;
    the frame holds the weight, m g upward, and no moment of the spring."""
    disc = md.Mechanism("heavy disc", [phi])
    disc.link("disc", m=3, J=I, angle=phi)
    disc.joint("O", ("frame", "disc"), at=(0, 0))
    disc.add(PreloadedSpring("torsion", k=k, q0=q0, M0=M0, along=phi))
    disc.gravity(9.81)
    angles = np.array([0.0, 1.0, 2.0])
    statics = md.kinetostatics(disc, VALUES, angles, omega=3.0, eps=4.0)
    assert np.allclose(statics.driving, 2.0 * 4.0 + 8.0 * (angles - 0.5) + 2.0,
                       rtol=0, atol=1e-12)
    assert np.allclose(statics.reactions["O"].y, 3 * 9.81, rtol=0, atol=1e-12)
    assert np.allclose(statics.reactions["O"].x, 0.0, rtol=0, atol=1e-12)


def test_an_edited_element_never_runs_the_code_compiled_from_the_old_one():
    """The same class name, the same attributes, a stiffer law (as after editing the
    class in a notebook): the compiled scene is keyed by the class's code, so the run
    follows the new law, omega = sqrt(2 k / I) = 2 sqrt(2)."""
    scene = md.Scene("swing", initial={phi: 1, md.speed(phi): 0}, t_end=1.0,
                     backend="scipy")
    first = _disc().simulate(scene, params=VALUES).final(phi)
    assert first == pytest.approx(0.25 + 0.75 * np.cos(2.0), abs=1e-7)

    @dataclass(frozen=True)
    class PreloadedSpring(globals()["PreloadedSpring"]):
        def work(self, motion):
            angle = motion.position(self.along, self.name)
            k, q0, M0 = (2 * motion.plain(self.k), motion.plain(self.q0),
                         motion.plain(self.M0))
            return md.Work(forces=((-(k * (angle - q0) + M0), angle),))

    stiffer = md.Mechanism("preloaded disc", [phi])
    stiffer.link("disc", J=I, angle=phi)
    stiffer.add(PreloadedSpring("torsion", k=k, q0=q0, M0=M0, along=phi))
    rest = 0.5 - 2.0 / 16.0
    assert stiffer.simulate(scene, params=VALUES).final(phi) == pytest.approx(
        rest + (1 - rest) * np.cos(np.sqrt(8.0)), abs=1e-7)


def test_its_rule_refuses_a_negative_stiffness_by_name():
    kappa = sp.Symbol("kappa")                     # no assumption: the element's rule
    disc = md.Mechanism("loose disc", [phi])
    disc.link("disc", J=I, angle=phi)
    disc.add(PreloadedSpring("torsion", k=kappa, q0=q0, M0=M0, along=phi))
    scene = md.Scene("swing", initial={phi: 1, md.speed(phi): 0}, t_end=0.1,
                     backend="scipy")
    with pytest.raises(md.ParameterError, match=r"preloadedspring 'torsion': k = kappa "
                       r"is negative .*a stiffness must not be negative"):
        disc.simulate(scene, params={I: 2.0, kappa: -8.0, q0: 0.5, M0: 2.0})
    res = disc.simulate(scene, params={I: 2.0, kappa: 8.0, q0: 0.5, M0: 2.0})
    assert res.final(phi) == pytest.approx(0.25 + 0.75 * np.cos(0.2), abs=1e-7)

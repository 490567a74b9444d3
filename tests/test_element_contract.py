"""The custom-element contract is checked at the door: a malformed ``Work``, a bad
``expressions()``, terms along a coordinate the mechanism does not have or written with
the raw ``phi(t)``, complex forces and exceptions inside an element's methods are refused
naming the element (and the method); a potential-only element exerts the force of its
potential, ``-dV/dq``, as its printed derivation says; a sweep refuses an element class
its workers cannot unpickle before it writes a row."""
from dataclasses import dataclass

import numpy as np
import pytest
import sympy as sp

import mechdyn as md

phi = md.coordinate("phi")
I, k = sp.symbols("I k", positive=True)
VALUES = {I: 2.0, k: 8.0}                       # omega = sqrt(k / I) = 2


@dataclass(frozen=True)
class Custom(md.Element):
    """An element whose ``work`` gives what ``make(self, motion)`` builds."""
    make: object = None

    def expressions(self):                     # so k is one of the mechanism's parameters
        return {"gain": k}

    def work(self, motion):
        return self.make(motion)


@dataclass(frozen=True)
class Well(md.Element):
    """A torsional spring given by its potential alone, V = k along^2 / 2."""
    k: object = 0
    along: object = None
    DEPENDS = {"k": ""}
    MOVING = ("along",)

    def expressions(self):
        return {"k": self.k, "along": self.along}

    def work(self, motion):
        angle = motion.position(self.along, self.name)
        return md.Work(potential=motion.plain(self.k) * angle ** 2 / 2)


def _disc(*elements):
    disc = md.Mechanism("disc", [phi])
    disc.link("disc", J=I, angle=phi)
    for element in elements:
        disc.add(element)
    return disc


SWING = md.Scene("swing", initial={phi: 1, md.speed(phi): 0}, t_end=1.0, backend="scipy")


def _simulate(*elements, scene=SWING):
    return _disc(*elements).simulate(scene, params=VALUES)


@pytest.mark.parametrize("make, match", [
    (lambda m: None, r"custom 'bad': work\(\) must return md.Work\(...\), got NoneType"),
    (lambda m: (0, 0), r"custom 'bad': work\(\) must return md.Work\(...\), got tuple"),
    (lambda m: md.Work(potential="k*phi**2/2"), r"custom 'bad': Work.potential: got the "
                                                r"string"),
    (lambda m: md.Work(potential=None), r"custom 'bad': Work.potential: None"),
    (lambda m: md.Work(forces=(1.0, sp.Symbol("phi"))), r"custom 'bad': Work.forces\[0\] "
                                                         "must be a pair"),
    (lambda m: md.Work(forces=((1.0,),)), r"custom 'bad': Work.forces\[0\] must be a pair"),
    (lambda m: md.Work(forces=[(None, sp.Symbol("phi"))]), r"Work.forces\[0\] value"),
    (lambda m: md.Work(forces=((-k * phi, sp.Symbol("phi")),)),
     r"custom 'bad': Work.forces\[0\] value = -k\*phi\(t\) holds the coordinate function "
     r"phi\(t\); write .* motion.position"),
    (lambda m: md.Work(forces=((2 + 3 * sp.I, sp.Symbol("phi")),)), r"custom 'bad': "
                                                                     "Work.forces.* complex"),
    (lambda m: md.Work(forces=((1.0, m.position(md.coordinate("psi"), "bad")),)),
     r"custom 'bad': Work.forces\[0\] along = psi\(t\) acts along psi\(t\), which is not a "
     r"coordinate of the mechanism \(coordinates: phi\)"),
    (lambda m: md.Work(potential=sp.Function("f")(m.plain(phi))),
     r"custom 'bad': Work.potential = f\(phi\) holds the undefined function f\(phi\)"),
])
def test_a_malformed_work_is_refused_naming_the_element(make, match):
    with pytest.raises(md.DeclarationError, match=match):
        _simulate(Custom("bad", make=make))


def test_expressions_must_be_a_dict():
    @dataclass(frozen=True)
    class Listed(md.Element):
        def expressions(self):
            return [k]

    with pytest.raises(md.DeclarationError, match=r"listed 'odd': expressions\(\) must "
                                                  "return a dict.* got list"):
        _disc(Listed("odd"))


def _raising(method):
    @dataclass(frozen=True)
    class Faulty(md.Element):
        def expressions(self):
            return {"k": k}

        def work(self, motion):
            if method == "work":
                raise KeyError("stiffness")
            return md.Work(forces=((-motion.plain(k * phi), motion.position(phi, "f")),))

        def check_units(self, units):
            if method == "check_units":
                raise KeyError("no such attribute")

        def output(self, eqs):
            if method == "output":
                return 1 / 0
            return super().output(eqs)
    return Faulty("faulty")


@pytest.mark.parametrize("method, cause", [("work", KeyError), ("check_units", KeyError),
                                           ("output", ZeroDivisionError)])
def test_an_exception_inside_an_element_names_the_element_and_the_method(method, cause):
    disc = _disc(_raising(method))
    scene = md.Scene("swing", initial={phi: 1, md.speed(phi): 0}, t_end=0.1,
                     outputs=["faulty"], backend="scipy")
    with pytest.raises(md.DeclarationError, match=rf"faulty 'faulty': its {method}\(\) "
                                                  rf"raised {cause.__name__}") as caught:
        if method == "check_units":
            disc.declare_units({I: "kg*m^2", k: "N*m"})
            disc.check_dimensions()
        disc.simulate(scene, params=VALUES)
    assert isinstance(caught.value.__cause__, cause)


def test_a_potential_only_element_exerts_minus_the_slope_of_its_potential():
    """I phi'' = -dV/dphi = -k phi: phi = cos(2 t), as the built-in spring gives, and
    the printed derivation's V and M_red are those of the run."""
    res = _simulate(Well("well", k=k, along=phi))
    assert res.final(phi) == pytest.approx(np.cos(2.0), abs=1e-7)
    spring = md.Mechanism("disc", [phi])
    spring.link("disc", J=I, angle=phi)
    spring.spring("spring", k, phi)
    assert spring.simulate(SWING, params=VALUES).final(phi) == pytest.approx(
        res.final(phi), abs=1e-9)
    disc = _disc(Well("well", k=k, along=phi))
    assert md.same(disc.reduced_moment(), -k * sp.Symbol("phi"))
    moment = next(line for line in disc.latex().splitlines()
                  if line.startswith("M_{\\mathrm{red}} &="))
    assert "k \\phi" in moment
    scene = md.Scene("swing", initial={phi: 1, md.speed(phi): 0}, t_end=1.0,
                     outputs=["well"], backend="scipy")
    out = disc.simulate(scene, params=VALUES)
    assert np.allclose(out["well"], -8.0 * out[phi], rtol=0, atol=1e-12)
    disc.joint("O", ("frame", "disc"), at=(0, 0))
    angles = np.array([0.0, 0.5, 1.0])        # the drive balances I eps + k phi
    statics = md.kinetostatics(disc, VALUES, angles, omega=1.0, eps=3.0)
    assert np.allclose(statics.driving, 2.0 * 3.0 + 8.0 * angles, rtol=0, atol=1e-12)


def test_a_dissipation_without_forces_is_refused_by_name():
    def make(motion):
        return md.Work(dissipation=motion.rate(motion.position(phi, "drag")) ** 2 / 2)
    with pytest.raises(md.DeclarationError, match=r"custom 'drag': its work\(\) gives the "
                                                  "dissipation .* but no forces"):
        _simulate(Custom("drag", make=make))


def test_a_potential_beside_forces_that_vanish_at_rest_is_refused_by_name():
    """V = k phi^2 / 2 with only a damping force -c phi': the spring's force is missing
    from the forces, so the potential would exert none."""
    def make(motion):
        angle = motion.position(phi, "leaky")
        return md.Work(potential=motion.plain(k) * angle ** 2 / 2,
                       forces=((-0.5 * motion.rate(angle), angle),))
    with pytest.raises(md.DeclarationError, match=r"custom 'leaky': its work\(\) gives the "
                                                  "potential .* forces that vanish at rest"):
        _simulate(Custom("leaky", make=make))


def test_a_sweep_refuses_a_local_element_class_before_writing_a_row(tmp_path):
    @dataclass(frozen=True)
    class LocalWell(Well):
        pass

    out = tmp_path / "sweep.csv"
    disc = _disc(LocalWell("well", k=k, along=phi))
    with pytest.raises(md.SweepError, match=r"localwell 'well'.*cannot be "
                                            "pickled.*module level"):
        md.sweep(disc, SWING, VALUES, {"k": [4.0, 8.0]}, out=str(out), workers=2,
                 progress=False)
    assert not out.exists() or len(out.read_text().strip().splitlines()) <= 1

"""The elements a mechanism is declared from: links and the loads acting on them.

Every element has a unique ``name`` and optional ``tags``; scenes select loads by either.
Values are sympy expressions (or numbers) of the coordinates, their speeds, the time
``md.t`` and parameters (any other symbols). Each element carries its own behaviour —
its work (energy, dissipation, forces), units check and output — as the methods of
:class:`~mechdyn.declare.element_base.Element` that every stage asks.

>>> import sympy as sp, mechdyn as md
>>> phi = md.coordinate("phi")
>>> md.Load("drive", sp.Symbol("M_1"), along=phi).value
M_1
"""
from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp

from mechdyn.declare.element_base import FRAME, Element, Sliding, Work, as_expression
from mechdyn.declare.constraints import Constraint
from mechdyn.declare.joints import Joint
from mechdyn.errors import DeclarationError
from mechdyn.symbols import t

__all__ = ["Element", "Link", "Load", "Spring", "Damper", "Gravity", "Friction",
           "Constraint", "Joint", "FRAME", "is_structural", "as_expression"]

@dataclass(frozen=True)
class Link(Element):
    """A rigid body: mass ``m`` at centre of mass ``(x, y)``, moment of inertia ``J``
    about the centre of mass, rotation ``angle``. All positions are expressions of the
    coordinates (and possibly of ``md.t`` for an imposed motion). ``points``: pairs
    ``(x, y)`` an animation draws as the link's outline (joints, ends); they do not
    enter the dynamics.

    Examples
    --------
    >>> import sympy as sp, mechdyn as md
    >>> phi = md.coordinate("phi")
    >>> l = sp.Symbol("l", positive=True)
    >>> md.Link("rod", m=2, x=l * sp.cos(phi) / 2, y=l * sp.sin(phi) / 2, angle=phi)
    Link(name='rod', tags=(), m=2, J=0, x=l*cos(phi(t))/2, y=l*sin(phi(t))/2, angle=phi(t))
    """
    m: object = 0
    J: object = 0
    x: object = 0
    y: object = 0
    angle: object = 0
    points: tuple = field(default=(), repr=False)

    DEPENDS = {"m": "", "J": "", "x": "qt", "y": "qt", "angle": "qt"}
    RULES = dict.fromkeys(("m", "J"), ("nonnegative", "masses and inertias must not be "
                                       "negative"))

    def __post_init__(self):
        super().__post_init__()
        self.convert("m", nonnegative=True)
        self.convert("J", nonnegative=True)
        for attribute in ("x", "y", "angle"):
            self.convert(attribute)
        points = []
        for index, point in enumerate(self.points):
            if not (isinstance(point, (tuple, list)) and len(point) == 2):
                raise DeclarationError(f"link {self.name!r}: points[{index}] must be a pair "
                                       f"(x, y), got {point!r}")
            points.append(tuple(as_expression(value, f"link {self.name!r}: points[{index}]")
                                for value in point))
        object.__setattr__(self, "points", tuple(points))

    def expressions(self):
        return {"m": self.m, "J": self.J, "x": self.x, "y": self.y, "angle": self.angle}

    def check_units(self, units):
        for attribute, unit, word in (("m", "kg", "a mass"), ("J", "kg*m^2", "a moment of "
                                      "inertia"), ("x", "m", "a position"),
                                      ("y", "m", "a position"), ("angle", "1", "an angle")):
            units.need(attribute, unit, word)


@dataclass(frozen=True)
class Load(Element):
    """A force or moment ``value`` acting along the displacement or angle ``along``.

    Its generalized force is ``value * d(along)/dq`` (virtual power). With an
    ``efficiency`` eta the load sits behind a lossy transmission: when it draws power
    (value and motion opposed) the drive must supply ``value/eta``; when it feeds power
    back only ``value*eta`` arrives. ``on`` names the link(s) it acts on, for
    kinetostatics (joint reactions); without it the link is found from ``along``.

    Examples
    --------
    >>> import sympy as sp, mechdyn as md
    >>> phi = md.coordinate("phi")
    >>> yoke = md.Mechanism("yoke", [phi])
    >>> _ = yoke.link("crank", J=1, angle=phi)
    >>> _ = yoke.load("resistance", 100, along=sp.cos(phi))   # 100 N along x = cos(phi) m
    >>> yoke.reduced_moment()
    -100*sin(phi)
    >>> md.Load("drive", 5, along=phi, efficiency=0.9).efficiency
    0.900000000000000
    """
    value: object = 0
    along: object = None
    efficiency: object = None
    on: tuple = ()

    DEPENDS = {"value": "qvt", "along": "qt", "efficiency": ""}
    MOVING = ("along",)
    RULES = {"efficiency": ("efficiency", "an efficiency must lie in (0, 1]")}

    def __post_init__(self):
        super().__post_init__()
        if self.along is None:
            raise DeclarationError(f"load {self.name!r}: 'along' is required "
                                   "(the angle or displacement the load acts along)")
        on = (self.on,) if isinstance(self.on, str) else tuple(self.on or ())
        if not all(isinstance(n, str) for n in on):
            raise DeclarationError(f"load {self.name!r}: on= takes link names, got {self.on!r}")
        object.__setattr__(self, "on", on)
        self.convert("along")
        if callable(self.value) and not isinstance(self.value, sp.Basic):
            object.__setattr__(self, "value", self._characteristic(self.value))
        self.convert("value")
        if self.efficiency is not None:
            self.convert("efficiency")
            eta = self.efficiency
            if sp.Le(eta, 0) == sp.true or sp.Gt(eta, 1) == sp.true:
                raise DeclarationError(
                    f"load {self.name!r}: efficiency must lie in (0, 1], got {eta}")

    def _characteristic(self, value):
        """A motor characteristic (``md.motors``) at the speed of ``along``."""
        from mechdyn.declare.motors import Characteristic
        if not isinstance(value, Characteristic):
            raise DeclarationError(
                f"load {self.name!r}: value {value!r} is a function; give a number or sympy "
                "expression, or a motor characteristic from md.motors (kloss, dc_shunt, "
                "table), which the load calls with the speed of its along")
        return value(sp.diff(self.along, t))

    def work(self, motion):
        along = motion.position(self.along, self.name)
        value = motion.law(self.value, along, self.name)
        if self.efficiency is not None:     # 1/eta while it draws power, eta feeding back
            eta = motion.plain(self.efficiency)
            value = value * sp.Piecewise((eta, value * motion.rate(along) > 0),
                                         (1 / eta, True))
        return Work(forces=((value, along),))

    def check_units(self, units):
        units.need("efficiency", "1", "an efficiency")
        units.work("value * d(along)/d{q}", "along", "value")

    def output(self, eqs):
        return eqs.to_plain(self.value)

    def expressions(self):
        out = {"value": self.value, "along": self.along}
        if self.efficiency is not None:
            out["efficiency"] = self.efficiency
        return out


@dataclass(frozen=True)
class _OnStretch(Element):
    """An element of one non-negative coefficient (the field named ``COEFFICIENT``)
    acting along the expression ``stretch``: a spring, a damper."""
    COEFFICIENT = ""
    MOVING = ("stretch",)

    def __post_init__(self):
        super().__post_init__()
        self.convert(self.COEFFICIENT, nonnegative=True)
        self.convert("stretch")

    def output_along(self):
        return self.stretch

    def expressions(self):
        return {self.COEFFICIENT: getattr(self, self.COEFFICIENT), "stretch": self.stretch}


@dataclass(frozen=True)
class Spring(_OnStretch):
    """A linear spring of stiffness ``k`` on the ``stretch`` (an expression that is zero
    when the spring is relaxed): potential ``k stretch^2 / 2``, force ``-k stretch``.
    A stiffness that varies (a gear mesh) acts as the force ``-k(q, t) stretch``.

    Examples
    --------
    >>> import mechdyn as md
    >>> phi_1, phi_2 = md.coordinates("phi_1 phi_2")
    >>> shaft = md.Spring("shaft", 2000, stretch=phi_2 - phi_1)
    >>> shaft.k, shaft.stretch
    (2000, -phi_1(t) + phi_2(t))
    """
    k: object = 0
    stretch: object = 0

    COEFFICIENT = "k"
    RULES = {"k": ("nonnegative", "a stiffness must not be negative")}

    def work(self, motion):
        stretch, k = motion.position(self.stretch, self.name), motion.plain(self.k)
        return Work(potential=k * stretch ** 2 / 2, forces=((-k * stretch, stretch),))

    def check_units(self, units):
        units.work("k * stretch * d(stretch)/d{q}", "stretch", "k", "stretch")

    def output(self, eqs):
        return eqs.to_plain(self.k * self.stretch)


@dataclass(frozen=True)
class Damper(_OnStretch):
    """A linear viscous damper ``c`` on the rate of ``stretch``: Rayleigh dissipation
    ``c stretch'^2 / 2``, force ``-c stretch'``.

    Examples
    --------
    >>> import mechdyn as md
    >>> x = md.coordinate("x")
    >>> shock = md.Mechanism("shock absorber", [x], units={x: "m"})
    >>> _ = shock.link("mass", m=1, x=x)
    >>> _ = shock.damper("damper", 40, stretch=x)
    >>> shock.equations().forcing
    Matrix([[-40*xdot]])
    """
    c: object = 0
    stretch: object = 0

    COEFFICIENT = "c"
    RULES = {"c": ("nonnegative", "a damping coefficient must not be negative")}

    def work(self, motion):
        stretch, c = motion.position(self.stretch, self.name), motion.plain(self.c)
        rate = motion.rate(stretch)
        return Work(dissipation=c * rate ** 2 / 2, forces=((-c * rate, stretch),))

    def check_units(self, units):
        units.work("c * d(stretch)/dt * d(stretch)/d{q}", "stretch", "c", "stretch",
                   per_time=1)

    def output(self, eqs):
        stretch = eqs.to_plain(self.stretch)
        rate = sum((sp.diff(stretch, q) * u for q, u in zip(eqs.q, eqs.u)), sp.S.Zero) \
            + sp.diff(stretch, t)
        return eqs.to_plain(self.c) * rate


STANDARD_GRAVITY = 9.81        # m/s^2, what mech.gravity() uses unless given another g
G = sp.Symbol("g", positive=True)


@dataclass(frozen=True)
class Gravity(Element):
    """Uniform gravity ``g`` along -y: potential ``m g y`` of every link. Without a
    ``g`` it is standard gravity, 9.81 m/s^2: the number in the equations, the symbol
    ``g`` in the printed derivation (:meth:`printed`).

    Examples
    --------
    >>> import sympy as sp, mechdyn as md
    >>> theta = md.coordinate("theta")
    >>> m, l, g = sp.symbols("m l g", positive=True)
    >>> pendulum = md.Mechanism("pendulum", [theta])
    >>> _ = pendulum.link("bob", m=m, x=l * sp.sin(theta), y=-l * sp.cos(theta))
    >>> pendulum.gravity(g)
    Gravity(name='gravity', tags=(), g=g)
    >>> pendulum.reduced_moment()
    -g*l*m*sin(theta)
    """
    g: object = None
    standard: bool = field(default=False, init=False, repr=False, compare=False)

    DEPENDS = {"g": ""}

    def __post_init__(self):
        super().__post_init__()
        if self.g is None:
            object.__setattr__(self, "g", STANDARD_GRAVITY)
            object.__setattr__(self, "standard", True)
        self.convert("g")

    def work(self, motion):
        g, potential, forces = motion.plain(self.g), sp.S.Zero, []
        for _, m, y in motion.heights():
            potential += m * g * y
            forces.append((-m * g, y))
        return Work(potential=potential, forces=tuple(forces))

    def printed(self):
        """Standard gravity writes ``g`` (= 9.81 m/s^2) where a textbook does."""
        if not self.standard:
            return self, {}
        return Gravity(self.name, g=G, tags=self.tags), {G: (self.g, "gravity (m/s^2)")}

    def check_units(self, units):
        units.need("g", "m/s^2", "gravity")

    def expressions(self):
        return {"g": self.g}


@dataclass(frozen=True)
class Friction(Element):
    """Coulomb friction (a brake) of magnitude ``moment`` along ``along``: opposes
    sliding with ``moment`` (which may depend on the sliding speed: Stribeck, tables),
    and holds at rest while the other loads stay within ``peak * moment`` (static
    friction, MSL's ``tau0_max = peak * tau0``; ``peak >= 1``).

    Examples
    --------
    >>> import mechdyn as md
    >>> phi = md.coordinate("phi")
    >>> brake = md.Mechanism("brake", [phi])
    >>> _ = brake.link("disc", J=0.4, angle=phi)
    >>> brake.friction("shoe", 0.8, along=phi, peak=1.2).peak
    1.20000000000000
    >>> try:
    ...     md.Friction("shoe", 0.8, along=phi, peak=0.5)
    ... except md.DeclarationError as error:
    ...     print(error)
    friction 'shoe': peak = 0.5 must be at least 1 (static friction is never below sliding friction)
    """
    moment: object = 0
    along: object = None
    peak: object = 1

    DEPENDS = {"moment": "qvt", "along": "qt", "peak": ""}
    MOVING = ("along",)
    RULES = {"moment": ("nonnegative", "a friction magnitude must not be negative"),
             "peak": ("peak", "static friction is never below sliding friction")}
    KIND = "friction"               # sliding: opposes the motion both ways

    def __post_init__(self):
        super().__post_init__()
        if self.along is None:
            raise DeclarationError(f"{type(self).__name__.lower()} {self.name!r}: 'along' "
                                   "is required")
        self.convert("moment", nonnegative=True)
        self.convert("along")
        self.convert("peak")
        if self.peak.is_number and not self.peak >= 1:
            raise DeclarationError(f"{type(self).__name__.lower()} {self.name!r}: peak = "
                                   f"{float(self.peak):g} must be at least 1 (static "
                                   "friction is never below sliding friction)")

    def work(self, motion):
        along = motion.position(self.along, self.name)
        law = motion.law(self.moment, along, self.name)
        return Work(forces=((-law * sp.sign(motion.rate(along)), along),),
                    sliding=Sliding(self.KIND, law, along, motion.plain(self.peak)))

    def check_units(self, units):
        units.work("moment * d(along)/d{q}", "along", "moment")

    def output(self, eqs):
        fr = next(f for f in eqs.frictions if f.name == self.name)
        return -fr.magnitude * sp.sign(fr.rate)

    def expressions(self):
        out = {"moment": self.moment, "along": self.along}
        if self.peak != 1:
            out["peak"] = self.peak
        return out


def is_structural(element) -> bool:
    """Links, loops and joints: always part of the mechanism, never a scene's effect."""
    return isinstance(element, (Link, Constraint, Joint))

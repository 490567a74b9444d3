"""The elements a mechanism is declared from: links and the loads acting on them.

Every element has a unique ``name`` and optional ``tags``; scenes select loads by either.
Values are sympy expressions (or numbers) of the coordinates, their speeds, the time
``md.t`` and parameters (any other symbols).

>>> import sympy as sp, mechdyn as md
>>> phi = md.coordinate("phi")
>>> md.Load("drive", sp.Symbol("M_1"), along=phi).value
M_1
"""
from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp
from sympy.core.sympify import SympifyError, _sympify

from .errors import DeclarationError

__all__ = ["Element", "Link", "Load", "Spring", "Damper", "Gravity", "Friction",
           "as_expression"]


def as_expression(value, what: str) -> sp.Expr:
    """Convert a number or sympy expression; strings are refused (no eval of text)."""
    if isinstance(value, str):
        raise DeclarationError(
            f"{what}: got the string {value!r}; pass a sympy expression or a number "
            "(build it with sp.symbols / md.coordinate), strings are never evaluated")
    try:
        expr = _sympify(value)
    except SympifyError:
        raise DeclarationError(f"{what}: {value!r} is not a number or sympy expression") from None
    if not isinstance(expr, sp.Expr):
        raise DeclarationError(f"{what}: {value!r} is not a scalar expression")
    if expr.has(sp.nan, sp.zoo, sp.oo, -sp.oo):
        raise DeclarationError(f"{what}: {value!r} is not finite")
    return expr


def _nonnegative(expr: sp.Expr, what: str) -> sp.Expr:
    """Refuse values that are negative by their numbers or their symbols' assumptions
    (``-m`` with ``m`` declared positive)."""
    if expr.is_negative:
        raise DeclarationError(f"{what} must not be negative, got {expr}")
    return expr


def _tags(tags) -> tuple:
    if isinstance(tags, str):
        return (tags,)
    return tuple(tags)


@dataclass(frozen=True)
class Element:
    """Base of all elements: a name and tags."""
    name: str
    tags: tuple = field(default=(), kw_only=True)

    def __post_init__(self):
        if not isinstance(self.name, str) or not self.name:
            raise DeclarationError(f"element name must be a non-empty string, got {self.name!r}")
        object.__setattr__(self, "tags", _tags(self.tags))

    def _expr(self, attribute: str, nonnegative=False):
        what = f"{type(self).__name__.lower()} {self.name!r}: {attribute}"
        expr = as_expression(getattr(self, attribute), what)
        if nonnegative:
            _nonnegative(expr, what)
        object.__setattr__(self, attribute, expr)

    def expressions(self) -> dict:
        """The element's expressions by attribute name."""
        return {}


@dataclass(frozen=True)
class Link(Element):
    """A rigid body: mass ``m`` at centre of mass ``(x, y)``, moment of inertia ``J``
    about the centre of mass, rotation ``angle``. All positions are expressions of the
    coordinates (and possibly of ``md.t`` for an imposed motion). ``points``: pairs
    ``(x, y)`` an animation draws as the link's outline (joints, ends); they do not
    enter the dynamics."""
    m: object = 0
    J: object = 0
    x: object = 0
    y: object = 0
    angle: object = 0
    points: tuple = field(default=(), repr=False)

    def __post_init__(self):
        super().__post_init__()
        self._expr("m", nonnegative=True)
        self._expr("J", nonnegative=True)
        for attribute in ("x", "y", "angle"):
            self._expr(attribute)
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


@dataclass(frozen=True)
class Load(Element):
    """A force or moment ``value`` acting along the displacement or angle ``along``.

    Its generalized force is ``value * d(along)/dq`` (virtual power). With an
    ``efficiency`` eta the load sits behind a lossy transmission: when it draws power
    (value and motion opposed) the drive must supply ``value/eta``; when it feeds power
    back only ``value*eta`` arrives.
    """
    value: object = 0
    along: object = None
    efficiency: object = None

    def __post_init__(self):
        super().__post_init__()
        if self.along is None:
            raise DeclarationError(f"load {self.name!r}: 'along' is required "
                                   "(the angle or displacement the load acts along)")
        self._expr("value")
        self._expr("along")
        if self.efficiency is not None:
            self._expr("efficiency")
            eta = self.efficiency
            if sp.Le(eta, 0) == sp.true or sp.Gt(eta, 1) == sp.true:
                raise DeclarationError(
                    f"load {self.name!r}: efficiency must lie in (0, 1], got {eta}")

    def expressions(self):
        out = {"value": self.value, "along": self.along}
        if self.efficiency is not None:
            out["efficiency"] = self.efficiency
        return out


@dataclass(frozen=True)
class Spring(Element):
    """A linear spring of stiffness ``k`` on the ``stretch`` (an expression that is zero
    when the spring is relaxed): potential ``k stretch^2 / 2``, force ``-k stretch``.
    A stiffness that varies (a gear mesh) acts as the force ``-k(q, t) stretch``."""
    k: object = 0
    stretch: object = 0

    def __post_init__(self):
        super().__post_init__()
        self._expr("k", nonnegative=True)
        self._expr("stretch")

    def expressions(self):
        return {"k": self.k, "stretch": self.stretch}


@dataclass(frozen=True)
class Damper(Element):
    """A linear viscous damper ``c`` on the rate of ``stretch``: Rayleigh dissipation
    ``c stretch'^2 / 2``, force ``-c stretch'``."""
    c: object = 0
    stretch: object = 0

    def __post_init__(self):
        super().__post_init__()
        self._expr("c", nonnegative=True)
        self._expr("stretch")

    def expressions(self):
        return {"c": self.c, "stretch": self.stretch}


@dataclass(frozen=True)
class Gravity(Element):
    """Uniform gravity ``g`` along -y: potential ``m g y`` of every link."""
    g: object = 9.81

    def __post_init__(self):
        super().__post_init__()
        self._expr("g")

    def expressions(self):
        return {"g": self.g}


@dataclass(frozen=True)
class Friction(Element):
    """Coulomb friction (a brake) of magnitude ``moment`` along ``along``: opposes
    sliding, and holds at rest while the other loads stay within it."""
    moment: object = 0
    along: object = None

    def __post_init__(self):
        super().__post_init__()
        if self.along is None:
            raise DeclarationError(f"friction {self.name!r}: 'along' is required")
        self._expr("moment", nonnegative=True)
        self._expr("along")

    def expressions(self):
        return {"moment": self.moment, "along": self.along}

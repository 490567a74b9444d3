"""The base of every element, and what an element tells each stage about itself.

Each stage asks the element instead of switching on its type, so a new element is one
subclass of :class:`Element` (a frozen dataclass) and nothing else:

- :meth:`Element.work`: its share of the equations of motion, a :class:`Work`
  (potential energy, Rayleigh dissipation, generalized forces ``value * d(along)/dq``,
  friction that sticks or slides, limits of a stop), written with the *motion* the
  deriving stage passes: ``motion.plain(expr)`` (the equations' plain symbols),
  ``motion.position(expr, owner)`` (a position it acts along), ``motion.law(expr,
  along, owner)`` (a law of the motion, a motor's moment), ``motion.rate(position)``
  (its time derivative) and ``motion.heights()`` (``(link, m, y)`` of every link). The
  derivation gives plain expressions; the printed derivation gives named ones
  (``x_slider``, ``M_motor``) and so writes each term as the element does;
- :meth:`Element.check_units`: the dimensions its attributes need, with the checker of
  :mod:`mechdyn.declare.dimensions`;
- :meth:`Element.output` and :meth:`Element.output_along`: the force or moment a
  scene records, and what it acts along (which gives its unit);
- :meth:`Element.printed`: the element as the printed derivation writes it and the
  numbers it names there (standard gravity's ``g`` = 9.81); by default itself;
- ``DEPENDS`` (what each attribute may depend on: ``q`` the coordinates, ``v``
  speeds, ``t`` the time; ``"qt"`` when not listed), ``MOVING`` (attributes that
  must move with the coordinates, or they do no work) and ``RULES`` (attribute ->
  ``(rule, why)``: what its parameters' values must give, ``"nonnegative"``,
  ``"fraction"``, ``"efficiency"`` or ``"peak"``).

>>> import sympy as sp
>>> class Plain:                      # the derivation's motion, one coordinate q
...     q, qdot = sp.symbols("q qdot")
...     def plain(self, expr): return expr
...     def position(self, expr, owner): return expr
...     def law(self, expr, along, owner): return expr
...     def rate(self, expr): return sp.diff(expr, self.q) * self.qdot
>>> Element("nothing").work(Plain())
Work(potential=0, dissipation=0, forces=(), sliding=None, contacts=())
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar

import sympy as sp
from sympy.core.sympify import SympifyError, _sympify

from mechdyn.errors import DeclarationError

__all__ = ["Element", "Work", "Sliding", "Limit", "FRAME", "as_expression"]

FRAME = "frame"     # the name joints use for the fixed frame (ground)


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
    if expr.has(sp.I) or any(a.is_real is False for a in expr.atoms(sp.Number)):
        raise DeclarationError(f"{what}: {value!r} is complex; mechanisms are declared "
                               "with real numbers and expressions")
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
class Sliding:
    """Friction that sticks or slides (run-time modes, :mod:`mechdyn.simulate.friction`):
    ``kind`` ``"friction"``, ``"one_way"`` (a one-way clutch) or ``"gear"`` (a lossy
    gear's mesh, ``law``: its efficiencies and bearing moments), the ``magnitude`` of
    the sliding force along ``along``, the static ``peak`` factor and a one-way clutch's
    ``release`` moment."""
    kind: str
    magnitude: object
    along: object
    peak: object = sp.S.One
    release: object = sp.S.Zero
    law: tuple = ()


@dataclass(frozen=True)
class Limit:
    """A one-sided limit ``side * (along - limit) >= 0`` (a stop's), ``label``
    ``NAME.lower`` or ``NAME.upper``; an impact reverses the speed of ``along`` times
    ``restitution``."""
    label: str
    side: int
    along: object
    limit: object
    restitution: object


@dataclass(frozen=True)
class Work:
    """An element's share of the equations of motion: ``potential`` energy,
    ``dissipation`` (Rayleigh), ``forces`` (pairs ``(value, along)``, each the
    generalized force ``value * d(along)/dq``: a force or moment ``value`` acting along
    a displacement or angle), ``sliding`` (a :class:`Sliding`) and ``contacts``
    (:class:`Limit` s).

    Examples
    --------
    >>> import sympy as sp, mechdyn as md
    >>> k, q = sp.symbols("k q")
    >>> md.Work(potential=k * q**2 / 2, forces=((-k * q, q),))
    Work(potential=k*q**2/2, dissipation=0, forces=((-k*q, q),), sliding=None, contacts=())
    """
    potential: object = sp.S.Zero
    dissipation: object = sp.S.Zero
    forces: tuple = ()
    sliding: object = None
    contacts: tuple = ()


@dataclass(frozen=True)
class Element:
    """Base of all elements: a name and tags, and the behaviour every stage asks of
    an element (see the module); the defaults are those of an element that does
    nothing.

    Examples
    --------
    A new element is a frozen dataclass deriving from ``Element`` whose ``work`` returns
    a :class:`Work` (the user guide's "Adding an element", docs/guide/architecture.md, has one with units):

    >>> from dataclasses import dataclass
    >>> import mechdyn as md
    >>> @dataclass(frozen=True)
    ... class Drag(md.Element):            # a moment -b * speed along `along`
    ...     b: object = 0
    ...     along: object = None
    ...     DEPENDS = {"b": ""}
    ...     MOVING = ("along",)
    ...     def __post_init__(self):
    ...         super().__post_init__()
    ...         self.convert("b")
    ...         self.convert("along")
    ...     def expressions(self):
    ...         return {"b": self.b, "along": self.along}
    ...     def work(self, motion):
    ...         along = motion.position(self.along, self.name)
    ...         return md.Work(forces=((-motion.plain(self.b) * motion.rate(along), along),))
    >>> phi = md.coordinate("phi")
    >>> fan = md.Mechanism("fan", [phi])
    >>> _ = fan.link("rotor", J=2, angle=phi)
    >>> _ = fan.add(Drag("air", b=3, along=phi))
    >>> fan.reduced_moment()
    -3*phidot
    """
    name: str
    tags: tuple = field(default=(), kw_only=True)

    DEPENDS: ClassVar[dict] = {}
    MOVING: ClassVar[tuple] = ()
    RULES: ClassVar[dict] = {}

    def __post_init__(self):
        if not isinstance(self.name, str) or not self.name:
            raise DeclarationError(f"element name must be a non-empty string, got {self.name!r}")
        object.__setattr__(self, "tags", _tags(self.tags))

    def convert(self, attribute: str, nonnegative=False):
        """Replace the attribute's value by a sympy expression (numbers and expressions;
        strings are refused); call it in ``__post_init__`` for each expression."""
        what = f"{type(self).__name__.lower()} {self.name!r}: {attribute}"
        expr = as_expression(getattr(self, attribute), what)
        if nonnegative:
            _nonnegative(expr, what)
        object.__setattr__(self, attribute, expr)

    def expressions(self) -> dict:
        """The element's expressions by attribute name (each is checked for its
        dependencies, parameters and units)."""
        return {}

    def work(self, motion) -> Work:
        """Its share of the equations of motion, written with ``motion`` (see the
        module)."""
        return Work()

    def printed(self) -> tuple:
        """``(element, values)``: the element as the printed derivation writes it and
        ``{symbol: (value, label)}`` of the symbols it writes there for numbers
        (standard gravity's ``g``); by default itself and none."""
        return self, {}

    def check_units(self, units) -> None:
        """Check the dimensions of its attributes with ``units`` (``units.need``,
        ``units.work``, ``units.same`` of :mod:`mechdyn.declare.dimensions`)."""

    def output(self, eqs):
        """The force or moment this element records as a scene output, written in the
        plain symbols of the derived equations ``eqs``; by default the value of its one
        force, None when it has not exactly one."""
        work = eqs.works.get(self.name)
        forces = work.forces if work is not None else ()
        return forces[0][0] if len(forces) == 1 else None

    def output_along(self):
        """What the output acts along (its unit is energy per unit of this); by default
        the attribute ``along``, None without one."""
        return getattr(self, "along", None)


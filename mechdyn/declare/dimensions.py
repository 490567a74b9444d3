"""Dimension checks: every element's contribution to every equation of motion.

With units declared for its parameters (``Mechanism(..., units={P: "N", R: "m"})``),
a mechanism's equation of the coordinate ``q`` holds terms of one dimension, energy per
unit of ``q``: a moment for an angle (angles are dimensionless), a force for a length.
:func:`check_elements` checks each element where it is declared — a link's mass, inertia
and positions, a load's ``value * d(along)/dq``, a spring's ``k stretch d(stretch)/dq``,
a damper's, gravity's ``g``, a friction element's — and :func:`check_equations` every
term of the derived equations; a misfit raises a :class:`~mechdyn.DeclarationError`
naming the element and both dimensions.

Numbers: exact ones (2, 1/2, pi) are dimensionless; a decimal written into an expression
(9.81) is an SI value whose unit mechdyn cannot know, so the term holding it adopts the
dimension its place needs (and goes unchecked). An element attribute given as a bare
number (``m=2``) is SI.

>>> import sympy as sp, mechdyn as md
>>> phi = md.coordinate("phi")
>>> l, F, J = sp.symbols("l F J", positive=True)
>>> yoke = md.Mechanism("yoke", [phi], units={l: "m", F: "N", J: "kg*m^2"})
>>> _ = yoke.link("crank", J=J, angle=phi)
>>> _ = yoke.load("resistance", F, along=phi)
>>> yoke.check_dimensions()
Traceback (most recent call last):
...
mechdyn.errors.DeclarationError: load 'resistance': value * d(along)/dphi has dimension N (a force) but the equation of phi needs N*m (a moment)
"""
from __future__ import annotations

from fractions import Fraction

import sympy as sp
from sympy.core.function import AppliedUndef

from mechdyn.declare.contract import call
from mechdyn.errors import DeclarationError
from mechdyn.symbols import dotted_symbol, t
from mechdyn.units import DIMENSIONLESS, Dimension, dimension

__all__ = ["check_elements", "check_equations", "dimension_of", "UnitCheck",
           "Misfit", "MissingUnit"]

ANY = None                     # a decimal's unknown dimension: fits anything
TIME = Dimension({"[time]": 1})
ENERGY = Dimension({"[mass]": 1, "[length]": 2, "[time]": -2})
_PLAIN_FUNCTIONS = (sp.sin, sp.cos, sp.tan, sp.cot, sp.sec, sp.csc, sp.asin, sp.acos,
                    sp.atan, sp.acot, sp.sinh, sp.cosh, sp.tanh, sp.asinh, sp.acosh,
                    sp.atanh, sp.exp, sp.log)


class Misfit(Exception):
    """Terms of different dimensions combined (``parts``: pairs of term and dimension)."""

    def __init__(self, expr, parts, why="adds"):
        super().__init__(expr)
        self.expr, self.parts, self.why = expr, parts, why

    def __str__(self):
        (a, da), (b, db) = self.parts
        if self.why == "argument":
            return f"{a} takes a dimensionless argument, but {b} has dimension {db.si}"
        return f"{self.why} {b} ({_short(db)}) to {a} ({_short(da)})"


class MissingUnit(Exception):
    """A symbol without a declared unit."""


# ------------------------------------------------------------------- the algebra
def dimension_of(expr, known: dict):
    """The dimension of a sympy expression in plain symbols, ``known``: symbol ->
    :class:`~mechdyn.units.Dimension`; None when a decimal makes it unknowable.
    Raises :class:`Misfit` for sums of unlike terms, :class:`MissingUnit` for symbols
    without a dimension."""
    return _walk(sp.sympify(expr), known, {})


def _walk(expr, known, memo):
    if expr in memo:
        return memo[expr]
    if expr.is_zero:
        result = ANY                       # zero fits every dimension
    elif expr.is_Symbol:
        if expr not in known:
            raise MissingUnit(expr)
        result = known[expr]
    elif expr.is_Float:
        result = ANY
    elif expr.is_number and not expr.free_symbols:
        result = ANY if expr.has(sp.Float) else DIMENSIONLESS
    elif isinstance(expr, (sp.Add, sp.Min, sp.Max)):
        result = _same(expr, expr.args, known, memo)
    elif isinstance(expr, sp.Mul):
        dims = [_walk(a, known, memo) for a in expr.args]
        result = ANY if ANY in dims else _product(dims)
    elif isinstance(expr, sp.Pow):
        result = _power(expr, known, memo)
    elif isinstance(expr, sp.Piecewise):
        for _, condition in expr.args:
            _walk_condition(condition, known, memo)
        result = _same(expr, [value for value, _ in expr.args], known, memo)
    elif isinstance(expr, (sp.sign, sp.Heaviside)):
        _walk(expr.args[0], known, memo)
        result = DIMENSIONLESS
    elif isinstance(expr, (sp.Abs, sp.re, sp.im, sp.floor, sp.ceiling)):
        result = _walk(expr.args[0], known, memo)
    elif isinstance(expr, (sp.atan2, sp.Mod)):
        dim = _same(expr, expr.args, known, memo)
        result = DIMENSIONLESS if isinstance(expr, sp.atan2) else dim
    elif isinstance(expr, _PLAIN_FUNCTIONS):
        for argument in expr.args:
            dim = _walk(argument, known, memo)
            if dim is not ANY and not dim.dimensionless:
                raise Misfit(expr, [(expr.func.__name__, None), (argument, dim)], "argument")
        result = DIMENSIONLESS
    else:                                  # an unknown function: its arguments only
        for argument in expr.args:
            if isinstance(argument, sp.Expr):
                _walk(argument, known, memo)
        result = ANY
    memo[expr] = result
    return result


def _same(expr, terms, known, memo):
    first = None
    for term in terms:
        dim = _walk(term, known, memo)
        if dim is ANY:
            continue
        if first is None:
            first = (term, dim)
        elif dim != first[1]:
            raise Misfit(expr, [first, (term, dim)],
                         "compares" if isinstance(expr, sp.core.relational.Relational)
                         else "adds")
    return None if first is None else first[1]


def _product(dims):
    result = DIMENSIONLESS
    for dim in dims:
        result = result * dim
    return result


def _power(expr, known, memo):
    base, exponent = expr.args
    dim = _walk(base, known, memo)
    exponent_dim = _walk(exponent, known, memo)
    if exponent_dim is not ANY and not exponent_dim.dimensionless:
        raise Misfit(expr, [("a power", None), (exponent, exponent_dim)], "argument")
    if dim is ANY or dim.dimensionless:
        return dim
    if not exponent.is_number:
        raise Misfit(expr, [("a symbolic power", None), (base, dim)], "argument")
    return dim ** Fraction(str(sp.nsimplify(exponent))).limit_denominator(1000)


def _walk_condition(condition, known, memo):
    if isinstance(condition, sp.core.relational.Relational):
        _same(condition, condition.args, known, memo)
    elif isinstance(condition, (sp.And, sp.Or, sp.Not, sp.Xor)):
        for argument in condition.args:
            _walk_condition(argument, known, memo)


def _short(dim):
    return "dimensionless" if dim is not ANY and dim.dimensionless else dim.si


# --------------------------------------------------------------- the mechanism
def known_dimensions(mechanism) -> dict:
    """Plain symbol -> dimension: coordinates (their declared units, rad by default),
    speeds, accelerations, the time and every parameter with a declared unit."""
    known = {t: TIME}
    for q in mechanism.coordinates:
        name = q.func.__name__
        dim = dimension(mechanism.units.get(name, "rad"))
        known[dotted_symbol(name, 0)] = dim
        known[dotted_symbol(name, 1)] = dim / TIME
        known[dotted_symbol(name, 2)] = dim / TIME ** 2
    for name, unit in mechanism.parameter_units.items():
        known[sp.Symbol(name)] = dimension(unit)
    return known


def _plain(expr):
    """Plain symbols for coordinates and speeds, every symbol without its assumptions
    (parameters are matched by name)."""
    from mechdyn.symbols import plain
    expr = sp.sympify(expr)
    expr = expr.xreplace({d: plain(d) for d in expr.atoms(sp.Derivative)})
    expr = expr.xreplace({f: plain(f) for f in expr.atoms(AppliedUndef)})
    return expr.xreplace({s: sp.Symbol(s.name) for s in expr.free_symbols
                          if isinstance(s, sp.Symbol)})


def _by_name(known):
    return {sp.Symbol(s.name): d for s, d in known.items()}


def _dims(expr, known, what):
    """The dimension of an element attribute or a term; a bare number is SI (ANY)."""
    plain = _plain(expr)
    if plain.is_number:
        return ANY
    try:
        return _walk(plain, known, {})
    except Misfit as misfit:
        raise DeclarationError(f"{what}: {misfit}") from None


def check_elements(mechanism):
    """Check the dimension of every element's contribution (see the module)."""
    known = _by_name(known_dimensions(mechanism))
    missing = _missing_units(mechanism, known)
    if missing:
        declared = "declares units, but not" if mechanism.parameter_units else \
            "declares no units of its parameters, not even"
        raise DeclarationError(
            f"mechanism {mechanism.name!r} {declared} for "
            f"{', '.join(missing)}; add them to units={{...}} ('1' for a dimensionless "
            "parameter)")
    for element in mechanism.elements.values():
        _check_element(element, known, mechanism)


def _missing_units(mechanism, known):
    symbols = set()
    for element in mechanism.elements.values():
        for expr in element.expressions().values():
            symbols |= _plain(expr).free_symbols
        for point in getattr(element, "points", ()):
            for expr in point:
                symbols |= _plain(expr).free_symbols
    return sorted({s.name for s in symbols if sp.Symbol(s.name) not in known})


def _check_element(element, known, mechanism):
    check = UnitCheck(element, known, mechanism)
    call(element, "check_units", check)
    for index, point in enumerate(getattr(element, "points", ())):
        for axis, expr in zip("xy", point):
            dim = _dims(expr, known, f"{check.label}: point {index} {axis}")
            if dim is not ANY and dim != dimension("m"):
                raise DeclarationError(f"{check.label}: point {index} {axis} = {_plain(expr)} "
                                       f"has dimension {_short(dim)} but a position needs m")


class UnitCheck:
    """What an element's ``check_units`` checks its attributes with (by attribute
    name): a unit one needs (:meth:`need`), the work of a force along a displacement
    against the equation it enters (:meth:`work`), two of one dimension (:meth:`same`).
    An attribute given as a bare or decimal number fits anything."""

    def __init__(self, element, known, mechanism):
        self.element, self.known, self.mechanism = element, known, mechanism
        self.label = f"{type(element).__name__.lower()} {element.name!r}"
        self.dims = {attribute: _dims(expr, known, f"{self.label}: {attribute} = "
                                                   f"{_plain(expr)}")
                     for attribute, expr in element.expressions().items()}

    def need(self, attribute, unit, word):
        """``attribute`` (when given) has the dimension of ``unit``; ``word`` names
        what needs it (``"a mass"``)."""
        have, need = self.dims.get(attribute, ANY), dimension(unit)
        if have is not ANY and have != need:
            raise DeclarationError(f"{self.label}: {attribute} = "
                                   f"{_plain(getattr(self.element, attribute))} has dimension "
                                   f"{_short(have)} but {word} needs {_short(need)}")

    def work(self, formula, along, *factors, per_time=0):
        """The force ``product of factors / time^per_time`` times ``d(along)/dq`` is
        energy per unit of ``q`` (``formula`` shows it, ``{q}`` the coordinate); an
        attribute not given fits anything."""
        dims = [self.dims.get(factor, ANY) for factor in factors]
        if ANY in dims or self.dims.get(along, ANY) is ANY:
            return
        size = _product(dims) / TIME ** per_time if per_time else _product(dims)
        _check_work(self.label, formula, size, self.dims[along],
                    getattr(self.element, along), self.known, self.mechanism)

    def same(self, attribute, other):
        """``attribute`` (when given) has the dimension of ``other``."""
        have, need = self.dims.get(attribute, ANY), self.dims.get(other, ANY)
        if ANY not in (have, need) and have != need:
            raise DeclarationError(f"{self.label}: {attribute} = "
                                   f"{_plain(getattr(self.element, attribute))} has dimension "
                                   f"{_short(have)} but {other} has {_short(need)}")


def _check_work(label, formula, size, along, along_expr, known, mechanism):
    """``size * d(along)/dq`` against the equation of the first coordinate in ``along``."""
    if size is ANY or along is ANY:
        return
    plain = _plain(along_expr)
    for q in mechanism.coordinates:
        symbol = sp.Symbol(q.func.__name__)         # plain symbols are matched by name
        if symbol in plain.free_symbols:
            break
    dq = _by_name(known)[symbol]
    have, need = size * along / dq, ENERGY / dq
    if have != need:
        raise DeclarationError(f"{label}: {formula.format(q=symbol)} has dimension "
                               f"{_named(have)} but the equation of {symbol} needs "
                               f"{_named(need)}")


def _named(dim):
    if dim == ENERGY:
        return "N*m (a moment)"
    return str(dim) if not dim.dimensionless else "dimensionless"


def check_equations(eqs, mechanism):
    """Check every term of the derived equations ``M a = f`` (see the module)."""
    known = _by_name(known_dimensions(mechanism))
    for i, qi in enumerate(eqs.q):
        need = ENERGY / known[sp.Symbol(qi.name)]
        terms = [(f"inertia term {eqs.mass_matrix[i, j] * eqs.a[j]}",
                  eqs.mass_matrix[i, j] * eqs.a[j]) for j in range(eqs.dof)
                 if eqs.mass_matrix[i, j] != 0]
        terms += [("velocity-dependent inertia forces", term)
                  for term in sp.Add.make_args(eqs.inertial_forcing[i]) if term != 0]
        terms += [(f"generalized force of {name!r}", column[i])
                  for name, column in eqs.generalized_forces.items() if column[i] != 0]
        for what, term in terms:
            dim = _dims(term, known, f"equation of {qi}: {what}")
            if dim is not ANY and dim != need:
                raise DeclarationError(f"equation of {qi}: {what} has dimension "
                                       f"{_named(dim)} but the equation needs {_named(need)}")

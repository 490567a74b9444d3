"""What a mechanism requires of its parameter values (the parameters: the symbols of its
elements' expressions and of its links' drawn points): the symbols' declared assumptions
(``positive=True``, ``integer=True``, ...) and the rules of the elements that use them
(link masses and inertias, stiffnesses, damping and friction magnitudes not negative;
efficiencies in (0, 1]). :class:`~mechdyn.declare.parameters.ParameterSet` applies them.

>>> import sympy as sp, mechdyn as md
>>> phi = md.coordinate("phi")
>>> disc = md.Mechanism("disc", [phi])
>>> _ = disc.link("disc", J=sp.Symbol("J", positive=True), angle=phi)
>>> facts = facts_of(disc)
>>> sorted(facts.symbols), facts.usage["J"]
(['J'], {"link 'disc'"})
>>> check_values(facts, {"J": -1.0}, lambda name: {facts.symbols[name]})
Traceback (most recent call last):
...
mechdyn.errors.ParameterError: parameter J = -1 is negative, but J is declared positive=True (used by link 'disc')
"""
from __future__ import annotations

import functools
import math
import weakref

import numpy as np
import sympy as sp
from sympy.core.function import AppliedUndef

from mechdyn.errors import DeclarationError, ParameterError
from mechdyn.symbols import t

__all__ = ["MechanismFacts", "facts_of", "scene_symbols", "check_values", "suspect_rows"]

# Assumptions a value is checked against: fact -> (test on the float, what it must be).
_FACTS = {
    "positive": (lambda v: v > 0, "positive"),
    "nonnegative": (lambda v: v >= 0, "zero or positive"),
    "negative": (lambda v: v < 0, "negative"),
    "nonpositive": (lambda v: v <= 0, "zero or negative"),
    "nonzero": (lambda v: v != 0, "non-zero"),
    "zero": (lambda v: v == 0, "zero"),
    "integer": (lambda v: v == int(v), "a whole number"),
    "even": (lambda v: v == int(v) and int(v) % 2 == 0, "an even number"),
    "odd": (lambda v: v == int(v) and int(v) % 2 == 1, "an odd number"),
}
_FAULTS = {       # rule -> (test, how a value breaks it): of an element's RULES
    "efficiency": (lambda v: 0 < v <= 1, "lies outside (0, 1]"),
    "fraction": (lambda v: 0 <= v <= 1, "lies outside [0, 1]"),
    "peak": (lambda v: v >= 1, "is below 1"),
    "nonnegative": (lambda v: v >= 0, "is negative"),
}


def check_values(facts, numbers, symbols_named):
    """Refuse the first value of ``numbers`` (name -> float) that breaks a declared
    assumption of its symbols (``symbols_named(name)``) or an element's rule."""
    for name, value in numbers.items():
        for symbol in symbols_named(name):
            for fact in _true_facts(symbol):
                holds, needed = _FACTS[fact]
                if not holds(value):
                    raise ParameterError(
                        f"parameter {name} = {value:g} {_violation(value, needed)}, but "
                        f"{name} is declared {_declared(symbol, fact)}=True"
                        f"{_used_by(facts, [name])}")
    values = None
    for label, attribute, expr, names, (rule, why) in facts.roles:
        if not names <= numbers.keys():
            continue
        if expr.is_Symbol:
            number = numbers[expr.name]
        else:
            values = values or {s: sp.Float(numbers[n]) for n, s in facts.symbols.items()
                                if n in numbers}
            number = _real(expr.xreplace(values))
            if number is None:
                raise ParameterError(f"parameter {', '.join(sorted(names))}: {label}: "
                                     f"{attribute} = {expr} is not a finite real number "
                                     f"with {_values_text(names, numbers)}")
        holds, breaks = _FAULTS[rule]
        fault = None if holds(number) else breaks
        if fault:
            where = "" if expr.is_Symbol else f" = {number:.6g}"
            raise ParameterError(
                f"parameter {', '.join(sorted(names))}: {label}: {attribute} = {expr}"
                f"{where} {fault} with {_values_text(names, numbers)}; {why}")


_NEAR_BOUND = 1e-9          # a computed value this close to a rule's bound: checked exactly


def suspect_rows(facts, fixed, names, columns, symbols_named) -> np.ndarray:
    """Rows of a grid that may break a rule of :func:`check_values`, all at once.

    ``columns`` (rows x ``names``, floats) vary the values ``names`` of ``fixed`` (name
    -> float, already checked). A row not flagged passes :func:`check_values`; a flagged
    one is to be checked exactly (it may pass). Element expressions are evaluated on
    the whole column in floating point, so a value within ``_NEAR_BOUND`` of a rule's
    bound, or not finite, is flagged too.

    >>> import sympy as sp, mechdyn as md
    >>> phi = md.coordinate("phi")
    >>> disc = md.Mechanism("disc", [phi])
    >>> _ = disc.link("disc", J=2 * sp.Symbol("J", positive=True), angle=phi)
    >>> facts = facts_of(disc)
    >>> suspect_rows(facts, {"J": 1.0}, ["J"], np.array([[1.0], [-1.0], [0.0]]),
    ...              lambda name: {facts.symbols[name]}).tolist()
    [False, True, True]
    """
    columns = np.asarray(columns, dtype=float).reshape(len(columns), len(names))
    flagged = np.zeros(len(columns), dtype=bool)
    swept = dict(zip(names, columns.T))
    for name, column in swept.items():
        for symbol in symbols_named(name):
            for fact in _true_facts(symbol):
                holds = _FACTS[fact][0]
                flagged |= [not holds(value) for value in column.tolist()]
    known = fixed.keys() | swept.keys()
    for _, _, expr, role_names, (rule, _) in facts.roles:
        if not role_names & swept.keys() or not role_names <= known:
            continue                     # checked with the fixed values, or not at all
        number = _evaluated(expr, role_names, fixed, swept, len(columns))
        holds = _FAULTS[rule][0]
        flagged |= [not (math.isfinite(v) and holds(v)) or _near_bound(v)
                    for v in number.tolist()]
    return flagged


def _evaluated(expr, role_names, fixed, swept, rows) -> np.ndarray:
    """``expr`` at every row (floats; NaN where it has no finite real value)."""
    if expr.is_Symbol:
        return np.broadcast_to(swept.get(expr.name, fixed.get(expr.name)), rows)
    symbols = sorted(expr.free_symbols, key=lambda s: s.name)
    try:
        function = _lambdified(expr, tuple(symbols))
        with np.errstate(all="ignore"):
            value = np.asarray(function(*(swept[s.name] if s.name in swept
                                          else fixed[s.name] for s in symbols)))
        if np.iscomplexobj(value):
            value = np.where(value.imag == 0, value.real, np.nan)
        return np.broadcast_to(value.astype(float), rows)
    except Exception:                    # not evaluable in numpy: every row exactly
        return np.full(rows, np.nan)


@functools.lru_cache(maxsize=256)
def _lambdified(expr, symbols):
    return sp.lambdify(symbols, expr, "numpy")


def _near_bound(value) -> bool:
    """Within ``_NEAR_BOUND`` of 0 or 1, the bounds of the rules in ``_FAULTS``."""
    return min(abs(value), abs(value - 1.0)) <= _NEAR_BOUND * max(1.0, abs(value))


def _used_by(facts, names) -> str:
    users = sorted({user for name in names for user in facts.usage.get(name, ())})
    return f" (used by {', '.join(users)})" if users else ""


class MechanismFacts:
    """What a mechanism says about its parameters: symbols by name, the elements using
    each, and the element attributes with a sign rule."""

    def __init__(self, mechanism=None):
        self.symbols, self.usage, self.roles = {}, {}, []
        if mechanism is None:
            return
        for element in mechanism.elements.values():
            label = f"{type(element).__name__.lower()} {element.name!r}"
            drawn = {f"points[{k}]": sp.Tuple(*point)               # a link's outline
                     for k, point in enumerate(getattr(element, "points", ()))}
            for attribute, expr in {**element.expressions(), **drawn}.items():
                free = expr.free_symbols - {t}
                for symbol in free:
                    other = self.symbols.setdefault(symbol.name, symbol)
                    if other != symbol:
                        raise DeclarationError(
                            f"{mechanism.name!r}: two different parameters are named "
                            f"{symbol.name!r} (their assumptions differ: "
                            f"{_assumption_text(other)} and {_assumption_text(symbol)}); "
                            "declare each parameter once and reuse its symbol")
                    self.usage.setdefault(symbol.name, set()).add(label)
                rule = getattr(element, "RULES", {}).get(attribute)
                if rule and free and not expr.has(AppliedUndef, sp.Derivative, t):
                    self.roles.append((label, attribute, expr, {s.name for s in free}, rule))


_facts_cache: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def facts_of(mechanism) -> MechanismFacts:
    """The mechanism's :class:`MechanismFacts`, remembered while its elements stay the
    same."""
    signature = tuple(map(id, mechanism.elements.values()))
    cached = _facts_cache.get(mechanism)
    if cached is None or cached[0] != signature:
        cached = (signature, MechanismFacts(mechanism))
        _facts_cache[mechanism] = cached
    return cached[1]


@functools.lru_cache(maxsize=4096)
@functools.lru_cache(maxsize=4096)
def _true_facts(symbol) -> tuple:
    """The checked assumptions (see ``_FACTS``) that hold for ``symbol``."""
    assumed = symbol.assumptions0
    return tuple(fact for fact in _FACTS if assumed.get(fact))


def scene_symbols(scene) -> set:
    """The parameters of a scene's initial values, stop conditions and outputs."""
    exprs = [v for v in scene.initial.values() if isinstance(v, sp.Basic)]
    for condition in scene.until:
        exprs += [condition.expression, condition.value]
    exprs += [o for o in scene.outputs if isinstance(o, sp.Basic)]
    return set().union(*(e.free_symbols for e in exprs)) - {t}


def _real(value):
    """A sympy number as a float, or None if it is not finite and real."""
    try:
        number = complex(value)
    except (TypeError, ValueError):
        return None
    if number.imag != 0 or not math.isfinite(number.real):
        return None
    return number.real


# ----------------------------------------------------------------------- wording
def _violation(value, needed) -> str:
    if needed in ("positive", "zero or positive") and value < 0:
        return "is negative"
    if value == 0 and needed in ("positive", "negative", "non-zero"):
        return "is zero"
    return f"is not {needed}"


def _declared(symbol, fact) -> str:
    """The assumption as the user declared it (``positive`` for a positive symbol's
    implied ``nonnegative``)."""
    original = getattr(symbol, "_assumptions_orig", None) or {}
    for given in original:
        if original[given] and sp.Symbol("x", **{given: True}).assumptions0.get(fact):
            return given
    return fact


def _assumption_text(symbol) -> str:
    original = getattr(symbol, "_assumptions_orig", None) or {}
    given = [f"{k}={v}" for k, v in original.items()]
    return f"{symbol.name}({', '.join(given)})" if given else f"{symbol.name}()"


def _values_text(names, values) -> str:
    return ", ".join(f"{n} = {values[n]:g}" for n in sorted(names))

"""Parameter values: given by symbol or by name, checked once, ordered for compiled code.

Every entry point that takes ``params`` (``simulate``, ``closed_form``,
``natural_frequencies``, periodic analysis, ``work_precision``, ``sweep``, the command
line's ``--param``) reads them through one :class:`ParameterSet`, which

- resolves keys given as symbols or as names (``{P: 20}`` and ``{"P": 20}`` are the same)
  to the mechanism's own symbols, with a model's ``params`` as defaults;
- converts each value to a float in one place, :func:`to_number` (numbers, numpy and
  sympy numbers, text read by :mod:`mechdyn.parse`; a value may also be an expression
  of other parameters);
- refuses unknown names, values that are not finite real numbers, values that violate
  the symbol's declared assumptions (``positive=True`` given -20) and values that break
  the element using them (a negative link mass or inertia, spring stiffness, damping or
  friction magnitude; an efficiency outside (0, 1]), naming the parameter and the
  elements that use it;
- gives the ordered vector of floats the compiled code takes, or exact values for the
  closed forms.

>>> import mechdyn as md
>>> brake = md.load_model("models/shoe_brake.py")
>>> values = ParameterSet({"P": 30}, defaults=brake.params, mechanism=brake.mechanism)
>>> values.vector(["I", "P", "R", "f"])
[0.4, 30.0, 0.1, 0.2]
>>> ParameterSet({"P": -20}, defaults=brake.params, mechanism=brake.mechanism)
Traceback (most recent call last):
...
mechdyn.errors.ParameterError: parameter P = -20 is negative, but P is declared positive=True (used by friction 'shoe')
"""
from __future__ import annotations

import difflib
import functools
import math
import numbers
import weakref
from collections.abc import Mapping

import sympy as sp
from sympy.core.function import AppliedUndef

from .elements import Damper, Friction, Link, Load, Spring
from .errors import DeclarationError, MechdynError, ParameterError
from .symbols import t

__all__ = ["ParameterSet", "to_number"]

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
# What the elements need of their constant attributes: (type, attribute) -> rule.
_ROLES = {
    (Link, "m"): ("nonnegative", "masses and inertias must not be negative"),
    (Link, "J"): ("nonnegative", "masses and inertias must not be negative"),
    (Spring, "k"): ("nonnegative", "a stiffness must not be negative"),
    (Damper, "c"): ("nonnegative", "a damping coefficient must not be negative"),
    (Friction, "moment"): ("nonnegative", "a friction magnitude must not be negative"),
    (Load, "efficiency"): ("efficiency", "an efficiency must lie in (0, 1]"),
}


def to_number(name: str, value) -> float:
    """The float value of parameter ``name``: the one place where a given value becomes
    a number (text goes through the restricted parser, never ``eval``).

    >>> to_number("P", "2*pi"), to_number("P", 3)
    (6.283185307179586, 3.0)
    >>> to_number("I", "__import__('os')")    # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    mechdyn.errors.ParameterError: parameter I: "__import__('os')": only numbers, ...
    """
    if isinstance(value, str):
        from .parse import number
        try:
            return number(value)
        except MechdynError as error:
            raise ParameterError(f"parameter {name}: {error}") from None
    if isinstance(value, bool) or value is None:
        raise ParameterError(f"parameter {name} = {_shown(value)} is not a number")
    if isinstance(value, sp.Basic):
        if not isinstance(value, sp.Expr) or not value.is_number:
            raise ParameterError(f"parameter {name} = {_shown(value)} is not a number")
        if value.has(sp.nan, sp.zoo):
            raise ParameterError(f"parameter values must be finite: {name} = {value}")
        value = complex(value)
    elif not isinstance(value, numbers.Number) and getattr(value, "shape", None) == ():
        value = value.item()                      # a 0-d numpy array
    if isinstance(value, numbers.Complex) and not isinstance(value, numbers.Real):
        if value.imag != 0:
            raise ParameterError(f"parameter {name} = {_shown(value)} is not a real number")
        value = value.real
    if not isinstance(value, numbers.Number):
        raise ParameterError(f"parameter {name} = {_shown(value)} is not a number")
    try:
        return float(value)
    except (OverflowError, TypeError, ValueError):
        raise ParameterError(f"parameter {name} = {_shown(value)} is not a finite "
                             "number") from None


class ParameterSet(Mapping):
    """Checked parameter values, by name.

    Parameters
    ----------
    values : dict, optional
        Parameter (symbol or name) -> value; these override ``defaults``.
    defaults : dict, optional
        Values used where ``values`` gives none (a model file's ``params``).
    mechanism : Mechanism, optional
        Knows the parameters: names are checked against it, values against the symbols'
        declared assumptions and the elements that use them.
    scene : Scene, optional
        Adds the parameters of its initial values, stop conditions and outputs.

    The mapping holds every resolved value by name: ``numbers`` (name -> float) and
    ``symbolic`` (name -> sympy expression of symbols without a value, kept for the
    closed forms).
    """

    def __init__(self, values=None, defaults=None, *, mechanism=None, scene=None):
        self.mechanism, self.scene = mechanism, scene
        facts = _facts(mechanism) if mechanism is not None else _Facts()
        self._symbols = dict(facts.symbols)
        self._usage = facts.usage
        if scene is not None:
            for symbol in _scene_symbols(scene):
                self._symbols.setdefault(symbol.name, symbol)
        raw, self._given = {}, {}
        for source, strict in ((defaults, False), (values, mechanism is not None)):
            raw.update(self._named(source, strict))
        self._raw = raw
        self.numbers, self.symbolic = _resolve(raw)
        if mechanism is not None:
            self._check_assumptions()
            self._check_roles(facts.roles)

    # ------------------------------------------------------------------ mapping
    def __getitem__(self, name):
        name = str(name)
        if name in self.numbers:
            return self.numbers[name]
        return self.symbolic[name]

    def __iter__(self):
        return iter({**self.numbers, **self.symbolic})

    def __len__(self):
        return len(self.numbers) + len(self.symbolic)

    def __repr__(self):
        shown = ", ".join(f"{k}={v!r}" for k, v in self.items())
        return f"ParameterSet({shown})"

    # ------------------------------------------------------------------ outputs
    def vector(self, names) -> list:
        """The float values of ``names``, in that order (the ``p`` of compiled code).

        All missing values are named in one error."""
        missing = [n for n in names if n not in self.numbers]
        if missing:
            unresolved = [f"{n} = {self.symbolic[n]}" for n in missing if n in self.symbolic]
            if unresolved:
                raise ParameterError(f"parameter values are not numbers: "
                                     f"{', '.join(unresolved)} (give values for "
                                     f"{', '.join(self._unresolved(missing))})")
            raise ParameterError(f"missing parameter values: {', '.join(missing)} "
                                 f"(the scene needs {', '.join(names)})")
        return [self.numbers[n] for n in names]

    def by_symbol(self) -> dict:
        """``{symbol: float}`` for every numeric value, keyed by the mechanism's symbols
        (and the symbols the values were given with): ready for ``xreplace``."""
        out = {}
        for name, value in self.numbers.items():
            for symbol in self._symbols_named(name):
                out[symbol] = value
        return out

    def exact(self) -> dict:
        """``{symbol: exact sympy value}`` for closed forms: floats become rationals
        (0.6 -> 3/5), expressions of other parameters are kept as expressions."""
        out = {}
        for name, value in self._raw.items():
            if isinstance(value, sp.Basic):
                value = exact_floats(value).xreplace(self._exact_numbers())
            elif isinstance(value, numbers.Rational):           # int, Fraction
                value = sp.Rational(value.numerator, value.denominator)
            else:
                value = exact_floats(sp.Float(self.numbers[name]))
            for symbol in self._symbols_named(name):
                out[symbol] = value
        return out

    def substitute(self, expr):
        """``expr`` with the numeric values put in (its symbols matched by name)."""
        expr = sp.sympify(expr)
        return expr.xreplace({s: sp.Float(self.numbers[s.name]) for s in expr.free_symbols
                              if s.name in self.numbers})

    # ---------------------------------------------------------------- internals
    def _named(self, source, strict) -> dict:
        """``{name: raw value}`` of one dict; unknown names refused when ``strict``."""
        if source is None:
            return {}
        if isinstance(source, ParameterSet):
            self._given.update({n: set(s) for n, s in source._given.items()})
            source = source._raw                  # the values as given: exact ones stay
        if not isinstance(source, Mapping):
            raise ParameterError(f"parameter values must be a dict {{symbol or name: "
                                 f"value}}, got {type(source).__name__}")
        named = {}
        for key, value in source.items():
            name = _key_name(key)
            if isinstance(key, sp.Symbol):
                self._given.setdefault(name, set()).add(key)
            if name in named and not _same(named[name], value):
                raise ParameterError(f"parameter {name} is given twice, as {named[name]!r} "
                                     f"and {value!r}")
            named[name] = value
        if strict:
            unknown = [n for n in named if n not in self._symbols]
            if unknown:
                raise ParameterError(self._unknown_text(unknown))
        return named

    def _unknown_text(self, unknown) -> str:
        known = sorted(self._symbols)
        hints = []
        for name in unknown:
            close = [k for k in known if k.lower() == name.lower()] or \
                difflib.get_close_matches(name, known, n=1)
            hints.append(f"{name!r}" + (f" (did you mean {close[0]!r}?)" if close else ""))
        what = self.mechanism.name if self.mechanism is not None else "the mechanism"
        return (f"unknown parameter {', '.join(hints)}: {what!r} has the parameters "
                f"{', '.join(known) or 'none'}")

    def _symbols_named(self, name) -> set:
        found = set(self._given.get(name, ()))
        if name in self._symbols:
            found.add(self._symbols[name])
        return found or {sp.Symbol(name)}

    def _unresolved(self, names) -> list:
        free = set()
        for name in names:
            if name in self.symbolic:
                free |= {s.name for s in self.symbolic[name].free_symbols}
        return sorted(free - set(self.numbers)) or sorted(names)

    def _exact_numbers(self) -> dict:
        return {s: exact_floats(sp.Float(v)) for s, v in self.by_symbol().items()}

    def _used_by(self, names) -> str:
        users = sorted({user for name in names for user in self._usage.get(name, ())})
        return f" (used by {', '.join(users)})" if users else ""

    def _check_assumptions(self):
        """Each value against the declared assumptions of its symbols."""
        for name, value in self.numbers.items():
            for symbol in self._symbols_named(name):
                for fact in _true_facts(symbol):
                    holds, needed = _FACTS[fact]
                    if not holds(value):
                        declared = _declared(symbol, fact)
                        raise ParameterError(
                            f"parameter {name} = {value:g} "
                            f"{_violation(value, needed)}, but {name} is declared "
                            f"{declared}=True{self._used_by([name])}")

    def _check_roles(self, roles):
        """The constant attributes of elements (link m and J, spring k, damper c,
        friction magnitude, efficiency) with the values put in."""
        values = None
        for label, attribute, expr, names, (rule, why) in roles:
            if not names <= self.numbers.keys():
                continue
            if expr.is_Symbol:
                number = self.numbers[expr.name]
            else:
                values = values or {s: sp.Float(v) for s, v in self.by_symbol().items()}
                number = _real(expr.xreplace(values))
                if number is None:
                    raise ParameterError(f"parameter {', '.join(sorted(names))}: {label}: "
                                         f"{attribute} = {expr} is not a finite real number "
                                         f"with {_values_text(names, self.numbers)}")
            if rule == "efficiency":
                fault = None if 0 < number <= 1 else "lies outside (0, 1]"
            else:
                fault = None if number >= 0 else "is negative"
            if fault:
                where = "" if expr.is_Symbol else f" = {number:.6g}"
                raise ParameterError(
                    f"parameter {', '.join(sorted(names))}: {label}: {attribute} = {expr}"
                    f"{where} {fault} with {_values_text(names, self.numbers)}; {why}")


# ------------------------------------------------------------------ mechanism facts
class _Facts:
    """What a mechanism says about its parameters: symbols by name, the elements using
    each, and the element attributes with a sign rule."""

    def __init__(self, mechanism=None):
        self.symbols, self.usage, self.roles = {}, {}, []
        if mechanism is None:
            return
        for element in mechanism.elements.values():
            label = f"{type(element).__name__.lower()} {element.name!r}"
            for attribute, expr in element.expressions().items():
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
                rule = _ROLES.get((type(element), attribute))
                if rule and free and not expr.has(AppliedUndef, sp.Derivative, t):
                    self.roles.append((label, attribute, expr, {s.name for s in free}, rule))


_facts_cache: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def _facts(mechanism) -> _Facts:
    """The mechanism's :class:`_Facts`, remembered while its elements stay the same."""
    signature = tuple(map(id, mechanism.elements.values()))
    cached = _facts_cache.get(mechanism)
    if cached is None or cached[0] != signature:
        cached = (signature, _Facts(mechanism))
        _facts_cache[mechanism] = cached
    return cached[1]


@functools.lru_cache(maxsize=4096)
def _true_facts(symbol) -> tuple:
    """The checked assumptions (see ``_FACTS``) that hold for ``symbol``."""
    assumed = symbol.assumptions0
    return tuple(fact for fact in _FACTS if assumed.get(fact))


def _scene_symbols(scene) -> set:
    exprs = [v for v in scene.initial.values() if isinstance(v, sp.Basic)]
    for condition in scene.until:
        exprs += [condition.expression, condition.value]
    exprs += [o for o in scene.outputs if isinstance(o, sp.Basic)]
    return set().union(*(e.free_symbols for e in exprs)) - {t}


# -------------------------------------------------------------------- resolution
def _key_name(key) -> str:
    if isinstance(key, sp.Symbol):
        return key.name
    if isinstance(key, str) and key.strip():
        return key.strip()
    what = "a coordinate" if isinstance(key, AppliedUndef) else repr(key)
    raise ParameterError(f"parameter key {key!r} is {what}, not a parameter symbol or name"
                         if what != repr(key) else
                         f"parameter key {key!r} is not a parameter symbol or name")


def _resolve(raw) -> tuple:
    """``(numbers, symbolic)``: floats by name, and sympy expressions whose symbols
    have no value. Expressions of other parameters are evaluated with their values."""
    numbers_, pending, bad = {}, {}, []
    for name, value in raw.items():
        if isinstance(value, sp.Basic) and not isinstance(value, sp.Number) \
                and value.free_symbols:
            if value.has(AppliedUndef, sp.Derivative) or t in value.free_symbols:
                raise ParameterError(f"parameter {name} = {value} depends on the motion "
                                     "(a coordinate, speed or t); a parameter is a constant")
            pending[name] = value
            continue
        number = to_number(name, value)
        if not math.isfinite(number):
            bad.append(f"{name} = {number}")
        numbers_[name] = number
    if bad:
        raise ParameterError(f"parameter values must be finite: {', '.join(bad)}")
    progress = True
    while pending and progress:
        progress = False
        for name, expr in list(pending.items()):
            if {s.name for s in expr.free_symbols} <= numbers_.keys():
                value = expr.xreplace({s: sp.Float(numbers_[s.name]) for s in expr.free_symbols})
                number = to_number(name, value)
                if not math.isfinite(number):
                    raise ParameterError(f"parameter values must be finite: {name} = {expr} "
                                         f"= {number}")
                numbers_[name] = number
                del pending[name]
                progress = True
    return numbers_, pending


def _real(value):
    """A sympy number as a float, or None if it is not finite and real."""
    try:
        number = complex(value)
    except (TypeError, ValueError):
        return None
    if number.imag != 0 or not math.isfinite(number.real):
        return None
    return number.real


def _same(a, b) -> bool:
    try:
        return bool(a == b)
    except Exception:
        return a is b


def exact_floats(expr):
    """Floats -> exact rationals (0.6 -> 3/5); everything else unchanged."""
    return expr.xreplace({f: sp.nsimplify(f, rational=True) for f in expr.atoms(sp.Float)})


# ----------------------------------------------------------------------- wording
def _shown(value) -> str:
    """A value as an error message shows it: short, strings quoted."""
    if isinstance(value, float):
        return f"{value:g}"
    text = repr(value) if isinstance(value, (str, list, tuple, dict, type(None))) \
        else str(value)
    return text if len(text) <= 40 else text[:37] + "..."


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

"""Parameter values: given by symbol or by name, checked once, ordered for compiled code.

Every entry point that takes ``params`` reads them through one :class:`ParameterSet`
before it derives or compiles anything (the list: ``tests/test_parameter_entry_points.py``),
which

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
  closed forms; a value still missing where one is needed is named by
  :func:`missing_values`, the one wording of that error.

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
from collections.abc import Mapping

import sympy as sp
from sympy.core.function import AppliedUndef

from mechdyn.errors import MechdynError, ParameterError
from mechdyn.declare.parameter_rules import (MechanismFacts, check_values, facts_of, scene_symbols,
                                            suspect_rows)
from mechdyn.symbols import t

__all__ = ["ParameterSet", "to_number", "missing_values"]

@functools.lru_cache(maxsize=4096)
def _sympy_complex(value) -> complex:
    """``complex(value)`` of a sympy number (an evalf: about 0.1 ms), kept."""
    return complex(value)


def to_number(name: str, value, unit=None) -> float:
    """The float value (SI) of parameter ``name``: the one place where a given value
    becomes a number. Text goes through the restricted parser, never ``eval``, and may
    carry a unit (``"2 kN"``), checked against the parameter's declared ``unit``; a
    pint quantity is converted the same way.

    >>> to_number("P", "2*pi"), to_number("P", 3), to_number("P", "0.02 kN", "N")
    (6.283185307179586, 3.0, 20.0)
    >>> to_number("I", "__import__('os')")    # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    mechdyn.errors.ParameterError: parameter I: "__import__('os')": ...
    """
    if type(value) is float:                      # the common case, first (large models)
        return value
    if isinstance(value, str) or hasattr(value, "dimensionality"):
        from mechdyn.units import to_si
        try:
            return to_si(value, unit)
        except MechdynError as error:
            raise ParameterError(f"parameter {name}: {error}") from None
    if isinstance(value, bool) or value is None:
        raise ParameterError(f"parameter {name} = {_shown(value)} is not a number")
    if isinstance(value, sp.Basic):
        if not isinstance(value, sp.Expr) or not value.is_number:
            raise ParameterError(f"parameter {name} = {_shown(value)} is not a number")
        if value.has(sp.nan, sp.zoo):
            raise ParameterError(f"parameter values must be finite: {name} = {value}")
        value = _sympy_complex(value)
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


def missing_values(names, needed_by, owner=None) -> ParameterError:
    """The error for parameters that have no value where one is needed (every entry
    point words it so): ``owner`` names the mechanism, ``needed_by`` what needs them.

    >>> print(missing_values(["P", "R"], "the scene 'braking'", "Shoe brake"))
    'Shoe brake': give values for P, R (needed by the scene 'braking')
    """
    names = ", ".join(dict.fromkeys(str(n) for n in names))
    return ParameterError(f"{'' if owner is None else repr(owner) + ': '}give values for "
                          f"{names} (needed by {needed_by})")


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
        facts = facts_of(mechanism) if mechanism is not None else MechanismFacts()
        self._symbols = dict(facts.symbols)
        if scene is not None:
            for symbol in scene_symbols(scene):
                self._symbols.setdefault(symbol.name, symbol)
        raw, self._given = {}, {}
        for source, strict in ((defaults, False), (values, mechanism is not None)):
            raw.update(self._named(source, strict))
        self._raw = raw
        self.numbers, self.symbolic = _resolve(raw, getattr(mechanism, "parameter_units", None))
        if mechanism is not None:
            check_values(facts, self.numbers, self._symbols_named)

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
    def vector(self, names, needed_by=None) -> list:
        """The float values of ``names``, in that order (the ``p`` of compiled code).

        All missing values are named in one error (:func:`missing_values`; ``needed_by``
        says what needs them, by default the scene)."""
        missing = [n for n in names if n not in self.numbers]
        if missing:
            unresolved = [f"{n} = {self.symbolic[n]}" for n in missing if n in self.symbolic]
            if unresolved:
                raise ParameterError(f"parameter values are not numbers: "
                                     f"{', '.join(unresolved)} (give values for "
                                     f"{', '.join(self._unresolved(missing))})")
            scene = "the scene" if self.scene is None else f"the scene {self.scene.name!r}"
            raise missing_values(missing, needed_by or f"{scene}: {', '.join(names)}",
                                 getattr(self.mechanism, "name", None))
        return [self.numbers[n] for n in names]

    def refused_points(self, names, points) -> dict:
        """``{index: ParameterError}``: the points (float values of ``names``, each
        overriding these numbers) that ``ParameterSet`` refuses, with the error it raises;
        the rules are applied to all points at once, and only the suspect points are
        checked one by one (a sweep's grid).

        >>> import mechdyn as md
        >>> brake = md.load_model("models/shoe_brake.py")
        >>> values = ParameterSet(brake.params, mechanism=brake.mechanism)
        >>> print(values.refused_points(["P"], [(10.0,), (-5.0,)])[1])
        parameter P = -5 is negative, but P is declared positive=True (used by friction 'shoe')
        """
        if self.mechanism is None or not points:
            return {}
        if set(names) <= self._symbols.keys() and not self.depending_on(names):
            suspects = suspect_rows(facts_of(self.mechanism), self.numbers, list(names),
                                    points, self._symbols_named)
        else:
            suspects = [True] * len(points)          # unknown names: the exact error
        refused = {}
        for index in (i for i, suspect in enumerate(suspects) if suspect):
            try:
                ParameterSet({**self.numbers, **self.depending_on(names),
                              **dict(zip(names, points[index]))},
                             mechanism=self.mechanism, scene=self.scene)
            except ParameterError as error:
                refused[index] = error
        return refused

    def depending_on(self, names) -> dict:
        """``{name: expression}`` of the values given as expressions of ``names``,
        directly or through each other: what changes with them (a sweep's points).

        >>> P, Q, R = sp.symbols("P Q R")
        >>> ParameterSet({P: 20, Q: 3 * P, R: Q + 1}).depending_on(["P"])
        {'Q': 3*P, 'R': Q + 1}
        """
        found, changed = {}, {str(name) for name in names}
        while True:
            more = {name: value for name, value in self._raw.items()
                    if name not in found and name not in changed
                    and isinstance(value, sp.Basic)
                    and {s.name for s in value.free_symbols} & (changed | found.keys())}
            if not more:
                return found
            found.update(more)

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

    def dependent(self) -> dict:
        """``{name: expression}`` of the values given as expressions of other
        parameters (``{Q: 2*k}``), as given."""
        return {name: value for name, value in self._raw.items()
                if isinstance(value, sp.Basic) and value.free_symbols}

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

# -------------------------------------------------------------------- resolution
def _key_name(key) -> str:
    if isinstance(key, sp.Symbol):
        return key.name
    if isinstance(key, str) and key.strip():
        return key.strip()
    kind = "a coordinate, " if isinstance(key, AppliedUndef) else ""
    raise ParameterError(f"parameter key {key!r} is {kind}not a parameter symbol or name")


def _resolve(raw, units=None) -> tuple:
    """``(numbers, symbolic)``: floats by name, and sympy expressions whose symbols
    have no value. Expressions of other parameters are evaluated with their values;
    ``units`` (name -> declared unit) checks values given with units."""
    units = units or {}
    numbers_, pending, bad = {}, {}, []
    for name, value in raw.items():
        if isinstance(value, sp.Basic) and not isinstance(value, sp.Number) \
                and value.free_symbols:
            if value.has(AppliedUndef, sp.Derivative) or t in value.free_symbols:
                raise ParameterError(f"parameter {name} = {value} depends on the motion "
                                     "(a coordinate, speed or t); a parameter is a constant")
            pending[name] = value
            continue
        number = to_number(name, value, units.get(name))
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

"""Names that must not clash. Coordinates, their speeds and accelerations (``qdot``,
``qddot``: the names the derivation gives them), the time ``t`` and the parameters all
meet as symbols in the derivation and in ``params`` dicts keyed by name, so two
declarations of one name would silently be one quantity: refused, naming both.

>>> import sympy as sp, mechdyn as md
>>> q = md.coordinate("q")
>>> check_parameters("spring 'k': stretch", sp.Symbol("q", real=True) - q, {}, [q])
Traceback (most recent call last):
...
mechdyn.errors.DeclarationError: spring 'k': stretch: the parameter q has the name of the coordinate q; rename the parameter
"""
from __future__ import annotations

import functools
import re

import sympy as sp

from mechdyn.errors import DeclarationError
from mechdyn.symbols import dotted_symbol, t

__all__ = ["check_coordinates", "check_parameters", "generated_names"]

# Symbols the code generator makes (friction signs, sides of switching functions: real
# symbols s0, s1, ..., w0, w1, ...); a parameter is one of them only if it is named so
# and declared real=True alone.
_INTERNAL = re.compile(r"[sw]\d+")


def generated_names(coordinates) -> dict:
    """Every name mechdyn gives a symbol of its own: name -> what it is."""
    names = {"t": "the time t"}
    for q in coordinates:
        name = q.func.__name__
        names[name] = f"the coordinate {name}"
        names[dotted_symbol(name, 1).name] = f"the speed of the coordinate {name}"
        names[dotted_symbol(name, 2).name] = f"the acceleration of the coordinate {name}"
    return names


@functools.lru_cache(maxsize=64)
def _reserved(coordinates) -> dict:
    """:func:`generated_names` of a tuple of coordinates, remembered: every element
    added is checked against them (a 200-disc chain: 600 elements, each re-checking all
    the others, took minutes to declare)."""
    return generated_names(coordinates)


def check_coordinates(mechanism, coordinates):
    """Refuse a coordinate named ``t`` or named as another coordinate's speed or
    acceleration (``x`` and ``xdot``)."""
    seen = {"t": "the time t"}
    for q in coordinates:
        own = generated_names([q])
        del own["t"]
        for text, what in own.items():
            if text in seen:
                raise DeclarationError(f"mechanism {mechanism!r}: {what} is named {text}, "
                                       f"the name of {seen[text]}; rename the coordinate")
        seen.update(own)


def check_parameters(what, expr, known: dict, coordinates):
    """Refuse a parameter symbol of ``expr`` (declared in ``what``) that has the name of
    the time, a coordinate, a speed or acceleration, a symbol of mechdyn's own, or of
    another parameter symbol in ``known`` (name -> (symbol, where), updated here)."""
    reserved = _reserved(tuple(coordinates))
    for symbol in sorted(sp.sympify(expr).free_symbols - {t}, key=str):
        name = symbol.name
        if name in reserved:
            raise DeclarationError(f"{what}: the parameter {name} has the name of "
                                   f"{reserved[name]}; rename the parameter")
        if _INTERNAL.fullmatch(name) and symbol == sp.Symbol(name, real=True):
            raise DeclarationError(f"{what}: the parameter {name} declared real=True is "
                                   "one of the symbols mechdyn makes for itself (friction "
                                   "signs s0, s1, ..., switch sides w0, w1, ...); rename it "
                                   "or declare it otherwise (positive=True, ...)")
        if name in known and known[name][0] != symbol:
            other, where = known[name]
            raise DeclarationError(
                f"{what}: the parameter {name} ({_facts(symbol)}) is another symbol than "
                f"the parameter {name} of {where} ({_facts(other)}); one name must be one "
                "symbol: declare it once and use it in both")
        known.setdefault(name, (symbol, what))


def _facts(symbol) -> str:
    given = getattr(symbol, "_assumptions_orig", None) or {}
    facts = [f"{k}={v}" for k, v in sorted(given.items()) if k != "commutative"]
    return "declared " + ", ".join(facts) if facts else "declared without assumptions"

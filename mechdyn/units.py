"""Units: values typed with units, the dimensions of declared units, display units.

Bare numbers are SI (kg, m, s, N, N m, W; angles in rad, speeds in rad/s), so every
model works without units. A value may carry one: :func:`to_si` reads numbers,
texts such as ``"2 kN"``, ``"1500 rpm"``, ``"20 mm"`` (read by the restricted parser
:func:`mechdyn.parse.quantity`: a number, then unit names looked up one at a time) and
pint quantities, checks the dimension against the unit expected and returns the SI
value. Units come from pint, imported on first need only: each unit's dimension and SI
factor is remembered in mechdyn's cache folder, so a warm run imports no pint.

Examples
--------
>>> to_si("0.02 kN", "N")
20.0
>>> to_si("1500 rpm", "rad/s")        # 50 pi
157.07963267948966
>>> to_si("20 mm")                    # no unit expected: SI base units
0.02
>>> to_si("2 kg", "N")
Traceback (most recent call last):
...
mechdyn.units.UnitError: '2 kg': kg is a mass but N (a force) is expected
>>> convert([157.07963267948966], "rad/s", "rpm")
array([1500.])
"""
from __future__ import annotations

import functools
import math
import re
from fractions import Fraction

import numpy as np

from mechdyn.errors import MechdynError, did_you_mean
from mechdyn.parse import ValueTextError, quantity, unit_terms

__all__ = ["UnitError", "Dimension", "DIMENSIONLESS", "to_si", "dimension", "convert",
           "si_factor", "registry", "finite"]

_BASES = {"[mass]": "kg", "[length]": "m", "[time]": "s", "[current]": "A",
          "[temperature]": "K", "[substance]": "mol", "[luminosity]": "cd"}


class UnitError(MechdynError, ValueError):
    """An unknown unit, or a value whose dimension does not fit.

    Examples
    --------
    >>> import mechdyn as md
    >>> try:
    ...     md.to_si("1500 rpm", "N*m")
    ... except md.UnitError as error:
    ...     print(error)
    '1500 rpm': rpm (read as revolutions_per_minute) is a rate or angular speed but N*m (a moment or an energy) is expected
    """


class Dimension:
    """A physical dimension: exponents of mass, length, time, ... (angles count as
    dimensionless, as in SI). ``Dimension.of("N*m")``; multiply, divide, raise."""
    __slots__ = ("exponents",)

    def __init__(self, exponents=()):
        items = exponents.items() if isinstance(exponents, dict) else exponents
        self.exponents = frozenset((base, Fraction(power)) for base, power in items
                                   if Fraction(power) != 0)

    @classmethod
    def of(cls, unit: str) -> "Dimension":
        """The dimension of a unit expression (``"kg*m^2"``)."""
        return dimension(unit)

    def __mul__(self, other):
        return self._combine(other, 1)

    def __truediv__(self, other):
        return self._combine(other, -1)

    def _combine(self, other, sign):
        powers = dict(self.exponents)
        for base, power in other.exponents:
            powers[base] = powers.get(base, 0) + sign * power
        return Dimension(powers)

    def __pow__(self, exponent):
        return Dimension({base: power * Fraction(exponent) for base, power in self.exponents})

    def __eq__(self, other):
        return isinstance(other, Dimension) and self.exponents == other.exponents

    def __hash__(self):
        return hash(self.exponents)

    @property
    def dimensionless(self) -> bool:
        return not self.exponents

    @property
    def si(self) -> str:
        """The SI unit: a named one (``N``, ``W``) or a product of base units."""
        if self in _NAMED:
            return _NAMED[self][0]
        ordered = sorted(self.exponents, key=lambda item: list(_BASES).index(item[0]))
        up = [_power(_BASES[b], p) for b, p in ordered if p > 0]
        down = [_power(_BASES[b], -p) for b, p in ordered if p < 0]
        return "*".join(up or ["1"]) + "".join("/" + d for d in down)

    def __str__(self):
        name = _NAMED.get(self, (None, ""))[1]
        return f"{self.si} ({name})" if name else self.si

    def __repr__(self):
        return f"Dimension({self.si!r})"


def _power(unit, power):
    return unit if power == 1 else f"{unit}^{power}" if power.denominator == 1 \
        else f"{unit}^({power})"


def _dim(**powers):
    return Dimension({f"[{base}]": p for base, p in powers.items()})


DIMENSIONLESS = Dimension()
_NAMED = {
    DIMENSIONLESS: ("1", "dimensionless"),
    _dim(mass=1): ("kg", "a mass"), _dim(length=1): ("m", "a length"),
    _dim(time=1): ("s", "a time"), _dim(time=-1): ("1/s", "a rate or angular speed"),
    _dim(time=-2): ("1/s^2", "an angular acceleration"),
    _dim(length=1, time=-1): ("m/s", "a velocity"),
    _dim(length=1, time=-2): ("m/s^2", "an acceleration"),
    _dim(mass=1, length=1, time=-2): ("N", "a force"),
    _dim(mass=1, length=2, time=-2): ("N*m", "a moment or an energy"),
    _dim(mass=1, length=2, time=-3): ("W", "a power"),
    _dim(mass=1, length=2): ("kg*m^2", "a moment of inertia"),
    _dim(mass=1, time=-2): ("N/m", "a stiffness"),
    _dim(mass=1, time=-1): ("N*s/m", "a damping coefficient"),
    _dim(mass=1, length=2, time=-1): ("N*m*s", "a torsional damping coefficient"),
    _dim(mass=1, length=-1, time=-2): ("Pa", "a pressure"),
}


# ------------------------------------------------------------------------- pint
_REGISTRY = None
_KNOWN: dict = {}          # unit text -> facts (dimension, SI factor, angle power, ...)
_DISK_LOADED = False


def registry():
    """pint's unit registry (imported and built on first use; ``rev`` added)."""
    global _REGISTRY
    if _REGISTRY is None:
        try:
            import pint
        except ImportError:
            raise UnitError("units need pint: pip install pint") from None
        # No pint disk cache: it pickles, and mechdyn's cache holds only authenticated
        # entries (docs/security.md); units.json below spares pint's import instead.
        _REGISTRY = pint.UnitRegistry()
        _REGISTRY.define("rev = revolution")
    return _REGISTRY


def _facts(terms) -> dict:
    """Dimension, SI factor, angle power and flags of unit terms, remembered in memory
    and in the cache folder (pint is imported only for units never seen before)."""
    key = "*".join(f"{name}^{power}" for name, power in terms)
    if key not in _KNOWN:
        _load_disk()
    if key not in _KNOWN:
        _KNOWN[key] = _facts_from_pint(terms)
        _save_disk()
    if "number_" in _KNOWN[key]["reads"]:        # pint: "Nm" is number_meter, 1e-9 m
        raise UnitError(f"{_text(terms)!r} would be read as {_KNOWN[key]['reads']} "
                        "(pint's reading), not newton metres: write N*m (or kN*m)")
    return _KNOWN[key]


_COMMON = ("rpm", "rps", "rad", "deg", "degree", "rev", "turn", "N", "kN", "MN", "kg", "g",
           "t", "m", "mm", "cm", "km", "s", "ms", "min", "h", "W", "kW", "MW", "J", "kJ", "Pa",
           "kPa", "MPa", "GPa", "bar", "Hz")       # suggested first for a misspelt unit


def _facts_from_pint(terms) -> dict:
    reg = registry()
    unit = reg.dimensionless
    for name, power in terms:
        try:
            unit = unit * reg.Unit(name) ** power
        except Exception:           # pint's UndefinedUnitError and parse errors
            hint = _power_hint(terms, name) or did_you_mean(name, _COMMON) \
                or did_you_mean(name, list(reg))
            raise UnitError(f"unknown unit {name!r}{hint}") from None
    base = reg.Quantity(1.0, unit).to_base_units()
    if reg.Quantity(0.0, unit).to_base_units().magnitude != 0:
        raise UnitError(f"{_text(terms)} has an offset (like degC); give such values in "
                        "their absolute unit")
    return {"dimension": {k: str(Fraction(v).limit_denominator())
                          for k, v in dict(unit.dimensionality).items() if v != 0},
            "factor": float(base.magnitude),
            # the powers of the base units: to_tuple() is pint's public form of them
            "angle": str(Fraction(dict(base.to_tuple()[1]).get("radian", 0)).limit_denominator()),
            "cycles": any("hertz" in str(reg.Unit(name)) for name, _ in terms),
            "reads": " * ".join(str(reg.Unit(name)) for name, _ in terms)}


def _load_disk():
    global _DISK_LOADED
    if _DISK_LOADED:
        return
    _DISK_LOADED = True
    from mechdyn import cache
    stored = cache.load("units.json") or {}          # authenticated, else None
    if isinstance(stored, dict):
        for key, facts in stored.items():
            _KNOWN.setdefault(key, facts)


def _save_disk():
    from mechdyn import cache
    cache.store("units.json", _KNOWN)   # a read-only home only costs pint's import


def _power_hint(terms, name) -> str:
    """A unit glued to its power (``m2`` in ``kg m2``): the whole unit as it is written.

    >>> _power_hint((("kg", 1), ("m2", 1)), "m2")
    ' (a power is written with ^: kg*m^2)'
    """
    glued = re.fullmatch(r"([A-Za-z]+?)(\d+)", name)
    if glued is None or glued.group(1) not in _COMMON:
        return ""
    fixed = [(glued.group(1), int(glued.group(2)) * power) if term == name else (term, power)
             for term, power in terms]
    return f" (a power is written with ^: {_text(fixed)})"


def _text(terms) -> str:
    return "*".join(name if power == 1 else f"{name}^{power}" for name, power in terms) or "1"


def _terms(unit) -> tuple:
    if unit is None:
        return ()
    if not isinstance(unit, str):
        raise UnitError(f"a unit is a text such as 'N*m', got {unit!r}")
    if unit.strip() in ("", "1", "dimensionless"):
        return ()
    try:
        return unit_terms(unit)
    except ValueTextError as error:
        raise UnitError(str(error)) from None


def dimension(unit: str) -> Dimension:
    """The dimension of a unit expression (angles are dimensionless).

    >>> print(dimension("kN*mm"))
    N*m (a moment or an energy)
    """
    return _dimension_of(_facts(_terms(unit)))


def _dimension_of(facts) -> Dimension:
    return Dimension({k: Fraction(v) for k, v in facts["dimension"].items()})


def si_factor(unit: str) -> float:
    """The SI value of one ``unit`` (``"kN"``: 1000.0, ``"rpm"``: 2 pi / 60)."""
    return _facts(_terms(unit))["factor"]


def to_si(value, unit=None) -> float:
    """The SI value of a number (already SI), a text with a unit or a pint quantity,
    checked against the ``unit`` expected (a unit expression; None: any).

    Texts convert exactly where they can: the decimal ``0.02`` times the factor 1000 of
    ``kN`` gives 20.0, the same float as typing ``20``.

    Raises
    ------
    UnitError
        An unknown unit, a text that is not a number with a unit, or a dimension that
        does not fit ``unit``.

    Examples
    --------
    >>> import mechdyn as md
    >>> md.to_si("0.02 kN", "N"), md.to_si(3), md.to_si("2 min", "s")
    (20.0, 3.0, 120.0)
    """
    if isinstance(value, bool) or value is None:
        raise UnitError(f"{value!r} is not a value")
    if isinstance(value, str):
        if unit is None or isinstance(unit, str):
            return _cached_text_to_si(value, unit)
        return _text_to_si(value, unit)
    if hasattr(value, "dimensionality") and hasattr(value, "to_base_units"):
        return _quantity_to_si(value, unit)
    return finite(value, UnitError, f"{value!r} is not a number, a text such as '2 kN' or a "
                  "pint quantity", f"{value!r} is not finite")


def finite(value, error, not_a_number, not_finite) -> float:
    """``float(value)``, or ``error`` with the message ``not_a_number`` or ``not_finite``.

    >>> finite("2.5", ValueError, "no number", "infinite")
    2.5
    >>> finite(float("inf"), ValueError, "no number", "infinite")
    Traceback (most recent call last):
    ValueError: infinite
    """
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise error(not_a_number) from None
    if not math.isfinite(number):
        raise error(not_finite)
    return number


@functools.lru_cache(maxsize=4096)
def _cached_text_to_si(text, unit):
    """:func:`_text_to_si` of a text and a unit text, kept: every run of a scene
    converts the same parameter texts."""
    return _text_to_si(text, unit)


def _text_to_si(text, unit):
    try:
        number, terms, literal = quantity(text)
    except ValueTextError as error:
        raise UnitError(str(error)) from None
    if not terms:
        return number
    given = _facts(terms)
    if unit is not None:
        expected = _facts(_terms(unit))
        _check_fits(text, terms, given, unit, expected)
    factor = given["factor"]
    if literal is not None:        # exact: decimal literal times the factor's decimal
        value = float(Fraction(literal) * Fraction(repr(factor)))
    else:
        value = number * factor
    if not math.isfinite(value):
        raise UnitError(f"{text!r} is not finite in SI units")
    return value


def _check_fits(text, terms, given, unit, expected):
    have, want = _dimension_of(given), _dimension_of(expected)
    if have != want:
        what = f"is {_NAMED[have][1]}" if have in _NAMED else f"has dimension {have.si}"
        wanted = f"{unit} ({_NAMED[want][1]})" if want in _NAMED else unit
        raise UnitError(f"{text!r}: {_text(terms)}{_reading(terms, given)} {what} but "
                        f"{wanted} is expected")
    if given["cycles"] and Fraction(expected["angle"]) != 0:
        raise UnitError(f"{text!r}: Hz counts cycles, not radians; for {unit} write "
                        "rpm, rev/s or rad/s")


def _reading(terms, facts) -> str:
    """How pint read unit names that are not plainly what was typed ("kNm": kilo
    number_meter, not kN*m)."""
    reads = facts.get("reads", "")
    if len(terms) == 1 and "_" in reads:
        return f" (read as {reads})"
    return ""


def _quantity_to_si(value, unit):
    base = value.to_base_units()
    magnitude = float(base.magnitude)
    if unit is not None:
        have = Dimension({k: Fraction(v) for k, v in dict(value.dimensionality).items()})
        if have != dimension(unit):
            raise UnitError(f"{value}: {have} does not fit {unit} ({dimension(unit)})")
    if not math.isfinite(magnitude):
        raise UnitError(f"{value} is not finite")
    return magnitude


def convert(values, unit: str, display: str):
    """``values`` in ``unit`` expressed in ``display`` (same dimension), as an array.

    >>> float(convert(1500.0, "W", "kW")[0])
    1.5
    """
    source, target = _facts(_terms(unit)), _facts(_terms(display))
    if _dimension_of(source) != _dimension_of(target):
        raise UnitError(f"cannot show {unit} ({dimension(unit)}) in {display} "
                        f"({dimension(display)})")
    if target["cycles"] != source["cycles"] and \
            Fraction(source["angle"]) != Fraction(target["angle"]):
        raise UnitError(f"cannot show {unit} in {display}: Hz counts cycles, not radians; "
                        "use rpm or rev/s")
    return np.atleast_1d(np.asarray(values, dtype=float)) * (source["factor"]
                                                             / target["factor"])

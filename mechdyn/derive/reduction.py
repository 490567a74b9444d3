"""Reduction of a drive train to one shaft by hand (worked example 7).

Masses, stiffnesses and loads are carried to the motor shaft (the centre of reduction)
keeping kinetic energy, potential energy and power equal. ``i`` is the transmission
ratio from the motor shaft to the element (motor speed / element speed); ``eta`` the
efficiency of the transmission between them. The functions take numbers (and return
floats) or sympy expressions (and return expressions), so they check a derivation
symbolically as well as numerically.

Examples
--------
>>> from mechdyn import reduction as red
>>> round(red.inertia(6.0, 40) + red.drum_mass(2000, 0.2, 40), 6)  # drum, load: kg m^2
0.05375
>>> round(red.drum_force(2000 * 9.81, 0.2, 40, eta=0.9), 3)  # lifting, N m
109.0
"""
from __future__ import annotations

import math
from numbers import Real

import sympy as sp

from mechdyn.errors import MechdynError

__all__ = ["ReductionError", "inertia", "drum_mass", "torsional_stiffness",
           "rope_stiffness", "mesh_stiffness", "series", "efficiency", "moment",
           "drum_force"]


class ReductionError(MechdynError, ValueError):
    """An argument of a reduction formula that makes no physical sense.

    Examples
    --------
    >>> import mechdyn as md
    >>> try:
    ...     md.reduction.inertia(4.0, 0)
    ... except md.ReductionError as error:
    ...     print(error)
    i = 0.0 must be nonzero (a gear ratio of zero transmits no motion)
    """


def _check(value, name, kind):
    """Return ``value`` (a float or a sympy expression) after checking it is ``kind``:
    ``"positive"``, ``"nonnegative"``, ``"nonzero"`` or ``"efficiency"`` (in (0, 1])."""
    if isinstance(value, sp.Basic):
        if not isinstance(value, sp.Expr):
            raise ReductionError(f"{name} = {value!r} is not a scalar expression")
        bad = {"positive": value.is_positive is False,
               "nonnegative": value.is_nonnegative is False,
               "nonzero": value.is_zero is True,
               "efficiency": value.is_positive is False or (value - 1).is_positive is True}
        if bad[kind]:
            raise ReductionError(f"{name} = {value} must be {_WORDS[kind]}")
        return value
    if isinstance(value, bool) or not isinstance(value, Real):
        raise ReductionError(f"{name} = {value!r} is not a number or sympy expression")
    value = float(value)
    ok = {"positive": value > 0, "nonnegative": value >= 0, "nonzero": value != 0,
          "efficiency": 0 < value <= 1}
    if not math.isfinite(value) or not ok[kind]:
        raise ReductionError(f"{name} = {value} must be {_WORDS[kind]}")
    return value


_WORDS = {"positive": "positive", "nonnegative": "zero or positive",
          "nonzero": "nonzero (a gear ratio of zero transmits no motion)",
          "efficiency": "an efficiency in (0, 1]"}


def inertia(J, i):
    """Moment of inertia ``J`` of a shaft turning ``i`` times slower than the motor,
    reduced to the motor shaft: ``J / i^2``.

    >>> inertia(4.0, 2)
    1.0
    """
    return _check(J, "J", "nonnegative") / _check(i, "i", "nonzero") ** 2


def drum_mass(m, r_b, i):
    """A mass ``m`` hanging from a drum of radius ``r_b`` (drum turning ``i`` times
    slower than the motor), reduced to the motor shaft: ``m r_b^2 / i^2``.

    >>> drum_mass(100, 0.5, 5)
    1.0
    """
    return (_check(m, "m", "nonnegative") * _check(r_b, "r_b", "positive") ** 2
            / _check(i, "i", "nonzero") ** 2)


def torsional_stiffness(c, i):
    """Torsional stiffness ``c`` of a shaft turning ``i`` times slower than the motor,
    reduced to the motor shaft: ``c / i^2``.

    >>> torsional_stiffness(900.0, 3)
    100.0
    """
    return _check(c, "c", "positive") / _check(i, "i", "nonzero") ** 2


def rope_stiffness(E_k, length, r_b, i):
    """A rope of axial rigidity ``E_k = E A`` and free length ``length`` on a drum of
    radius ``r_b``, reduced to the motor shaft: ``(E_k / length) r_b^2 / i^2``.

    >>> round(rope_stiffness(8e6, 20.0, 0.2, 40), 9)
    10.0
    """
    linear = _check(E_k, "E_k", "positive") / _check(length, "length", "positive")
    return linear * _check(r_b, "r_b", "positive") ** 2 / _check(i, "i", "nonzero") ** 2


def mesh_stiffness(C_l, r, i=1):
    """A gear mesh of linear stiffness ``C_l`` (N/m along the line of action) seen from
    the shaft of pitch radius ``r`` (torsional ``C_l r^2``), reduced to the motor shaft
    when that shaft turns ``i`` times slower: ``C_l r^2 / i^2``.

    >>> round(mesh_stiffness(1e8, 0.05))
    250000
    """
    return (_check(C_l, "C_l", "positive") * _check(r, "r", "positive") ** 2
            / _check(i, "i", "nonzero") ** 2)


def series(*stiffnesses):
    """Stiffness of elements in series (all reduced to one shaft): ``1/c = sum 1/c_k``.

    >>> series(100.0, 100.0, 50.0)
    25.0
    """
    if not stiffnesses:
        raise ReductionError("series() needs at least one stiffness")
    compliance = sum(1 / _check(c, f"stiffness {k + 1}", "positive")
                     for k, c in enumerate(stiffnesses))
    return 1 / compliance


def efficiency(gear_stages=0, bearings=0, eta_gear=0.95, eta_bearing=0.98):
    """Transmission efficiency ``eta_tr = eta_gear^n eta_bearing^m`` of ``n`` gear
    stages and ``m`` pairs of bearings.

    >>> round(efficiency(gear_stages=2, bearings=3), 4)
    0.8494
    """
    for name, count in (("gear_stages", gear_stages), ("bearings", bearings)):
        if isinstance(count, bool) or not isinstance(count, int) or count < 0:
            raise ReductionError(f"{name} = {count!r} must be a whole number >= 0")
    return (_check(eta_gear, "eta_gear", "efficiency") ** gear_stages
            * _check(eta_bearing, "eta_bearing", "efficiency") ** bearings)


def moment(M_c, i, eta=1, overhauling=False):
    """A resisting moment ``M_c`` on a shaft turning ``i`` times slower than the motor,
    reduced to the motor shaft through a transmission of efficiency ``eta``.

    The losses follow the power flow: while the motor drives the load (a hoist lifting)
    the motor must supply ``M_c / (i eta)``; when the load drives the motor
    (``overhauling=True``, a hoist lowering) only ``M_c eta / i`` arrives.

    >>> moment(900.0, 10, eta=0.9), moment(900.0, 10, eta=0.9, overhauling=True)
    (100.0, 81.0)
    """
    M_c = _check(M_c, "M_c", "nonnegative")
    i = _check(i, "i", "nonzero")
    eta = _check(eta, "eta", "efficiency")
    return M_c * eta / i if overhauling else M_c / (i * eta)


def drum_force(P, r_b, i, eta=1, overhauling=False):
    """A force ``P`` on a drum of radius ``r_b`` (the rope pull, e.g. the weight of a
    load), reduced to the motor shaft: ``P r_b / (i eta)`` while the motor drives,
    ``P r_b eta / i`` while the load drives (``overhauling=True``).

    >>> drum_force(1000.0, 0.2, 10, eta=0.8)
    25.0
    """
    P = _check(P, "P", "nonnegative")
    return moment(P * _check(r_b, "r_b", "positive"), i, eta, overhauling)

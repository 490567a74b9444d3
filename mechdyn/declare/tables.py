"""Tables: piecewise-linear characteristics (friction against speed, efficiencies).

``md.table(xs, ys)`` is a function of one argument; called with an expression it gives
the piecewise-linear interpolation, extrapolated through the first two and the last
two points, as MSL's ``CombiTable1D`` (``LinearSegments``, ``LastTwoPoints``). A short
table (up to 16 points) or one whose values are expressions is a ``Piecewise``
(compiled like any other, its breakpoints located as switching events); a longer one
of numbers (a measured motor curve of thousands of points) is one lookup node
(:mod:`mechdyn.declare.lookup`), built in milliseconds, whose generated code finds the
segment by binary search.

>>> import sympy as sp
>>> mu = table([0, 1, 2], [0.5, 0.4, 0.35])
>>> w = sp.Symbol("w")
>>> mu(w)
Piecewise((0.5 - 0.1*w, w < 1), (0.45 - 0.05*w, True))
>>> mu(3), mu(-1)
(0.300000000000000, 0.600000000000000)
"""
from __future__ import annotations

import math
import numbers

import sympy as sp

from mechdyn.declare.elements import as_expression
from mechdyn.declare.lookup import Lookup, Points
from mechdyn.errors import DeclarationError

__all__ = ["Table", "table"]

PIECEWISE_POINTS = 16        # longer tables of numbers are one lookup node


class Table:
    """A piecewise-linear function through the points ``(xs[i], ys[i])`` (``xs``
    strictly increasing), extrapolated linearly beyond the ends.

    Examples
    --------
    >>> import mechdyn as md
    >>> mu = md.Table([0, 1, 2], [0.4, 0.3, 0.25], name="mu")
    >>> mu(0.5), mu(3)                     # between points; beyond the last: extrapolated
    (0.350000000000000, 0.200000000000000)
    """

    def __init__(self, xs, ys, name="table"):
        xs, ys = list(xs), list(ys)
        if len(xs) != len(ys) or len(xs) < 2:
            raise DeclarationError(f"{name}: give two lists of equal length, at least two "
                                   f"points (got {len(xs)} x and {len(ys)} y values)")
        self.name, self.points = name, None
        if len(xs) > PIECEWISE_POINTS and all(map(_plain_number, xs + ys)):
            self.xs, self.ys = [_finite(x, name, "x", i) for i, x in enumerate(xs)], \
                [_finite(y, name, "y", i) for i, y in enumerate(ys)]
            self.points = Points(self.xs, self.ys, name)      # a lookup: no sympy numbers
        else:
            self.xs = [_number(x, f"{name}: x[{i}]") for i, x in enumerate(xs)]
            self.ys = [as_expression(y, f"{name}: y[{i}]") for i, y in enumerate(ys)]
        floats = [float(x) for x in self.xs]
        for i, (a, b) in enumerate(zip(floats, floats[1:])):
            if not b > a:
                raise DeclarationError(f"{name}: x values must increase strictly, but "
                                       f"x[{i}] = {self.xs[i]} and x[{i + 1}] = "
                                       f"{self.xs[i + 1]}")

    def __call__(self, x):
        """The interpolation at ``x`` (a number or an expression)."""
        x = as_expression(x, f"{self.name}: argument")
        if self.points is not None:
            return Lookup(x, self.points)
        lines = [self._line(i, x) for i in range(len(self.xs) - 1)]
        if len(lines) == 1:
            return lines[0]
        pieces = [(line, x < right) for line, right in zip(lines[:-1], self.xs[1:-1])]
        return sp.Piecewise(*pieces, (lines[-1], True))

    def _line(self, i, x):
        x0, x1, y0, y1 = self.xs[i], self.xs[i + 1], self.ys[i], self.ys[i + 1]
        slope = (y1 - y0) / (x1 - x0)
        return sp.expand(y0 - slope * x0 + slope * x)

    def __repr__(self):
        return f"Table({self.xs}, {self.ys})"


def table(xs, ys, name="table") -> Table:
    """A piecewise-linear :class:`Table` through ``(xs[i], ys[i])``, extrapolated
    through the first two and the last two points; call it with an expression.

    Examples
    --------
    A motor's moment against its speed, as a load's value:

    >>> import mechdyn as md
    >>> phi = md.coordinate("phi")
    >>> curve = md.table([0, 100, 150], [80, 60, 0])
    >>> curve(md.speed(phi)).subs(md.speed(phi), 125)
    30
    """
    return Table(xs, ys, name)


def _plain_number(value) -> bool:
    """An int or float (numpy's too), not a bool: read without sympy."""
    return isinstance(value, numbers.Real) and not isinstance(value, (bool, sp.Basic))


def _finite(value, name, axis, i) -> float:
    number = float(value)
    if not math.isfinite(number):
        raise DeclarationError(f"{name}: {axis}[{i}]: {value!r} is not a finite real number")
    return number


def _number(value, what):
    expr = as_expression(value, what)
    if not expr.is_number or not expr.is_real or not math.isfinite(float(expr)):
        raise DeclarationError(f"{what}: {value!r} is not a finite real number")
    return expr

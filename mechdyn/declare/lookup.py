"""Long tables as one lookup: a measured curve of thousands of points is one expression
node, built in milliseconds, whose generated code finds the segment by a balanced
binary search (about log2(n) comparisons) and interpolates linearly, extrapolating
through the first two and the last two points. Its derivative is the segment's slope.

The points are one atom (:class:`Points`): derivation, substitution and common
subexpressions never look inside, and its ``srepr`` (the compile cache's key) holds every
number. The same code runs as Python and compiles with numba; ``lambdify`` to numpy
uses ``numpy.interp``.

>>> import sympy as sp
>>> w = sp.Symbol("w")
>>> curve = Lookup(w, Points([0, 1, 2, 3], [0.5, 0.4, 0.35, 0.3], "mu"))
>>> curve, curve.subs(w, 1.5), curve.subs(w, -1)
(mu(w), 0.375000000000000, 0.600000000000000)
>>> curve.diff(w).subs(w, 0.5)
-0.100000000000000
"""
from __future__ import annotations

import bisect

import sympy as sp

__all__ = ["Points", "Lookup", "LookupSlope"]


class Points(sp.Atom):
    """The abscissas ``xs`` (increasing) and ordinates ``ys`` of a table, as floats."""

    def __new__(cls, xs, ys, name="table"):
        obj = super().__new__(cls)
        obj.xs, obj.ys, obj.name = tuple(map(float, xs)), tuple(map(float, ys)), str(name)
        return obj

    def _hashable_content(self):
        return (self.xs, self.ys, self.name)

    def __getnewargs__(self):
        return (self.xs, self.ys, self.name)

    def __getstate__(self):
        return {}

    def _sympystr(self, printer):
        return f"<{len(self.xs)} points of {self.name}>"

    def _sympyrepr(self, printer):
        return f"Points({self.xs!r}, {self.ys!r}, {self.name!r})"

    def segment(self, x: float) -> int:
        """The index of the segment used at ``x`` (the first or last beyond the ends)."""
        return min(max(bisect.bisect_right(self.xs, x) - 1, 0), len(self.xs) - 2)

    def slope(self, i: int) -> float:
        return (self.ys[i + 1] - self.ys[i]) / (self.xs[i + 1] - self.xs[i])

    def value(self, x: float) -> float:
        i = self.segment(x)
        return self.ys[i] + self.slope(i) * (x - self.xs[i])


class _TableFunction(sp.Function):
    nargs = 2

    @classmethod
    def eval(cls, x, points):
        if x.is_Number and x.is_finite:
            return sp.Float(cls._number(points, float(x)))
        return None

    def _eval_is_extended_real(self):
        return self.args[0].is_extended_real

    def _eval_derivative(self, s):          # the points do not depend on anything
        return self.fdiff(1) * self.args[0].diff(s)

    def _sympystr(self, printer):
        return f"{self._label()}({printer._print(self.args[0])})"

    def _latex(self, printer):
        return rf"\operatorname{{{self._label()}}}\left({printer._print(self.args[0])}\right)"

    def _pythoncode(self, printer):
        """mechdyn's generated code: a call of a shared search (the printer's
        ``table_call``); numpy: :meth:`_numpycode`; other Python: :meth:`_lambdacode`."""
        if hasattr(printer, "table_call"):
            return printer.table_call(self)
        if getattr(printer, "_module", "") == "numpy":
            return self._numpycode(printer)
        return self._lambdacode(printer)

    def _lambdacode(self, printer):
        """Plain Python (``lambdify`` to math): a balanced binary search over the
        segments, one conditional expression."""
        points, x = self.args[1], f"({printer._print(self.args[0])})"

        def node(lo, hi):
            if lo == hi:
                return self._segment_code(points, lo, x)
            mid = (lo + hi + 1) // 2
            return f"({node(mid, hi)} if {x} >= {points.xs[mid]!r} else {node(lo, mid - 1)})"
        return node(0, len(points.xs) - 2)


class Lookup(_TableFunction):
    """The linear interpolation of :class:`Points` at ``x``."""

    @staticmethod
    def _number(points, x):
        return points.value(x)

    def _label(self):
        return self.args[1].name

    def fdiff(self, argindex=1):
        return LookupSlope(*self.args)

    @staticmethod
    def _segment_code(points, i, x):
        return f"({points.ys[i]!r} + {points.slope(i)!r}*({x} - {points.xs[i]!r}))"

    def _numpycode(self, printer):
        points, x = self.args[1], printer._print(self.args[0])
        first, last = (self._segment_code(points, i, f"({x})")
                       for i in (0, len(points.xs) - 2))
        select, interp = (printer._module_format(f"numpy.{f}") for f in ("select", "interp"))
        return (f"{select}([({x}) < {points.xs[1]!r}, ({x}) >= {points.xs[-2]!r}], "
                f"[{first}, {last}], {interp}({x}, {list(points.xs)!r}, "
                f"{list(points.ys)!r}))")


class LookupSlope(_TableFunction):
    """The slope of the segment of :class:`Points` used at ``x`` (the derivative of
    :class:`Lookup`; zero derivative itself)."""

    @staticmethod
    def _number(points, x):
        return points.slope(points.segment(x))

    def _label(self):
        return f"d{self.args[1].name}"

    def fdiff(self, argindex=1):
        return sp.S.Zero

    @staticmethod
    def _segment_code(points, i, x):
        return repr(points.slope(i))

    def _numpycode(self, printer):
        points, x = self.args[1], printer._print(self.args[0])
        slopes = [points.slope(i) for i in range(len(points.xs) - 1)]
        array, searchsorted = (printer._module_format(f"numpy.{f}")
                               for f in ("array", "searchsorted"))
        return (f"{array}({slopes!r})[{searchsorted}({list(points.xs[1:-1])!r}, {x}, "
                "side='right')]")

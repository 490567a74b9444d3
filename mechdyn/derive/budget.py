"""Cheap, deterministic simplification for printing, bounded in time.

Simplification is ``factor_terms`` and ``together`` (no search whose result depends on
hash order); a :class:`Budget` stops it after some seconds, and what it leaves is printed
as derived.

>>> x, y = sp.symbols("x y")
>>> Budget().tidy(sp.Matrix([2*x*y + 2*x, x + y]))
Matrix([
[2*x*(y + 1)],
[      x + y]])
"""
from __future__ import annotations

import time

import sympy as sp

__all__ = ["Budget", "cheap_tidy"]

_TIDY_LIMIT = 400        # operations; larger expressions are printed as derived


def cheap_tidy(expr):
    """The shortest of ``expr``, ``factor_terms(expr)`` and ``factor_terms(together)``
    (by operations, then text): fast and the same whatever the hash order.

    >>> x, y = sp.symbols("x y")
    >>> cheap_tidy(2*x*y + 2*x)
    2*x*(y + 1)
    """
    if not isinstance(expr, sp.Expr) or sp.count_ops(expr) > _TIDY_LIMIT \
            or expr.has(sp.Piecewise):
        return expr
    candidates = [expr, sp.factor_terms(expr)]
    candidates.append(sp.factor_terms(sp.together(candidates[1])))
    return min(candidates, key=lambda e: (sp.count_ops(e), len(sp.sstr(e)), sp.sstr(e)))


class Budget:
    """Time for simplification: ``seconds`` in all from when it is made; then
    expressions are left as derived and ``spent`` is set."""

    def __init__(self, seconds=10.0):
        self.seconds = seconds
        self.start = time.perf_counter()
        self.spent = False

    def tidy(self, expr):
        """``expr`` tidied (:func:`cheap_tidy`) while time is left, else as it is."""
        if isinstance(expr, sp.MatrixBase):
            return expr.applyfunc(self.tidy)
        if self.spent or time.perf_counter() - self.start > self.seconds:
            self.spent = True
            return expr
        return cheap_tidy(expr)

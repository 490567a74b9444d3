"""Generated code for long tables (:mod:`mechdyn.declare.lookup`): each table's points
are module-level constants of the generated source, named by a hash of the numbers,
and one shared binary search finds the segment. The same text runs as Python (the
points a tuple) and compiles with numba (the points a numpy array, a constant of the
compiled code).

>>> namespace = {}
>>> exec(HELPERS, namespace)
>>> xs, ys = (0.0, 1.0, 2.0, 4.0), (0.0, 10.0, 30.0, 30.0)
>>> [namespace["table_value"](x, xs, ys) for x in (-1.0, 0.5, 1.0, 3.0, 5.0)]
[-10.0, 5.0, 10.0, 30.0, 30.0]
>>> namespace["table_slope"](1.5, xs, ys)
20.0
"""
from __future__ import annotations

import hashlib

from mechdyn.compile.generated import TABLE_HELPERS as HELPERS
from mechdyn.declare.lookup import Lookup, Points

__all__ = ["HELPERS", "table_constants", "call_text"]


def _name(points: Points) -> str:
    digest = hashlib.sha256(repr((points.xs, points.ys)).encode()).hexdigest()[:16]
    return f"_table_{digest}"


def call_text(expr, argument: str) -> str:
    """The code of a :class:`Lookup` (or its slope) at ``argument``."""
    function = "table_value" if isinstance(expr, Lookup) else "table_slope"
    name = _name(expr.args[1])
    return f"{function}({argument}, {name}_x, {name}_y)"


def table_constants(expressions) -> str:
    """Module-level lines defining the points of every table in ``expressions``."""
    found = set()
    for expr in expressions:
        if hasattr(expr, "atoms"):               # expressions and matrices
            found |= expr.atoms(Points)
    lines = []
    for points in sorted(found, key=_name):
        name = _name(points)
        lines += [f"{name}_x = table_points({points.xs!r})",
                  f"{name}_y = table_points({points.ys!r})"]
    return "\n".join(lines) + "\n" if lines else ""


"""Parameters given as expressions of others (``Q = 2*k``) in an FMU: calculated
parameters (``causality="calculatedParameter"``) the C code computes from the tunable
ones, so setting ``k`` in the FMU changes ``Q`` as it does in mechdyn.

>>> import sympy as sp
>>> k, Q, R = sp.symbols("k Q R")
>>> names, dependent = calculated_parameters({"Q": 2 * k, "R": Q + 1}, ["Q", "R"])
>>> names, dependent
(['Q', 'R', 'k'], {'Q': 2*k, 'R': 2*k + 1})
>>> for line in calculated_code(names, dependent)[0].splitlines()[2:6]:
...     print(line)
    const double p2 = p[2];
    const double c_0 = 2*p2;
    out[0] = c_0;
    out[1] = c_0 + 1;
"""
from __future__ import annotations

import sympy as sp

from mechdyn.report.fmu.c_code import c_function

__all__ = ["calculated_parameters", "calculated_code"]


def calculated_parameters(given: dict, names: list) -> tuple:
    """``(names, dependent)``: the FMU's parameters (``names``, then the tunable ones the
    calculated ones need that the equations do not) and, of ``names``, those ``given``
    as expressions, written in the tunable ones (chains resolved)."""
    resolved = {}
    for name, expr in given.items():
        for _ in range(len(given) + 1):
            inner = {s: given[s.name] for s in expr.free_symbols if s.name in given}
            if not inner:
                break
            expr = expr.xreplace(inner)
        resolved[name] = expr
    dependent = {n: resolved[n] for n in names if n in resolved}
    needed = sorted({s.name for e in dependent.values() for s in e.free_symbols}
                    - set(names))
    return list(names) + needed, dependent


def calculated_code(names: list, dependent: dict) -> tuple:
    """``(C source of md_calculated, the p index of each calculated parameter)``."""
    index = {n: j for j, n in enumerate(names)}
    rename = {s: sp.Symbol(f"p{index[s.name]}") for e in dependent.values()
              for s in e.free_symbols}
    source = c_function("md_calculated", {}, {f"p{j}": f"p[{j}]" for j in range(len(names))},
                        [e.xreplace(rename) for e in dependent.values()],
                        what=[f"calculated parameter {n}" for n in dependent])
    return source, [index[n] for n in dependent]

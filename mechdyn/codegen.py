"""Scalar Python code from sympy expressions: common subexpressions shared, math-module
calls, parameters unpacked from a vector passed at run time.

The generated text is mechdyn's own (never user text); it is compiled with ``exec``.

>>> import sympy as sp
>>> x, k = sp.symbols("x k")
>>> src = function_source("f", ["x"], ["k"], [k * sp.sin(x) ** 2, sp.sin(x)], "return [{0}, {1}]")
>>> namespace = compile_source(src)
>>> namespace["f"](0.0, 0.5, [2.0])
[0.4596976941318603, 0.479425538604203]
"""
from __future__ import annotations

import math

import numpy

import sympy as sp
from sympy.printing.pycode import PythonCodePrinter

__all__ = ["function_source", "compile_source", "safe_symbols"]

_PRINTER = PythonCodePrinter({"fully_qualified_modules": False, "standard": "python3"})


def safe_symbols(prefix: str, count: int) -> list:
    """``count`` plain symbols named ``prefix0, prefix1, ...`` for generated code."""
    return [sp.Symbol(f"{prefix}{i}") for i in range(count)]


def function_source(name, arguments, parameters, expressions, body_return, doc="",
                    checks=()) -> str:
    """Source of ``def name(t, <state>, p)`` computing ``expressions`` with shared cse.

    ``arguments`` are the names unpacked from the state vector ``y`` (or, when the list
    is ``["x"]``-like and single, taken as a scalar), ``parameters`` the names unpacked
    from ``p``. ``body_return`` is a format string over the expressions' printed forms,
    e.g. ``"return [{0}, {1}]"``; the expressions are bound to the locals ``_e0, _e1, ...``
    first, so templates need no parentheses. ``checks`` are extra source lines placed
    after them.
    """
    temporaries, reduced = sp.cse(list(expressions), symbols=sp.numbered_symbols("_c"),
                                  order="none")
    lines = [f"def {name}(t, y, p):"]
    if doc:
        lines.append(f'    """{doc}"""')
    if len(arguments) == 1:
        lines.append(f"    {arguments[0]} = y")
    elif arguments:     # Python floats: 2-3x faster than numpy scalars, and 1/0 raises
        lines.append(f"    {', '.join(arguments)}, = y.tolist() if type(y) is ndarray else y")
    if parameters:
        lines.append(f"    {', '.join(parameters)}, = p")
    for symbol, value in temporaries:
        lines.append(f"    {symbol} = {_PRINTER.doprint(value)}")
    for i, expr in enumerate(reduced):
        lines.append(f"    _e{i} = {_PRINTER.doprint(expr)}")
    lines.extend("    " + c for c in checks)
    lines.append("    " + body_return.format(*[f"_e{i}" for i in range(len(reduced))]))
    return "\n".join(lines) + "\n"


def compile_source(source: str, extra=None) -> dict:
    """Execute generated source in a namespace holding the math module's names."""
    namespace = {name: getattr(math, name) for name in dir(math) if not name.startswith("_")}
    namespace["ndarray"] = numpy.ndarray
    namespace.update(extra or {})
    exec(compile(source, "<mechdyn generated>", "exec"), namespace)
    return namespace

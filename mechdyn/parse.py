"""A restricted parser for values typed by users (command line, sweep grids).

Accepts numbers and arithmetic on them: ``+ - * / **``, parentheses, ``pi``, ``e`` and
``sqrt``, ``sin``, ``cos``, ``tan``, ``exp``, ``log``. Nothing else is evaluated — no
names, attributes, calls of other functions or indexing — and results must be finite.

>>> number("2*pi/3")
2.0943951023931953
>>> number("__import__('os').system('true')")  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
mechdyn.parse.ValueTextError: ...only numbers, ... are allowed (found a call of '__import__')
"""
from __future__ import annotations

import ast
import math
import operator

from .errors import MechdynError

__all__ = ["number", "assignment", "ValueTextError"]

_BINARY = {ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul,
           ast.Div: operator.truediv, ast.Pow: operator.pow}
_UNARY = {ast.UAdd: operator.pos, ast.USub: operator.neg}
_CONSTANTS = {"pi": math.pi, "e": math.e}
_FUNCTIONS = {name: getattr(math, name) for name in ("sqrt", "sin", "cos", "tan", "exp", "log")}
_ALLOWED = "only numbers, + - * / ** and pi, e, sqrt, sin, cos, tan, exp, log are allowed"


class ValueTextError(MechdynError, ValueError):
    """Text that is not an allowed numeric expression."""


def number(text: str) -> float:
    """The finite value of a restricted arithmetic expression."""
    if not isinstance(text, str) or not text.strip():
        raise ValueTextError(f"{text!r}: expected a number")
    if len(text) > 200:
        raise ValueTextError(f"{text[:20]!r}...: value text longer than 200 characters")
    try:
        tree = ast.parse(text.strip(), mode="eval")
    except SyntaxError:
        raise ValueTextError(f"{text!r}: not a number or arithmetic expression") from None
    try:
        value = _evaluate(tree.body, text)
    except (OverflowError, ZeroDivisionError, ValueError) as error:
        if isinstance(error, ValueTextError):
            raise
        raise ValueTextError(f"{text!r}: {error}") from None
    if isinstance(value, complex) or not math.isfinite(value):
        raise ValueTextError(f"{text!r}: the value is not a finite real number")
    return float(value)


def assignment(text: str) -> tuple:
    """``"name=value"`` -> ``(name, value text)``; the value is read where it is used
    (:func:`mechdyn.parameters.to_number`), so its errors name the parameter.

    >>> assignment("P = 2*pi")
    ('P', '2*pi')
    """
    name, sep, value = text.partition("=")
    name = name.strip()
    if not sep or not name.isidentifier():
        raise ValueTextError(f"{text!r}: expected name=value, e.g. I=0.4")
    return name, value.strip()


def _evaluate(node, text):
    if isinstance(node, ast.Constant) and type(node.value) in (int, float):
        if isinstance(node.value, int) and abs(node.value) > 10 ** 300:
            raise ValueTextError(f"{text!r}: number too large")
        return float(node.value)
    if isinstance(node, ast.BinOp) and type(node.op) in _BINARY:
        left, right = _evaluate(node.left, text), _evaluate(node.right, text)
        if isinstance(node.op, ast.Pow) and abs(right) > 1000:
            raise ValueTextError(f"{text!r}: exponent too large")
        return _BINARY[type(node.op)](left, right)
    if isinstance(node, ast.UnaryOp) and type(node.op) in _UNARY:
        return _UNARY[type(node.op)](_evaluate(node.operand, text))
    if isinstance(node, ast.Name) and node.id in _CONSTANTS:
        return _CONSTANTS[node.id]
    if (isinstance(node, ast.Call) and isinstance(node.func, ast.Name)
            and node.func.id in _FUNCTIONS and len(node.args) == 1 and not node.keywords):
        return _FUNCTIONS[node.func.id](_evaluate(node.args[0], text))
    raise ValueTextError(f"{text!r}: {_ALLOWED} (found {_describe(node)})")


def _describe(node):
    if isinstance(node, ast.Call):
        inner = node.func
        while isinstance(inner, (ast.Attribute, ast.Call)):
            inner = inner.value if isinstance(inner, ast.Attribute) else inner.func
        name = inner.id if isinstance(inner, ast.Name) else type(inner).__name__
        return f"a call of {name!r}"
    if isinstance(node, ast.Name):
        return f"the name {node.id!r}"
    if isinstance(node, ast.Constant):
        return f"the constant {node.value!r}"
    return f"a {type(node).__name__}"

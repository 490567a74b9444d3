"""A restricted parser for values typed by users (command line, sweep grids).

Accepts numbers and arithmetic on them: ``+ - * / **``, parentheses, ``pi``, ``e`` and
``sqrt``, ``sin``, ``cos``, ``tan``, ``exp``, ``log``. Nothing else is evaluated — no
names, attributes, calls of other functions or indexing — and results must be finite.
A value may end in a unit (:func:`quantity`): a product of unit names with powers,
``"0.02 kN"``, ``"9.81 m/s^2"``, ``"0.5 kg m^2"``; :mod:`mechdyn.units` looks the names
up one by one (the text is never handed to a general parser).

>>> number("2*pi/3")
2.0943951023931953
>>> quantity("9.81 m/s^2")
(9.81, (('m', Fraction(1, 1)), ('s', Fraction(-2, 1))), '9.81')
>>> number("__import__('os').system('true')")  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
mechdyn.parse.ValueTextError: ...only numbers, ... are allowed (found a call of '__import__')
"""
from __future__ import annotations

import ast
import math
import operator
import re
from fractions import Fraction

from mechdyn.errors import MechdynError

__all__ = ["number", "assignment", "named_value", "quantity", "unit_terms",
           "ValueTextError"]

_BINARY = {ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul,
           ast.Div: operator.truediv, ast.Pow: operator.pow}
_UNARY = {ast.UAdd: operator.pos, ast.USub: operator.neg}
_CONSTANTS = {"pi": math.pi, "e": math.e}
_FUNCTIONS = {name: getattr(math, name) for name in ("sqrt", "sin", "cos", "tan", "exp", "log")}
_ALLOWED = "only numbers, + - * / ** and pi, e, sqrt, sin, cos, tan, exp, log are allowed"


class ValueTextError(MechdynError, ValueError):
    """Text that is not an allowed numeric expression.

    Examples
    --------
    The restricted parser evaluates arithmetic, nothing else:

    >>> import mechdyn as md
    >>> from mechdyn.parse import number
    >>> number("2*pi")
    6.283185307179586
    >>> try:
    ...     number("__import__('os')")
    ... except md.ValueTextError as error:
    ...     print(type(error).__name__)
    ValueTextError
    """


def number(text: str) -> float:
    """The finite value of a restricted arithmetic expression."""
    if not isinstance(text, str) or not text.strip():
        raise ValueTextError(f"{text!r}: expected a number")
    if len(text) > 200:
        raise ValueTextError(f"{text[:20]!r}...: value text longer than 200 characters")
    try:
        tree = ast.parse(text.strip(), mode="eval")
    except (SyntaxError, ValueError):       # ValueError: a null byte, on Python 3.10
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
    (:func:`mechdyn.declare.parameters.to_number`), so its errors name the parameter.

    >>> assignment("P = 2*pi")
    ('P', '2*pi')
    """
    name, sep, value = text.partition("=")
    name = name.strip()
    if not sep or not name.isidentifier():
        raise ValueTextError(f"{text!r}: expected name=value, e.g. I=0.4")
    return name, value.strip()


def named_value(text: str) -> tuple:
    """``"name=value text"`` -> ``(name, value text)``, the value read later (it may carry
    a unit: :func:`mechdyn.units.to_si`)."""
    name, sep, value = text.partition("=")
    name = name.strip()
    if not sep or not name.isidentifier() or not value.strip():
        raise ValueTextError(f"{text!r}: expected name=value, e.g. I=0.4 or P=2 kN")
    return name, value.strip()


_TOKEN = re.compile(r"\s*(?:(?P<number>(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)"
                    r"|(?P<name>[A-Za-z_][A-Za-z_0-9]*)|(?P<op>\*\*|[-+*/^()]))")
_DECIMAL = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?")
_UNIT_NAME = re.compile(r"[A-Za-z][A-Za-z_0-9]{0,39}")


def _tokens(text):
    tokens, position = [], 0
    while position < len(text.rstrip()):
        match = _TOKEN.match(text, position)
        if not match or match.end() == position:
            raise ValueTextError(f"{text!r}: unexpected {text[position:].strip()[:10]!r}")
        kind = match.lastgroup
        tokens.append((kind, match.group(kind), match.start(kind)))
        position = match.end()
    return tokens


def quantity(text: str) -> tuple:
    """A number with an optional unit: ``(value, unit terms, literal)``.

    The unit starts at the first name that is not ``pi``, ``e`` or a function; its terms
    are ``(unit name, exponent)`` pairs (no unit: ``()``). ``literal`` is the number's
    text when it is a plain decimal (for exact conversion), else None.

    >>> quantity("2*pi rad/s")[:2]
    (6.283185307179586, (('rad', Fraction(1, 1)), ('s', Fraction(-1, 1))))
    >>> quantity("1500")
    (1500.0, (), '1500')
    """
    if not isinstance(text, str) or not text.strip():
        raise ValueTextError(f"{text!r}: expected a number, optionally with a unit")
    if len(text) > 200:
        raise ValueTextError(f"{text[:20]!r}...: value text longer than 200 characters")
    tokens = _tokens(text)
    start = None
    for k, (kind, token, _) in enumerate(tokens):
        follows_call = k + 1 < len(tokens) and tokens[k + 1][1] == "("
        if kind == "name" and token not in _CONSTANTS and not (
                token in _FUNCTIONS and follows_call):
            start = k
            break
    if start is None:
        value_text, unit = text.strip(), ()
    else:
        while start and tokens[start - 1][1] == "(" and not (
                start > 1 and tokens[start - 2][0] == "name"):
            start -= 1                                 # "4 (m/s)^2"
        position = tokens[start][2]
        if start and tokens[start - 1][1] == "/":      # "100/s": the unit is 1/s
            position = tokens[start - 1][2]
            unit = unit_terms("1" + text[position:])
        else:
            unit = unit_terms(text[position:])
        value_text = text[:position].strip()
        if not value_text:
            raise ValueTextError(f"{text!r}: expected a number before the unit, "
                                 "e.g. '2 kN'")
    value = number(value_text)
    return value, unit, value_text if _DECIMAL.fullmatch(value_text) else None


def unit_terms(text: str) -> tuple:
    """A unit expression -> ``((name, exponent), ...)``, exponents as fractions.

    Names multiply by ``*`` or a space and divide by ``/``; powers are ``^`` or ``**``
    with a number (``m^2``, ``s^-1``, ``m^(1/2)``); ``1`` stands for no unit
    (``1/s``). Names are not checked here (:mod:`mechdyn.units` does).

    >>> unit_terms("kg m^2 / s")
    (('kg', Fraction(1, 1)), ('m', Fraction(2, 1)), ('s', Fraction(-1, 1)))
    """
    if not isinstance(text, str) or len(text) > 100:
        raise ValueTextError(f"{text!r}: expected a unit expression such as 'N*m'")
    tokens = _tokens(text)
    pieces = []
    for k, (kind, token, _) in enumerate(tokens):
        if token == "^":
            token = "**"
        if k and (kind == "name" or token == "(") and (
                tokens[k - 1][0] in ("name", "number") or tokens[k - 1][1] == ")"):
            pieces.append("*")                         # "N m" is N*m
        pieces.append(token)
    try:
        tree = ast.parse("".join(pieces), mode="eval")
    except (SyntaxError, ValueError):       # ValueError: a null byte, on Python 3.10
        raise ValueTextError(f"{text!r}: not a unit expression (names with * / and "
                             "powers, e.g. 'kg*m^2' or 'N m/rad')") from None
    terms = {}
    _unit(tree.body, Fraction(1), terms, text)
    return tuple((name, power) for name, power in terms.items() if power != 0)


def _unit(node, power, terms, text):
    if isinstance(node, ast.Name):
        if not _UNIT_NAME.fullmatch(node.id) or node.id in _CONSTANTS:
            raise ValueTextError(f"{text!r}: {node.id!r} is not a unit name")
        terms[node.id] = terms.get(node.id, Fraction(0)) + power
    elif isinstance(node, ast.Constant) and node.value == 1 and type(node.value) is int:
        pass
    elif isinstance(node, ast.BinOp) and isinstance(node.op, (ast.Mult, ast.Div)):
        _unit(node.left, power, terms, text)
        _unit(node.right, -power if isinstance(node.op, ast.Div) else power, terms, text)
    elif isinstance(node, ast.BinOp) and isinstance(node.op, ast.Pow):
        exponent = Fraction(number(ast.unparse(node.right))).limit_denominator(12)
        if abs(exponent) > 12:
            raise ValueTextError(f"{text!r}: unit exponent {exponent} out of range")
        _unit(node.left, power * exponent, terms, text)
    else:
        raise ValueTextError(f"{text!r}: a unit holds only unit names, * / and powers "
                             f"(found {_describe(node)})")


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

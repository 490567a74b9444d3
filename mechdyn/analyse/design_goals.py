"""Objectives and constraints of a design study, read from text without ``eval``.

A goal is a measure's name (``fluctuation``, ``t_end``, ``final:phidot``; see
:mod:`mechdyn.analyse.sensitivities`) or an arithmetic expression of parameter names
(``J_f``, ``P + 100*R``: numbers, names, ``+ - * / **`` and parentheses, nothing else).
A constraint is ``GOAL <= LIMIT``, ``>=`` or ``==``; the limit is a number with an
optional unit (``"5 s"``, ``"1425 rpm"``), converted to SI and checked against the
goal's unit where it is known.

>>> import sympy as sp
>>> P, R = sp.symbols("P R", positive=True)
>>> goal = read_goal("P + 100*R", {"P": P, "R": R})
>>> goal.expression, goal.measure
(P + 100*R, None)
>>> c = read_constraint("t_end <= 2 min", {"P": P}, {"t_end": "s"})
>>> c.goal.measure, c.relation, c.limit
('t_end', '<=', 120.0)
>>> read_goal("__import__('os')", {"P": P})     # doctest: +ELLIPSIS
Traceback (most recent call last):
...
mechdyn.analyse.design_goals.GoalError: ...only numbers, parameter names, + - * / ** and parentheses...
"""
from __future__ import annotations

import ast
import re
from dataclasses import dataclass

import sympy as sp

from mechdyn.errors import MechdynError, did_you_mean
from mechdyn.units import UnitError, to_si
from mechdyn.analyse.sensitivities import CYCLE_MEASURES, RUN_MEASURES

__all__ = ["Goal", "Constraint", "read_goal", "read_constraint", "GoalError",
           "OptimizeError"]

_DIFFERENTIABLE = RUN_MEASURES + CYCLE_MEASURES      # what sensitivities() differentiates
_MEASURE = re.compile("(" + "|".join(_DIFFERENTIABLE) + r"|(stop_angle|final):[A-Za-z_]\w*)")
_RELATION = re.compile(r"^(.*?)(<=|>=|==)(.*)$")
_BINARY = {ast.Add: sp.Add, ast.Sub: lambda a, b: a - b, ast.Mult: sp.Mul,
           ast.Div: lambda a, b: a / b, ast.Pow: sp.Pow}
_ALLOWED = "only numbers, parameter names, + - * / ** and parentheses are allowed"


class OptimizeError(MechdynError, ValueError):
    """A sizing problem that cannot be set up (bounds, goals) or was not solved.

    Examples
    --------
    >>> import mechdyn as md
    >>> brake = md.load_model("shoe_brake")
    >>> try:
    ...     md.optimize(brake.mechanism, brake.scenes["braking"], brake.params,
    ...                 vary={"P": (100, 1)}, minimize="t_end")
    ... except md.OptimizeError as error:
    ...     print(type(error).__name__)
    OptimizeError
    """


class GoalError(OptimizeError):
    """An objective or constraint that cannot be read.

    Examples
    --------
    Goals are read, never evaluated:

    >>> import mechdyn as md
    >>> brake = md.load_model("shoe_brake")
    >>> try:
    ...     md.optimize(brake.mechanism, brake.scenes["braking"], brake.params,
    ...                 vary={"P": (1, 100)}, minimize="__import__('os')")
    ... except md.GoalError as error:
    ...     print(type(error).__name__)
    GoalError
    """


@dataclass(frozen=True)
class Goal:
    """``measure`` (a measure's name) or ``expression`` (of parameters); ``text``."""
    text: str
    measure: str | None = None
    expression: sp.Expr | None = None


@dataclass(frozen=True)
class Constraint:
    """``goal relation limit`` (``relation``: "<=", ">=" or "=="; ``limit`` in SI)."""
    text: str
    goal: Goal
    relation: str
    limit: float


def read_goal(text, parameters) -> Goal:
    """A measure's name or an expression of the ``parameters`` ({name: symbol})."""
    if not isinstance(text, str) or not text.strip():
        raise GoalError(f"{text!r}: expected a measure's name or an expression of parameters")
    text = text.strip()
    if len(text) > 200:
        raise GoalError(f"{text[:20]!r}...: goal text longer than 200 characters")
    if _MEASURE.fullmatch(text):
        return Goal(text, measure=text)
    try:
        tree = ast.parse(text, mode="eval")
    except SyntaxError:
        raise GoalError(f"{text!r}: not a measure's name or an expression of parameters "
                        f"(measures: {', '.join(_DIFFERENTIABLE)}, final:STATE)") from None
    return Goal(text, expression=_build(tree.body, text, parameters))


def _build(node, text, parameters):
    if isinstance(node, ast.Constant) and type(node.value) in (int, float):
        return sp.Float(node.value) if isinstance(node.value, float) else sp.Integer(node.value)
    if isinstance(node, ast.Name):
        if node.id not in parameters:
            raise GoalError(f"{text!r}: {node.id!r} is not a parameter or measure"
                            f"{did_you_mean(node.id, list(parameters))}")
        return parameters[node.id]
    if isinstance(node, ast.BinOp) and type(node.op) in _BINARY:
        return _BINARY[type(node.op)](_build(node.left, text, parameters),
                                      _build(node.right, text, parameters))
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
        inner = _build(node.operand, text, parameters)
        return -inner if isinstance(node.op, ast.USub) else inner
    raise GoalError(f"{text!r}: {_ALLOWED} (found {type(node).__name__})")


def read_constraint(text, parameters, units) -> Constraint:
    """``"GOAL <= LIMIT"`` (or ``>=``, ``==``); ``units``: {measure or parameter name:
    SI unit} to check the limit's unit against."""
    match = _RELATION.match(text.strip()) if isinstance(text, str) else None
    if not match or not match.group(1).strip() or not match.group(3).strip():
        raise GoalError(f"{text!r}: expected GOAL <= LIMIT, GOAL >= LIMIT or GOAL == LIMIT, "
                        "e.g. 'fluctuation <= 0.05' or 't_end <= 5 s'")
    goal = read_goal(match.group(1), parameters)
    unit = units.get(goal.measure or goal.text.strip())
    try:
        limit = to_si(match.group(3).strip(), unit or None)
    except UnitError as error:
        raise GoalError(f"{text!r}: the limit: {error}") from None
    return Constraint(text.strip(), goal, match.group(2), float(limit))

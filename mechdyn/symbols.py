"""Time, generalized coordinates and their plain-symbol stand-ins.

A user writes positions as expressions of coordinates, which are functions of the time
``t``. The derivation works on plain symbols instead: a coordinate ``phi`` becomes the
symbol ``phi``, its speed the symbol ``phidot`` (printed as a dotted phi), its
acceleration ``phiddot``.

>>> import mechdyn as md
>>> phi = md.coordinate("phi")
>>> md.speed(phi)
Derivative(phi(t), t)
>>> md.plain(phi), md.plain(md.speed(phi))
(phi, phidot)
"""
from __future__ import annotations

import sympy as sp
from sympy.core.function import AppliedUndef
from sympy.printing.conventions import split_super_sub

from mechdyn.errors import DeclarationError

__all__ = ["t", "coordinate", "coordinates", "speed", "acceleration", "plain",
           "is_coordinate", "dotted_symbol", "difference", "same", "written"]

t = sp.Symbol("t", real=True)


def coordinate(name: str) -> sp.Expr:
    """A generalized coordinate: the function ``name(t)`` of the time ``md.t``.

    Examples
    --------
    >>> coordinate("phi_2")
    phi_2(t)

    >>> coordinate("t")
    Traceback (most recent call last):
    ...
    mechdyn.errors.DeclarationError: coordinate name 't' is the time md.t; name the coordinate otherwise (x, s, phi, ...)
    """
    if not isinstance(name, str) or not name.isidentifier():
        raise DeclarationError(f"coordinate name must be an identifier (letters, digits, "
                               f"underscores; not starting with a digit), got {name!r}")
    if name == "t":
        raise DeclarationError("coordinate name 't' is the time md.t; name the coordinate "
                               "otherwise (x, s, phi, ...)")
    return sp.Function(name)(t)


def coordinates(names: str) -> tuple:
    """Several coordinates from one string of names separated by spaces or commas.

    Examples
    --------
    >>> coordinates("phi_1 phi_2")
    (phi_1(t), phi_2(t))
    """
    return tuple(coordinate(n) for n in names.replace(",", " ").split())


def is_coordinate(expr) -> bool:
    """True for an applied undefined function of ``t`` alone, such as ``phi(t)``."""
    return isinstance(expr, AppliedUndef) and expr.args == (t,)


def _check_coordinate(q):
    if not is_coordinate(q):
        raise TypeError(f"{q!r} is not a coordinate; make one with md.coordinate('name')")


def speed(q) -> sp.Expr:
    """The speed dq/dt of a coordinate (an angular speed for an angle).

    Examples
    --------
    >>> import mechdyn as md
    >>> phi = md.coordinate("phi")
    >>> md.speed(phi)
    Derivative(phi(t), t)
    >>> md.plain(md.speed(phi))
    phidot
    """
    _check_coordinate(q)
    return sp.Derivative(q, t)


def acceleration(q) -> sp.Expr:
    """The acceleration d2q/dt2 of a coordinate.

    Examples
    --------
    >>> import mechdyn as md
    >>> x = md.coordinate("x")
    >>> md.acceleration(x), md.plain(md.acceleration(x))
    (Derivative(x(t), (t, 2)), xddot)
    """
    _check_coordinate(q)
    return sp.Derivative(q, (t, 2))


def dotted_symbol(name: str, dots: int) -> sp.Symbol:
    """The plain (real) symbol for the ``dots``-th time derivative of the coordinate
    ``name``.

    The modifier goes on the base of the name so subscripts print right:
    ``phi_2`` with one dot is ``phidot_2``, printed as a dotted phi with subscript 2.
    The symbols are real, so ``Abs``, ``sign`` and ``sqrt`` of them differentiate as
    real functions.
    """
    if dots == 0:
        return sp.Symbol(name, real=True)
    base, sups, subs = split_super_sub(name)
    text = base + ("dot" if dots == 1 else "ddot")
    if subs:
        text += "_" + "_".join(subs)
    if sups:
        text += "__" + "__".join(sups)
    return sp.Symbol(text, real=True)


def plain(expr) -> sp.Symbol:
    """The plain symbol of a coordinate, its speed or its acceleration.

    Reduced quantities and derived equations are written in these symbols.

    Examples
    --------
    >>> import mechdyn as md
    >>> phi_2 = md.coordinate("phi_2")
    >>> md.plain(phi_2), md.plain(md.speed(phi_2)), md.plain(md.acceleration(phi_2))
    (phi_2, phidot_2, phiddot_2)
    """
    if is_coordinate(expr):
        return dotted_symbol(expr.func.__name__, 0)
    if isinstance(expr, sp.Derivative) and is_coordinate(expr.expr):
        order = sum(n for v, n in expr.variable_count if v == t)
        if order in (1, 2) and len(expr.variable_count) == 1:
            return dotted_symbol(expr.expr.func.__name__, order)
    raise TypeError(f"{expr!r} is not a coordinate, a speed or an acceleration")


def written(expr) -> str:
    """An expression as a user reads it: coordinates and their derivatives as plain
    symbols.

    >>> phi = coordinate("phi")
    >>> written(2 * sp.sin(phi) * speed(phi))
    '2*phidot*sin(phi)'
    """
    expr = sp.sympify(expr)
    expr = expr.xreplace({d: plain(d) for d in expr.atoms(sp.Derivative)})
    return str(expr.xreplace({f: plain(f) for f in expr.atoms(AppliedUndef)}))


# ------------------------------------------------------- comparing with a hand formula
def difference(derived, formula):
    """``derived - formula``, simplified, with ``formula`` read as a user writes it: its
    coordinates, speeds and accelerations (``phi``, ``md.speed(phi)``) stand for their
    plain symbols, and each symbol for the symbol of the same name in ``derived``
    whatever its assumptions (``sp.Symbol("phi")`` is the real ``phi`` derived results
    are written in; ``sp.Symbol("J_1")`` the positive ``J_1`` a mechanism declared).
    Zero when the two agree; otherwise what is left over. Works on matrices alike.

    Examples
    --------
    >>> import sympy as sp
    >>> phi, J = sp.Symbol("phi", real=True), sp.Symbol("J", positive=True)
    >>> derived = J + sp.sin(phi) ** 2
    >>> sp.simplify(derived - (sp.Symbol("J") + 1 - sp.cos(sp.Symbol("phi")) ** 2)) == 0
    False
    >>> difference(derived, sp.Symbol("J") + 1 - sp.cos(sp.Symbol("phi")) ** 2)
    0
    >>> difference(derived, J + sp.sin(coordinate("phi")) ** 2 / 2)
    sin(phi)**2/2
    """
    derived, formula = _plain_all(sp.sympify(derived)), _plain_all(sp.sympify(formula))
    named = {}
    for symbol in sorted(_symbols(derived), key=str):
        named.setdefault(symbol.name, symbol)
    formula = formula.xreplace({symbol: named[symbol.name] for symbol in _symbols(formula)
                                if symbol.name in named})
    left = derived - formula
    if isinstance(left, sp.MatrixBase):
        return left.applyfunc(_simplest)
    return _simplest(left)


def same(derived, formula) -> bool:
    """Whether a derived result equals a hand formula, symbols matched by name
    (:func:`difference` is 0).

    Examples
    --------
    >>> import sympy as sp
    >>> same(sp.sin(sp.Symbol("phi", real=True)) ** 2, 1 - sp.cos(sp.Symbol("phi")) ** 2)
    True
    """
    left = difference(derived, formula)
    return bool(left.is_zero_matrix if isinstance(left, sp.MatrixBase) else left == 0)


def _symbols(expr) -> set:
    return {s for s in expr.free_symbols if isinstance(s, sp.Symbol)}


def _plain_all(expr):
    """``expr`` with every coordinate and its derivatives as plain symbols."""
    derivatives = {d: plain(d) for d in expr.atoms(sp.Derivative)
                   if is_coordinate(d.expr) and d.variables in ((t,), (t, t))}
    expr = expr.xreplace(derivatives)
    return expr.xreplace({q: plain(q) for q in expr.atoms(AppliedUndef) if is_coordinate(q)})


def _simplest(expr):
    """``expr`` simplified; a piecewise one branch by branch (fast, and the branch that
    differs is the one left non-zero), its conditions freed of positive factors first
    (``g m r_b phidot / i < 0`` is ``phidot < 0``: the derived and the hand-written
    branches then line up)."""
    if expr == 0 or sp.expand(expr) == 0:
        return sp.S.Zero
    if expr.has(sp.Piecewise):
        folded = sp.piecewise_fold(expr.replace(
            lambda e: isinstance(e, sp.core.relational.Relational) and e.rhs == 0,
            lambda e: e.func(sp.Mul(*[f for f in sp.Mul.make_args(e.lhs)
                                      if not f.is_positive]), 0)))
        if not isinstance(folded, sp.Piecewise):
            return _simplest(folded) if not folded.has(sp.Piecewise) else sp.simplify(folded)
        pieces = [(_simplest(branch), condition) for branch, condition in folded.args]
        if all(branch == 0 for branch, _ in pieces):
            return sp.S.Zero
        return sp.Piecewise(*pieces)
    return sp.simplify(expr)

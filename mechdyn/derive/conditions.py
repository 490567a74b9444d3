"""Switching conditions as a user writes them, for the printed derivation.

sympy stores a ``Piecewise``'s conditions in a canonical form: the user's
``x_ram > r + l - h`` becomes ``-h + l + r < r cos(phi) + ...`` and "the ram moves
down", ``x_ram' phidot > 0``, becomes ``phidot r sin(phi) + ... < 0``. For printing,
:func:`written` turns each relation back into the named quantities of the derivation
(a link's position ``x_ram``, its rate ``phidot x_ram'``) with the moving quantity on
the left and its sign positive, so it reads in the sense it was written; the conditions
of a conjunction print positions first, then speeds, joined by ``and`` (``\\wedge``).
The numerics never see these: they keep the plain, canonical form.

>>> import sympy as sp
>>> phi, phidot, h = sp.symbols("phi phidot h")
>>> x = sp.cos(phi)                                  # a position named x_ram
>>> ram = sp.Symbol("x_ram"), sp.Symbol("x_ram'") * phidot
>>> quantities = [(x, ram[0]), (sp.diff(x, phi) * phidot, ram[1])]
>>> law = sp.Piecewise((1, sp.And(x > 1 - h, sp.diff(x, phi) * phidot > 0)), (0, True))
>>> law                                                   # canonical: flipped
Piecewise((1, (phidot*sin(phi) < 0) & (cos(phi) > 1 - h)), (0, True))
>>> written(law, quantities, {phi, phidot}, {phidot})
Piecewise((1, x_ram > 1 - h and phidot*x_ram' > 0), (0, True))
"""
from __future__ import annotations

import sympy as sp
from sympy.core.relational import Relational
from sympy.logic.boolalg import And, Boolean, Or

__all__ = ["written", "AllOf", "AnyOf"]

_REVERSED = {sp.StrictGreaterThan: sp.StrictLessThan, sp.StrictLessThan: sp.StrictGreaterThan,
             sp.GreaterThan: sp.LessThan, sp.LessThan: sp.GreaterThan}


class AllOf(Boolean):
    """Conditions that all hold, printed in their order (``a and b``, ``a \\wedge b``)."""
    WORD, LATEX = " and ", " \\wedge "

    def _sympystr(self, printer):
        return self.WORD.join(_part(printer, a, self.WORD) for a in self.args)

    def _latex(self, printer):
        return self.LATEX.join(_part(printer, a, self.LATEX) for a in self.args)


class AnyOf(AllOf):
    """Conditions of which one holds (``a or b``, ``a \\vee b``)."""
    WORD, LATEX = " or ", " \\vee "


def _part(printer, arg, joint):
    text = printer._print(arg)
    if isinstance(arg, AllOf):
        return ("\\left(" + text + "\\right)") if "\\" in joint else f"({text})"
    return text


def written(expr, quantities, moving, speeds):
    """``expr`` with the conditions of its ``Piecewise`` s written for reading (see the
    module): ``quantities`` pairs ``(plain expression, named expression)`` to write
    them in, ``moving`` the symbols of the motion (coordinates, speeds, time),
    ``speeds`` the speeds."""
    if not isinstance(expr, sp.Basic):
        return expr
    pieces = {pw: _rewritten(pw, quantities, moving, speeds)
              for pw in expr.atoms(sp.Piecewise)}
    return expr.xreplace(pieces) if pieces else expr


def _rewritten(pw, quantities, moving, speeds):
    pairs = [(written(e, quantities, moving, speeds),
              _condition(c, quantities, moving, speeds)) for e, c in pw.args]
    return sp.Piecewise(*pairs, evaluate=False)


def _condition(cond, quantities, moving, speeds):
    if isinstance(cond, Relational) and type(cond) in _REVERSED:
        return _relation(cond, quantities, moving)
    if isinstance(cond, (And, Or)):
        parts = [_condition(c, quantities, moving, speeds) for c in cond.args]
        parts.sort(key=lambda c: bool(c.free_symbols & speeds))   # where, then which way
        return (AllOf if isinstance(cond, And) else AnyOf)(*parts)
    return cond


def _relation(rel, quantities, moving):
    """``rel`` as ``named op rest`` when ``lhs - rhs`` is plus or minus a named quantity
    plus a rest free of the motion; else with its moving side on the left, sign first."""
    difference = rel.lhs - rel.rhs                    # rel reads: difference op 0
    if difference.free_symbols & moving:
        expanded = sp.expand(difference)
        for plain, named in quantities:
            for sign in (1, -1):
                rest = sp.expand(expanded - sign * plain)
                if not rest.free_symbols & moving:    # sign * named + rest op 0
                    op = type(rel) if sign == 1 else _REVERSED[type(rel)]
                    return op(named, -sign * rest, evaluate=False)
    lhs, rhs, op = rel.lhs, rel.rhs, type(rel)
    if not lhs.free_symbols & moving and rhs.free_symbols & moving:
        lhs, rhs, op = rhs, lhs, _REVERSED[op]
    if rhs == 0 and lhs.could_extract_minus_sign():
        lhs, op = -lhs, _REVERSED[op]
    return op(lhs, rhs, evaluate=False)

"""The custom-element contract, checked at the door: what an element's methods return
and raise, before any stage uses it.

- :func:`call` runs one of an element's methods; an exception it raises (other than a
  mechdyn error, which names its culprit already) comes back as a
  :class:`~mechdyn.errors.DeclarationError` naming the element and the method, the
  original chained;
- :func:`checked_expressions` refuses ``expressions()`` that does not give a dict of
  attribute names;
- :func:`checked_work` refuses a malformed :class:`Work` (not a Work, ``None``, text or
  complex values, force entries that are not pairs), terms written with a raw
  coordinate ``phi(t)`` instead of the motion's symbols, and terms along a coordinate
  the mechanism does not have;
- :func:`completed` gives a potential-only element its forces, ``-dV/dq`` along each
  coordinate (Lagrange), so the derivation and the simulation agree; a dissipation
  without forces, and a potential beside forces that vanish at rest (its force left
  out), are refused.

>>> import sympy as sp, mechdyn as md
>>> q = sp.Symbol("q")
>>> completed(md.Element("well"), md.Work(potential=3 * q ** 2), (q,), sp.diff).forces
((-6*q, q),)
"""
from __future__ import annotations

from dataclasses import replace

import sympy as sp
from sympy.core.function import AppliedUndef

from mechdyn.declare.element_base import Limit, Sliding, Work, as_expression
from mechdyn.errors import DeclarationError, MechdynError
from mechdyn.symbols import t

__all__ = ["call", "checked_expressions", "checked_work", "completed", "label"]


def label(element) -> str:
    """How messages name an element: ``"preloadedspring 'torsion'"``."""
    return f"{type(element).__name__.lower()} {element.name!r}"


def call(element, method: str, *args):
    """``element.method(*args)``; a non-mechdyn exception is re-raised naming both."""
    try:
        return getattr(element, method)(*args)
    except MechdynError:
        raise
    except Exception as error:
        raise DeclarationError(f"{label(element)}: its {method}() raised "
                               f"{type(error).__name__}: {error}") from error


def checked_expressions(element) -> dict:
    """The element's ``expressions()``, refused unless a dict keyed by attribute names."""
    expressions = call(element, "expressions")
    if not isinstance(expressions, dict) or not all(isinstance(k, str) for k in expressions):
        raise DeclarationError(
            f"{label(element)}: expressions() must return a dict of attribute name -> "
            f"expression, got {type(expressions).__name__} {expressions!r}")
    return expressions


def checked_work(element, motion, coordinates) -> Work:
    """``element.work(motion)`` checked field by field (see the module); ``coordinates``:
    the mechanism's coordinate functions, to name a raw or foreign one."""
    work = call(element, "work", motion)
    who = label(element)
    if not isinstance(work, Work):
        raise DeclarationError(f"{who}: work() must return md.Work(...), got "
                               f"{type(work).__name__} {work!r}")
    potential = as_expression(work.potential, f"{who}: Work.potential")
    dissipation = as_expression(work.dissipation, f"{who}: Work.dissipation")
    if not isinstance(work.forces, (tuple, list)):
        raise DeclarationError(f"{who}: Work.forces must be a tuple of pairs (value, along), "
                               f"got {work.forces!r}")
    forces = []
    for index, pair in enumerate(work.forces):
        if not (isinstance(pair, (tuple, list)) and len(pair) == 2):
            raise DeclarationError(f"{who}: Work.forces[{index}] must be a pair (value, "
                                   f"along), got {pair!r}")
        forces.append(tuple(as_expression(part, f"{who}: Work.forces[{index}] {role}")
                            for part, role in zip(pair, ("value", "along"))))
    if work.sliding is not None and not isinstance(work.sliding, Sliding):
        raise DeclarationError(f"{who}: Work.sliding must be a Sliding (mechdyn.declare.element_base) or None, got "
                               f"{work.sliding!r}")
    if not (isinstance(work.contacts, (tuple, list))
            and all(isinstance(limit, Limit) for limit in work.contacts)):
        raise DeclarationError(f"{who}: Work.contacts must be a tuple of Limit (mechdyn.declare.element_base), got "
                               f"{work.contacts!r}")
    terms = [("potential", potential), ("dissipation", dissipation)] + [
        (f"forces[{i}] {role}", part) for i, pair in enumerate(forces)
        for role, part in zip(("value", "along"), pair)]
    for what, expr in terms:
        _no_raw_functions(who, what, expr, coordinates)
    return replace(work, potential=potential, dissipation=dissipation, forces=tuple(forces),
                   contacts=tuple(work.contacts))


def _no_raw_functions(who, what, expr, coordinates):
    functions = sorted(expr.atoms(AppliedUndef), key=str)
    names = {c.func.__name__ for c in coordinates} if functions else ()
    for function in functions:
        name = function.func.__name__
        if function.args != (t,):
            raise DeclarationError(f"{who}: Work.{what} = {expr} holds the undefined "
                                   f"function {function}, which has no value to compute")
        if name in names:
            raise DeclarationError(
                f"{who}: Work.{what} = {expr} holds the coordinate function {function}; "
                "write the element's terms with motion.position(...) / motion.plain(...), "
                "which give the derivation's symbols")
        raise DeclarationError(
            f"{who}: Work.{what} = {expr} acts along {function}, which is not a coordinate "
            f"of the mechanism (coordinates: {', '.join(sorted(names))})")


def completed(element, work: Work, q, slope, u=()) -> Work:
    """``work`` with forces derived from its potential when it gives none (``-dV/dq_i``
    along each ``q_i``, ``slope(expr, q_i)`` the derivative); a dissipation without
    forces is refused (its force needs the speeds: give ``forces`` yourself). With the
    speeds ``u``, forces that vanish at rest beside a potential that does not vanish in
    slope are refused: the potential's own force is missing from them."""
    who = label(element)
    if work.forces:
        if u and work.potential != 0 and _missing_potential_force(work, q, slope, u):
            raise DeclarationError(
                f"{who}: its work() gives the potential {work.potential} but forces that "
                "vanish at rest, so the potential would exert no force; add its force "
                "-dV/d(along) to forces, or give no forces (they are then derived from "
                "the potential)")
        return work
    if work.potential == 0 and work.dissipation == 0:
        return work
    if work.dissipation != 0:
        raise DeclarationError(
            f"{who}: its work() gives the dissipation {work.dissipation} but no forces; "
            "give its forces as well, e.g. forces=((-c * motion.rate(s), s),) for "
            "R = c s'^2/2")
    forces = tuple((-slope(work.potential, qi), qi) for qi in q)
    return replace(work, forces=tuple((value, qi) for value, qi in forces if value != 0))


def _missing_potential_force(work, q, slope, u) -> bool:
    at_rest = dict.fromkeys(u, sp.S.Zero)
    resting = [sum((value * slope(along, qi) for value, along in work.forces), sp.S.Zero)
               .xreplace(at_rest) for qi in q]
    return all(sp.expand(f) == 0 for f in resting) and \
        any(slope(work.potential, qi) != 0 for qi in q)

"""Paths of a one-DOF machine's motion by quadrature: time, angle and speed as functions
of each other, real parts of logarithms tidied, the speed inverted where sympy can.
"""
from __future__ import annotations

import sympy as sp
from mechdyn.symbols import t
from mechdyn.derive.analytic import AnalyticError

__all__ = []


def _bound_symbols(expr):
    return set().union(*(i.variables for i in expr.atoms(sp.Integral)))


def _integral(integrand, s, lower, upper):
    """``integral_lower^upper integrand ds`` in closed form, or None."""
    result = sp.integrate(integrand, (s, lower, upper))
    return None if _unevaluated(result) else _real(result)


def _unevaluated(result):
    """True when sympy found no antiderivative a student would call closed (an
    ``Integral`` left, or hypergeometric forms)."""
    return result.has(sp.Integral, sp.hyper, sp.meijerg, sp.exp_polar)


def _real(result):
    """The real form of a real integral that sympy wrote with complex logarithms
    (``log(x - 100) + I pi`` for ``x < 100``): ``log|x - 100|``, the constant
    ``I pi`` dropped (the real part, all symbols being real)."""
    real = sp.re(result)
    if not real.has(sp.re, sp.im):
        return sp.factor_terms(real)
    return _real_logs(result)


def _real_logs(expr):
    """``re(expr)`` for real symbols, where sympy's ``re`` stops at Piecewise or logs:
    each branch, ``log(u)`` as ``log(|u|)``, imaginary constants dropped; the
    expression unchanged if some imaginary part is not a constant."""
    if isinstance(expr, sp.Piecewise):
        return sp.Piecewise(*[(_real_logs(e), c) for e, c in expr.args])
    if not expr.has(sp.I):
        return expr
    as_abs = expr.replace(lambda e: isinstance(e, sp.log) and not e.args[0].is_positive,
                          lambda e: sp.log(sp.Abs(e.args[0])))
    terms = []
    for term in sp.Add.make_args(sp.expand(as_abs, deep=False)):
        if term.has(sp.I):
            if term.free_symbols or term.has(sp.Piecewise):
                return expr
            term = sp.re(term)
        terms.append(term)
    return sp.Add(*terms)


# ----------------------------------------------------------- the three integrable paths
def _tidy(expr):
    """A sum of powers of t with factored coefficients."""
    return sp.collect(sp.expand(expr), t, func=sp.factor)


def _time_path(p):
    """I constant, M of t (or constant): integrate twice."""
    s = sp.Dummy("s", real=True)
    acceleration = p.moment / p.inertia
    t0 = p.start["t"]
    omega = _integral(acceleration.subs(t, s), s, t0, t)
    if omega is None:
        raise AnalyticError(f"{p.name!r}: sympy finds no antiderivative of M_red(t) = "
                            f"{p.moment}; use mech.simulate(scene, params)")
    omega = _tidy(p.start["omega"] + omega)
    phi = _integral(omega.subs(t, s), s, t0, t)
    return {"omega(t)": omega, "phi(t)": _tidy(p.start["phi"] + phi)}, (), ()


def _angle_path(p):
    """M of phi (I constant or of phi): the energy integral, t(phi) by quadrature."""
    s = sp.Dummy("s", real=True)
    work = _integral(p.moment.subs(p.q, s), s, p.start["phi"], p.q)
    if work is None:
        raise AnalyticError(f"{p.name!r}: sympy finds no antiderivative of M_red(phi) = "
                            f"{p.moment} (the work); use mech.simulate(scene, params)")
    omega0 = p.start["omega"]
    direction = sp.sign(omega0) if omega0 != 0 else sp.sign(p.moment.subs(p.q, p.start["phi"]))
    if direction == 0:
        raise AnalyticError(f"{p.name!r} starts at rest where M_red = 0: it stays in "
                            "equilibrium, there is no motion to solve")
    energy = p.inertia.subs(p.q, p.start["phi"]) * omega0**2 / 2 + work
    omega = direction * sp.sqrt(sp.simplify(2 * energy / p.inertia))
    t_phi = p.start["t"] + sp.Integral(1 / omega.subs(p.q, s), (s, p.start["phi"], p.q))
    note = ("omega(phi) from the energy integral I(phi) omega^2/2 = I(phi0) omega0^2/2 + "
            "integral of M dphi; t(phi) by numeric quadrature")
    return {"omega(phi)": omega, "t(phi)": t_phi}, ("t(phi)",), (note,)


def _speed_path(p):
    """I constant, M of omega: t(omega) and phi(omega) by one quadrature each."""
    w, upper = sp.Dummy("w", real=True), sp.Dummy("omega", real=True)
    m = p.moment.subs(p.u, w)
    relations, raw, numeric, notes = {}, {}, [], []
    for name, integrand, offset in (("t(omega)", p.inertia / m, p.start["t"]),
                                    ("phi(omega)", p.inertia * w / m, p.start["phi"])):
        raw[name] = offset + sp.integrate(integrand, (w, p.start["omega"], upper))
        if _unevaluated(raw[name]):
            raw[name] = offset + sp.Integral(integrand, (w, p.start["omega"], upper))
            numeric.append(name)
            notes.append(f"{name}: sympy finds no antiderivative; numeric quadrature")
        relations[name] = _real(raw[name]).xreplace({upper: p.u})
    if not numeric:
        relations.update(_invert_speed(p, raw["t(omega)"], relations["phi(omega)"], upper))
    return relations, tuple(numeric), tuple(notes)


def _zero_factor(expr, x):
    """What must vanish for ``expr`` to vanish: ``c sqrt(A/B)`` -> ``A``."""
    expr = sp.numer(sp.together(expr))
    if expr.is_Mul:
        expr = sp.Mul(*[f for f in expr.args if f.has(x)])
    if expr.is_Pow and expr.exp.is_positive:
        return _zero_factor(expr.base, x)
    return expr


def _solvable(expr, x):
    """Whether ``expr = 0`` is worth handing to sp.solve for ``x``: algebraic in ``x``, or
    ``x`` occurring once (sympy can hang on the rest, e.g. logs of several speeds)."""
    occurrences = sum(1 for node in sp.preorder_traversal(expr) if node == x)
    return occurrences == 1 or expr.is_algebraic_expr(x)


def _invert_speed(p, t_of_omega, phi_of_omega, upper):
    """omega(t) and phi(t) when sympy can solve t(omega) = t for omega."""
    if not _solvable(t_of_omega, upper):
        return {}
    try:
        roots = sp.solve(sp.Eq(t_of_omega, t), upper)
    except NotImplementedError:
        return {}
    starting = [r for r in roots
                if sp.simplify(r.subs(t, p.start["t"]) - p.start["omega"]) == 0]
    if len(starting) != 1:
        return {}
    omega = sp.simplify(starting[0])
    return {"omega(t)": omega,
            "phi(t)": sp.factor_terms(sp.expand_log(phi_of_omega.subs(p.u, omega)))}



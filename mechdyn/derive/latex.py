"""Printing of the derivation: energies, forces, reduced quantities, equations.

Time derivatives print with dots, Greek names as Greek letters, ``J_1A`` as ``J_{1A}``.

>>> import mechdyn as md
>>> phi = md.coordinate("phi")
>>> disc = md.Mechanism("disc", [phi])
>>> _ = disc.link("disc", J=2, angle=phi)
>>> _ = disc.load("drive", 6, along=phi)
>>> print(disc.latex().splitlines()[2])
T &= \\dot{\\phi}^{2} \\\\
"""
from __future__ import annotations

import sympy as sp
from sympy.core.function import AppliedUndef

from mechdyn.derive.conditions import written
from mechdyn.derive.coupling_steps import coupling_steps
from mechdyn.derive.textbook import Budget, applies, textbook, to_latex

__all__ = ["derivation_latex", "derivation_text", "equations_latex", "derivation_steps",
           "coupling_steps", "presentable", "readable", "rhs_latex", "tidy"]

def tidy(expr, budget=None):
    """A readable form: cheaply simplified (deterministic) while ``budget`` (a
    :class:`~mechdyn.derive.textbook.Budget`) has time left."""
    if isinstance(expr, sp.Eq):
        return sp.Eq(tidy(expr.lhs, budget), tidy(expr.rhs, budget))
    return (budget or Budget()).tidy(expr)


def derivation_steps(eqs, expanded=False, budget=None) -> list:
    """The derivation as ``(label, left side LaTeX, left side text, right side)``: named
    quantities as a textbook writes them (:mod:`mechdyn.derive.textbook`), or with
    ``expanded`` (and for closed loops and imposed motions) every term written out in
    the coordinates."""
    return _derivation(eqs, expanded, budget or Budget())


def _derivation(eqs, expanded, budget) -> list:
    if not expanded and applies(eqs):
        return textbook(eqs, budget).steps
    quantities = _loop_rates(eqs) if eqs.constraints else []
    moving = set(eqs.q) | set(eqs.u) | {sp.Symbol("t", real=True)}
    return [(label, lhs_latex, lhs_text, written(rhs, quantities, moving, set(eqs.u)))
            for label, lhs_latex, lhs_text, rhs in _expanded(eqs, budget)]


def _loop_rates(eqs) -> list:
    """``(plain, named)`` rates ``theta_2' phidot`` of a one-DOF linkage's dependent
    coordinates, to write its switching conditions in."""
    from mechdyn.derive import transmission
    if len(eqs.independent) != 1 or eqs.rheonomic:
        return []
    speed = eqs.u[eqs.q.index(eqs.independent[0])]
    return [(ratio * speed, transmission.ratio_symbol(q) * speed)
            for q, ratio in transmission.ratios(eqs).items()]


def _expanded(eqs, budget) -> list:
    steps = [(label, sp.latex(symbol), str(symbol), float(value))
             for symbol, (value, label) in eqs.named_values.items()]
    for c, expr in eqs.eliminated.items():
        plain = expr.xreplace({q: sp.Symbol(q.func.__name__)
                               for q in expr.atoms(AppliedUndef)})
        name = c.func.__name__
        steps.append(("rigid", sp.latex(sp.Symbol(name)), name, plain))
    steps.append(("kinetic energy", "T", "T", budget.tidy(eqs.kinetic_energy)))
    if eqs.potential_energy != 0:
        steps.append(("potential energy", "V", "V", budget.tidy(eqs.potential_energy)))
    if eqs.dissipation != 0:
        steps.append(("dissipation", "D", "D", budget.tidy(eqs.dissipation)))
    for name, column in eqs.generalized_forces.items():
        for qi, entry in zip(eqs.q, column):
            if entry != 0:
                label = f"Q_{{\\text{{{name}}}, {sp.latex(qi)}}}" if eqs.dof > 1 else \
                    f"Q_{{\\text{{{name}}}}}"
                steps.append(("generalized force", label, f"Q[{name}, {qi}]",
                              budget.tidy(entry)))
    steps += coupling_steps(eqs)
    if eqs.constraints:
        steps += _loop_steps(eqs)
        return steps
    if eqs.dof == 1 and not eqs.rheonomic:
        inertia = budget.tidy(eqs.reduced_inertia)
        steps.append(("reduced inertia", "I_{\\mathrm{red}}", "I_red", inertia))
        steps.append(("reduced moment", "M_{\\mathrm{red}}", "M_red",
                      budget.tidy(eqs.reduced_moment)))
        q, u, a = eqs.q[0], eqs.u[0], eqs.a[0]
        textbook_lhs = ("I_{\\mathrm{red}} " + sp.latex(a) + " + \\frac{1}{2} "
                        "\\frac{d I_{\\mathrm{red}}}{d " + sp.latex(q) + "} "
                        + sp.latex(u) + "^{2}")
        steps.append(("textbook form", textbook_lhs, f"I_red*{a} + 1/2*dI_red/d{q}*{u}**2",
                      sp.Symbol("M_red")))
        lhs = inertia * a + budget.tidy(sp.diff(inertia, q) / 2) * u ** 2
        steps.append(("equation of motion", sp.latex(lhs), str(lhs), eqs.textbook_equation.rhs))
    else:
        mass = budget.tidy(eqs.mass_matrix)
        forcing = budget.tidy(eqs.forcing)
        for i in range(eqs.dof):
            lhs = sum((mass[i, j] * eqs.a[j] for j in range(eqs.dof)), sp.S.Zero)
            steps.append(("equation of motion", sp.latex(lhs), str(lhs), forcing[i]))
    return steps


def derivation_latex(eqs, expanded=False, budget=None) -> str:
    """The derivation as an ``align*`` block, a line per step (see
    :func:`derivation_steps`)."""
    budget = budget or Budget()
    steps = derivation_steps(eqs, expanded, budget)
    lines = [f"% mechdyn: {eqs.name}" + (f" (without {', '.join(eqs.excluded)})"
                                         if eqs.excluded else "")]
    if budget.spent:
        lines.append(f"% {_SPENT.format(budget.seconds)}")
    lines.append("\\begin{align*}")
    rows = [f"{lhs} &= {rhs_latex(rhs)}" for _, lhs, _, rhs in steps]
    lines += [row + " \\\\" for row in rows[:-1]] + rows[-1:]
    lines.append("\\end{align*}")
    return "\n".join(lines)


_SPENT = ("simplification stopped after the budget of {:g} s: later expressions are "
          "printed as derived")


def rhs_latex(rhs) -> str:
    """The LaTeX of a step's right side (``M_red`` in the textbook form's line)."""
    return "M_{\\mathrm{red}}" if rhs == sp.Symbol("M_red") else to_latex(rhs)


def derivation_text(eqs, expanded=False, budget=None) -> str:
    """The derivation as plain text, a labelled line per step."""
    budget = budget or Budget()
    steps = derivation_steps(eqs, expanded, budget)
    lines = [f"{eqs.name}: coordinates {', '.join(str(q) for q in eqs.q)}"]
    if eqs.excluded:
        lines.append(f"  left out: {', '.join(eqs.excluded)}")
    if budget.spent:
        lines.append(f"  ({_SPENT.format(budget.seconds)})")
    for label, _, lhs, rhs in steps:
        lines.append(f"  {label + ':':22s} {lhs} = {sp.sstr(rhs)}")
    return "\n".join(lines)


def equations_latex(eqs) -> str:
    """The equations of motion alone, one per line."""
    rows = [f"{sp.latex(tidy(e.lhs))} = {sp.latex(tidy(e.rhs))}" for e in eqs.eqs]
    return " \\\\ ".join(rows) if len(rows) == 1 else \
        "\\begin{aligned}" + " \\\\ ".join(r.replace(" = ", " &= ", 1) for r in rows) + \
        "\\end{aligned}"


_READABLE_OPS, _READABLE_DIGITS = 16, 6


def readable(number) -> bool:
    """An exact number a person reads at a glance: few operations, no long integers,
    nothing imaginary."""
    return (not number.has(sp.I) and sp.count_ops(number) <= _READABLE_OPS
            and all(abs(r.p) < 10 ** _READABLE_DIGITS and r.q < 10 ** _READABLE_DIGITS
                    for r in number.atoms(sp.Rational)))


def presentable(expr, digits=12):
    """``expr`` written for reading: numeric parts that are not readable at a glance
    (long rationals from decimal parameters, nested roots) become decimals of
    ``digits`` significant digits; symbols, functions and readable numbers stay.

    >>> import sympy as sp
    >>> w = sp.Symbol("w")
    >>> presentable(sp.Rational(105664062500000, 5543626589101) * sp.log(w) + sp.Rational(1, 2))
    19.0604581318*log(w) + 1/2
    """
    expr = sp.sympify(expr)
    if not expr.args:
        return expr if not expr.is_Rational or readable(expr) else sp.Float(expr, digits)
    if expr.is_number:
        return expr if readable(expr) else sp.Float(expr.evalf(digits + 3), digits)
    if isinstance(expr, (sp.Mul, sp.Add)):          # the numeric part as one number
        numeric = expr.func(*[a for a in expr.args if a.is_number])
        rest = [presentable(a, digits) for a in expr.args if not a.is_number]
        return expr.func(presentable(numeric, digits), *rest)
    if isinstance(expr, sp.Integral):
        return sp.Integral(presentable(expr.function, digits), *expr.limits)
    return expr.func(*[presentable(a, digits) for a in expr.args])


def _loop_steps(eqs) -> list:
    """Closed loops: the constraints, the equations of motion with the constraint forces
    ``G' lambda``, and for one-DOF linkages the transmission functions, I_red and M_red
    (in the first-order transmission functions ``theta_2'``)."""
    from mechdyn.derive import transmission
    steps = []
    multipliers = [sp.Symbol(f"lambda_{k + 1}") for k in range(len(eqs.constraints))]
    for c, lam in zip(eqs.constraints, multipliers):
        steps.append((f"loop closure ({lam})", f"0 = g_{{\\text{{{c.name}}}}}",
                      f"0 = g[{c.name}]", c.expression))
    mass, forcing = eqs.mass_matrix, eqs.forcing      # as derived (simplify is slow here)
    for i in range(eqs.dof):
        lhs = sum((mass[i, j] * eqs.a[j] for j in range(eqs.dof)), sp.S.Zero)
        pull = sum((c.gradient[i] * lam for c, lam in zip(eqs.constraints, multipliers)),
                   sp.S.Zero)
        steps.append(("equation of motion", sp.latex(lhs), str(lhs), forcing[i] + pull))
    if len(eqs.independent) != 1 or eqs.rheonomic:
        return steps
    crank = eqs.independent[0]
    for order, table in ((1, transmission.ratios(eqs)), (2, transmission.second_ratios(eqs))):
        for q, expr in table.items():
            symbol = transmission.ratio_symbol(q, order)
            text = f"d{'' if order == 1 else '2'}{q}/d{crank}{'' if order == 1 else '2'}"
            steps.append(("transmission function", sp.latex(symbol), text, expr))
    steps.append(("reduced inertia", "I_{\\mathrm{red}}", "I_red",
                  transmission.reduced_inertia_in_ratios(eqs)))
    steps.append(("reduced moment", "M_{\\mathrm{red}}", "M_red",
                  transmission.reduced_moment(eqs)))
    return steps

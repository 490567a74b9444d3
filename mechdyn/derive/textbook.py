"""The derivation as a textbook prints it: the positions, the transmission functions
once, as named quantities (``x_slider' = dx_slider/dphi``, ``x_slider''``; with several
coordinates the Jacobian entries ``dx/dphi_1``), each element's term as its element
writes it (``M_motor(phidot)``, ``-F_r x_slider' sign(phidot x_slider')``), then
``I_red``, ``I_red'``, ``M_red`` and ``I_red eps + 1/2 I_red' omega^2 = M_red`` in them.

Simplification is cheap and deterministic (``factor_terms``, ``together``: no search
whose result depends on hash order) and bounded by a :class:`Budget` in seconds; what
the budget leaves is printed as derived, and the derivation says so.

>>> import sympy as sp, mechdyn as md
>>> phi = md.coordinate("phi")
>>> J1, m3, l, M1, F3 = sp.symbols("J_1 m_3 l M_1 F_3", positive=True)
>>> yoke = md.Mechanism("Scotch yoke", [phi])
>>> _ = yoke.link("crank", J=J1, angle=phi)
>>> _ = yoke.link("yoke", m=m3, x=l * sp.cos(phi))
>>> _ = yoke.load("drive", M1, along=phi)
>>> _ = yoke.load("resistance", F3, along=l * sp.cos(phi))
>>> book = textbook(yoke.equations())
>>> book.reduced_inertia, book.reduced_inertia_slope, book.reduced_moment
(J_1 + m_3*x_yoke'**2, 2*m_3*x_yoke'*x_yoke'', F_3*x_yoke' + M_1)
>>> book.expand(book.reduced_inertia)
J_1 + l**2*m_3*sin(phi)**2
"""
from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp
from sympy.printing.latex import LatexPrinter

from mechdyn.declare.contract import call, completed
from mechdyn.derive.budget import Budget, cheap_tidy
from mechdyn.derive.conditions import written
from mechdyn.derive.coupling_steps import coupling_steps
from mechdyn.symbols import t

__all__ = ["Named", "Budget", "Derivation", "textbook", "applies", "to_latex", "cheap_tidy"]

_ANGLES = ("rad", "deg", "degree", "rev", "revolution", "1")


class Named(sp.Symbol):
    """A named quantity of the derivation: a position (``x_slider``), its derivatives
    (``x_slider'``, or ``dx_slider/dphi_1`` with several coordinates) or an element's
    law (``M_motor``). ``base`` its letter, ``owner`` the link or element, ``wrt`` the
    coordinates it is differentiated by, ``one_dof`` whether primes mean d/dq."""

    def __new__(cls, base, owner, wrt=(), one_dof=True):
        wrt = tuple(wrt)
        stem = f"{base}_{owner.replace(' ', '_')}"
        if one_dof or not wrt:
            name = stem + "'" * len(wrt)
        else:
            order = "" if len(wrt) == 1 else str(len(wrt))
            name = f"d{order}{stem}/" + "".join(f"d{q}" for q in wrt)
        obj = super().__new__(cls, name)
        obj.base, obj.owner, obj.wrt, obj.one_dof = base, owner, wrt, one_dof
        return obj

    @classmethod
    def class_key(cls):
        return 2, 1, "Symbol"          # after the parameters: m_s x_slider'^2

    def __getnewargs__(self):
        return (self.base, self.owner, self.wrt, self.one_dof)

    def _latex(self, printer):
        owner = self.owner.replace("_", "\\_")
        stem = f"{printer._print(sp.Symbol(self.base))}_{{\\text{{{owner}}}}}"
        if not self.wrt:
            return stem
        if self.one_dof:
            return stem + "^{" + "\\prime" * len(self.wrt) + "}"
        top = "\\partial" if len(self.wrt) == 1 else f"\\partial^{{{len(self.wrt)}}}"
        below = " ".join(f"\\partial {printer._print(q ** self.wrt.count(q))}"
                         for q in dict.fromkeys(self.wrt))
        return f"\\frac{{{top} {stem}}}{{{below}}}"


class InOrder(sp.Add):
    """A sum printed in the order of its terms (each element's term where it was
    declared), in LaTeX and text."""

    def _latex(self, printer):
        return printer._print_Add(self, order="none")

    def _sympystr(self, printer):
        return printer._print_Add(self, order="none")


def in_order(terms):
    """The sum of ``terms`` kept (and printed) in their order."""
    terms = [term for term in terms if term != 0]
    if len(terms) < 2:
        return sp.Add(*terms)
    return InOrder(*terms, evaluate=False)


class _Printer(LatexPrinter):
    """sympy's LaTeX with powers of fraction-like named quantities in parentheses."""

    def _print_Pow(self, expr):
        if isinstance(expr.base, Named) and expr.base.wrt and not expr.base.one_dof \
                and expr.exp.is_Integer and expr.exp > 0:
            return f"\\left({self._print(expr.base)}\\right)^{{{self._print(expr.exp)}}}"
        return super()._print_Pow(expr)


def to_latex(expr) -> str:
    """LaTeX of a derivation's expression (named quantities as textbooks write them)."""
    return _Printer().doprint(expr)


@dataclass
class Derivation:
    """The named derivation of one mechanism: ``steps`` (label, LaTeX left side, text
    left side, right side), ``quantities`` (named symbol -> its definition in the
    coordinates), the mass matrix and generalized forces in the named quantities and,
    for one DOF, ``reduced_inertia``, ``reduced_inertia_slope`` (``dI_red/dphi``) and
    ``reduced_moment``. :meth:`expand` writes an expression back in the coordinates."""
    steps: list
    quantities: dict
    mass_matrix: sp.Matrix
    forces: sp.Matrix
    velocity_terms: sp.Matrix
    reduced_inertia: object = None
    reduced_inertia_slope: object = None
    reduced_moment: object = None
    budget_spent: bool = False
    terms: dict = field(default_factory=dict)

    def expand(self, expr):
        """``expr`` with every named quantity replaced by its definition."""
        return sp.sympify(expr).xreplace(self.quantities)


def applies(eqs) -> bool:
    """Whether the named derivation applies: no closed loops and no positions or
    ``along`` expressions that depend explicitly on time."""
    alongs = [along for work in eqs.works.values() for _, along in work.forces]
    return not (eqs.constraints or eqs.rheonomic or eqs.gears
                or any(t in expr.free_symbols for expr in alongs))


class _Book:
    """Names positions and derivatives as they are first needed (see :func:`textbook`)."""

    def __init__(self, eqs, budget):
        self.eqs, self.budget = eqs, budget
        self.q, self.one = tuple(eqs.q), eqs.dof == 1
        self.moving = set(eqs.q) | set(eqs.u) | {t}
        self.definitions, self.kinds = {}, {}
        self.by_expr, self.slopes = {}, {}
        self.link_names, self.written = {}, None
        for name, (m, J, x, y, angle) in eqs.links.items():
            for base, expr in (("x", x), ("y", y), ("theta", angle)):
                self.link_names.setdefault(expr, (base, name))

    def define(self, symbol, expr, kind):
        self.definitions[symbol] = expr
        self.kinds[symbol] = kind
        return symbol

    def position(self, expr, base, owner):
        """A named position for an expression nonlinear in the coordinates (the link's
        name where a link has it), else the expression itself."""
        if self._linear(expr):
            return expr
        for sign in (1, -1):
            if sign * expr in self.by_expr:
                return sign * self.by_expr[sign * expr]
        base, owner = self.link_names.get(expr, (base, owner))
        symbol = self.define(Named(base, owner, one_dof=self.one), expr, "position")
        self.by_expr[expr] = symbol
        return symbol

    def _linear(self, expr):
        present = expr.free_symbols & set(self.q)
        return all(not (sp.diff(expr, qi).free_symbols & set(self.q)) for qi in present)

    def value(self, expr, letter, owner):
        """An element's law: named (``M_motor``) when it varies with the motion."""
        if not (expr.free_symbols & self.moving):
            return expr
        return self.define(Named(letter, owner), expr, "law")

    def slope(self, expr, qk):
        """``d expr / d qk`` by the chain rule through the named quantities."""
        total = sp.diff(expr, qk)
        for symbol in sorted(expr.atoms(Named), key=str):
            factor = sp.diff(expr, symbol)
            if factor != 0:
                total += factor * self._named_slope(symbol, qk)
        return total

    def _named_slope(self, symbol, qk):
        key = (symbol, qk)
        if key not in self.slopes:
            raw = sp.diff(self.definitions[symbol], qk)
            if raw.free_symbols & set(self.q) and self.kinds[symbol] != "law":
                wrt = tuple(sorted(symbol.wrt + (qk,), key=self.q.index))
                named = Named(symbol.base, symbol.owner, wrt, self.one)
                if named not in self.definitions:
                    self.define(named, self.budget.tidy(raw), f"order {len(wrt)}")
                raw = named
            self.slopes[key] = raw
        return self.slopes[key]

    def rate(self, expr):
        return sp.Add(*[self.slope(expr, qk) * uk for qk, uk in zip(self.q, self.eqs.u)])

    def shown(self, expr):
        """``expr`` with its switching conditions as written (:mod:`~mechdyn.derive.
        conditions`): in the named positions and their rates, moving side first."""
        if not isinstance(expr, sp.Basic) or not expr.has(sp.Piecewise):
            return expr
        if isinstance(expr, InOrder):
            return InOrder(*[self.shown(term) for term in expr.args], evaluate=False)
        return written(expr, self.quantities(), self.moving, set(self.eqs.u))

    def quantities(self):
        """``(plain, named)`` of the named positions and their rates, taken once (after
        the terms are named, before the steps print: a rate names its slopes)."""
        if self.written is None:
            positions = [s for s in self.definitions if self.kinds[s] == "position"]
            self.written = [(self.definitions[s], s) for s in positions] + \
                [(self.rate(self.definitions[s]), self.rate(s)) for s in positions]
        return self.written

    def letter(self, along):
        """M for a moment (along an angle), F for a force, Q when it cannot tell."""
        named = along.atoms(Named)
        if len(named) == 1:                       # a named position, perhaps negated
            base = next(iter(named)).base
            return "M" if base == "theta" else "F" if base in "xy" else "Q"
        units = [self.eqs.coordinate_units.get(q, "rad") for q in along.free_symbols
                 if q in self.q]
        return "M" if all(unit in _ANGLES for unit in units) else "F"


class _NamedMotion:
    """The motion elements write their terms with (:mod:`mechdyn.declare.element_base`),
    in the book's named positions and laws."""

    def __init__(self, book):
        self.book = book
        self.plain = book.eqs.to_plain

    def position(self, expr, owner):
        return self.book.position(self.plain(expr), "s", owner)

    def law(self, expr, along, owner):
        return self.book.value(self.plain(expr), self.book.letter(along), owner)

    def rate(self, expr):
        return self.book.rate(expr)

    def heights(self):
        return [(link, m, self.book.position(y, "y", link) if m != 0 else sp.S.Zero)
                for link, (m, _, _, y, _) in self.book.eqs.links.items()]


def textbook(eqs, budget=None) -> Derivation:
    """The named derivation of ``eqs`` (see the module); ``budget`` a :class:`Budget`."""
    budget = budget or Budget()
    book = _Book(eqs, budget)
    for symbol, (value, _) in eqs.named_values.items():
        book.define(symbol, value, "value")
    n, q, u = eqs.dof, book.q, eqs.u
    kinetic, mass = sp.S.Zero, sp.zeros(n, n)
    for name, (m, J, x, y, angle) in eqs.links.items():
        for inertia, expr, base in ((m, x, "x"), (m, y, "y"), (J, angle, "theta")):
            h = book.position(expr, base, name) if inertia != 0 else sp.S.Zero
            if not h.free_symbols & (set(q) | set(book.definitions)):
                continue
            grads = [book.slope(h, qk) for qk in q]
            kinetic += inertia * book.rate(h) ** 2 / 2
            mass += inertia * sp.Matrix(n, n, lambda i, j: grads[i] * grads[j])
    potential, dissipation, terms = sp.S.Zero, sp.S.Zero, {}
    motion = _NamedMotion(book)
    for name, element in eqs.acting.items():
        work = completed(element, call(element, "work", motion), q, book.slope)
        potential += work.potential
        dissipation += work.dissipation
        if not work.forces:
            continue                             # a stop: its limits are printed apart
        column = sp.zeros(n, 1)
        for value, along in work.forces:
            column += value * sp.Matrix([book.slope(along, qk) for qk in q])
        terms[name] = column
    forces = sp.Matrix(n, 1, lambda i, _: sp.Add(*[c[i] for c in terms.values()]))
    mass = mass.applyfunc(lambda e: sp.factor_terms(sp.expand(e)))
    christoffel = _velocity_terms(book, mass)
    result = Derivation([], book.definitions, mass, forces, christoffel, terms=terms)
    if n == 1:
        result.reduced_inertia = mass[0, 0]
        result.reduced_inertia_slope = sp.factor_terms(sp.expand(book.slope(mass[0, 0], q[0])))
        result.reduced_moment = forces[0]
    book.quantities()
    result.steps = _steps(eqs, book, result, kinetic, potential, dissipation)
    result.budget_spent = budget.spent
    return result


def _velocity_terms(book, mass):
    """``h_i = sum_jk G_ijk u_j u_k`` (Christoffel symbols of the named mass matrix)."""
    n, q, u = mass.shape[0], book.q, book.eqs.u
    if n == 1:
        return sp.Matrix([sp.factor_terms(sp.expand(book.slope(mass[0, 0], q[0]) / 2)) * u[0] ** 2])
    slope = {(i, j, k): book.slope(mass[i, j], q[k])
             for i in range(n) for j in range(n) for k in range(n)}
    rows = []
    for i in range(n):
        total = sp.Add(*[(slope[i, j, k] + slope[i, k, j] - slope[j, k, i]) / 2 * u[j] * u[k]
                         for j in range(n) for k in range(n)])
        rows.append(sp.factor_terms(sp.expand(total)))
    return sp.Matrix(rows)


def _steps(eqs, book, result, kinetic, potential, dissipation) -> list:
    steps = []
    for c, expr in eqs.eliminated.items():
        steps.append(("rigid", sp.latex(sp.Symbol(c.func.__name__)), c.func.__name__,
                      expr.xreplace({c: sp.Symbol(c.func.__name__)})))
    steps += [(label, to_latex(symbol), str(symbol), float(value))
              for symbol, (value, label) in eqs.named_values.items()]
    order = ["position", "order 1", "order 2", "order 3", "law"]
    labels = {"position": "position", "order 1": "transmission function",
              "order 2": "transmission function", "order 3": "transmission function",
              "law": "element law"}
    names = list(book.definitions)

    def rank(symbol):               # derivatives in the order of their positions
        stem = Named(symbol.base, symbol.owner, one_dof=symbol.one_dof)
        return names.index(stem) if stem in book.definitions else 0, str(symbol)
    for kind in order:
        chosen = [s for s in book.definitions if book.kinds[s] == kind]
        for symbol in sorted(chosen, key=rank) if kind != "law" else chosen:
            expr = book.definitions[symbol]
            lhs_latex, lhs_text = to_latex(symbol), str(symbol)
            if kind == "law":
                args = sorted(expr.free_symbols & book.moving, key=str)
                lhs_latex += "\\left(" + ", ".join(map(sp.latex, args)) + "\\right)"
                lhs_text += "(" + ", ".join(map(str, args)) + ")"
            steps.append((labels[kind], lhs_latex, lhs_text, book.shown(expr)))
    steps.append(("kinetic energy", "T", "T", sp.factor_terms(kinetic)))
    if potential != 0:
        steps.append(("potential energy", "V", "V", potential))
    if dissipation != 0:
        steps.append(("dissipation", "D", "D", dissipation))
    steps += coupling_steps(eqs)
    q, u, a = eqs.q, eqs.u, eqs.a
    moment = in_order([column[0] for column in result.terms.values()]) if eqs.dof == 1 else None
    if eqs.dof == 1:
        dq = sp.latex(q[0])
        slope_latex = f"\\frac{{d I_{{\\mathrm{{red}}}}}}{{d {dq}}}"
        steps.append(("reduced inertia", "I_{\\mathrm{red}}", "I_red", result.reduced_inertia))
        steps.append(("its slope", slope_latex, f"dI_red/d{q[0]}", result.reduced_inertia_slope))
        steps.append(("reduced moment", "M_{\\mathrm{red}}", "M_red", book.shown(moment)))
        textbook_lhs = (f"I_{{\\mathrm{{red}}}} {sp.latex(a[0])} + \\frac{{1}}{{2}} "
                        f"{slope_latex} {sp.latex(u[0])}^{{2}}")
        steps.append(("textbook form", textbook_lhs,
                      f"I_red*{a[0]} + 1/2*dI_red/d{q[0]}*{u[0]}**2", sp.Symbol("M_red")))
    for i in range(eqs.dof):
        force = in_order([column[i] for column in result.terms.values()])
        if eqs.dof > 1 and force != 0:
            steps.append(("generalized force", f"Q_{{{sp.latex(q[i])}}}", f"Q[{q[i]}]",
                          book.shown(force)))
        parts = [(result.mass_matrix[i, j], a[j]) for j in range(eqs.dof)
                 if result.mass_matrix[i, j] != 0]
        if eqs.dof == 1:        # the textbook's 1/2 I_red' omega^2
            parts.append((result.reduced_inertia_slope / 2, u[0] ** 2))
        else:
            parts.append((1, result.velocity_terms[i]))
        parts = [(m, x) for m, x in parts if m * x != 0]
        latex_lhs = " + ".join(_product(m, x, to_latex, " ", "\\left(", "\\right)")
                               for m, x in parts)
        text_lhs = " + ".join(_product(m, x, sp.sstr, "*", "(", ")") for m, x in parts)
        steps.append(("equation of motion", latex_lhs.replace("+ -", "- "),
                      text_lhs.replace("+ -", "- "), book.shown(force)))
    return steps


def _product(factor, x, printer, times, left, right) -> str:
    """``factor * x`` printed with ``factor`` first, in parentheses when it is a sum."""
    if factor == 1:
        return printer(x)
    first = left + printer(factor) + right if factor.is_Add else printer(factor)
    return first + times + printer(x)

"""Derivation: energies and generalized forces -> Lagrange's equations of the 2nd kind.

Produces ``M(q) q'' = f(q, q', t)`` in plain symbols (``phi``, ``phidot``, ``phiddot``).
The mass matrix is never inverted symbolically. With ``T = u'M(q,t)u/2 + b(q,t)'u + T0``
and momenta ``p = dT/du`` the i-th equation is

    sum_j M_ij q''_j = Q_i + dT/dq_i - sum_k dp_i/dq_k u_k - dp_i/dt

For one coordinate it also gives the reduced inertia ``I_red = M_11``, the reduced moment
``M_red = Q`` and the textbook form ``I_red eps + I_red'/2 omega^2 = M_red``.

>>> import sympy as sp, mechdyn as md
>>> phi = md.coordinate("phi")
>>> gear = md.Mechanism("disc", [phi])
>>> _ = gear.link("disc", J=2, angle=phi)
>>> _ = gear.load("drive", 6, along=phi)
>>> gear.equations().eqs
[Eq(2*phiddot, 6)]
"""
from __future__ import annotations

import sympy as sp
from mechdyn.declare.contract import call, checked_work, completed
from mechdyn.declare.elements import Constraint, Link, is_structural
from mechdyn.errors import DerivationError
from mechdyn.symbols import dotted_symbol, t
from mechdyn.derive.terms import (ConstraintTerm, ContactTerm, Equations, FrictionTerm, GearTerm)
from mechdyn.derive.regularity import check_regular

__all__ = ["derive", "element_works"]


# ----------------------------------------------------------------------- derivation
def derive(mechanism, element_names=None, rigid=(), printed=False) -> Equations:
    """Form the equations of ``mechanism`` with the named elements (all if None) and
    the springs in ``rigid`` (pairs ``(spring name, coordinate name or None)``) rigid;
    ``printed``: of the elements as the printed derivation writes them (standard
    gravity as ``g``, its value in ``named_values``)."""
    elements, named_values = mechanism.elements, {}
    if printed:
        elements, named_values = _printed(mechanism)
    if element_names is None:
        element_names = tuple(n for n, e in elements.items() if not is_structural(e))
    rigid_names = tuple(name for name, _ in rigid)
    frame = _Frame(mechanism, rigid)
    q, u, a, gradient, rate = frame.q, frame.u, frame.a, frame.gradient, frame.rate
    kept, eliminated, plain_of = frame.kept, frame.eliminated, frame.plain_of
    to_plain, link_plain, motion = frame.to_plain, frame.links, frame.motion
    coords = list(mechanism.coordinates)

    def scaled(factor, column):        # factor * column, skipping the zero entries
        return column.applyfunc(lambda entry: factor * entry if entry != 0 else entry)

    # Sums built once from their terms (``+=`` re-sorts the whole sum: N^2 for N links)
    kinetic = sp.Add(*[m * (rate(x) ** 2 + rate(y) ** 2) / 2 + J * rate(angle) ** 2 / 2
                       for m, J, x, y, angle in link_plain.values()])
    potentials, dissipations = [], []
    rheonomic = any(t in e.free_symbols for (_, _, *pos) in link_plain.values() for e in pos)

    def moving(expr):                  # gradient, rate and bias of an expression
        grad = gradient(expr)
        slide = rate(expr, grad)
        bias = sum((_diff(slide, qi) * ui for qi, ui in zip(q, u)), sp.S.Zero) \
            + _diff(slide, t)
        return grad, slide, bias

    forces, powers, frictions, contacts, works = {}, {}, [], [], {}
    for name in element_names:
        if name in rigid_names:
            continue
        work = checked_work(elements[name], motion, coords)
        works[name] = work = completed(elements[name], work, q, _diff,
                                       u if _foreign(elements[name]) else ())
        potentials.append(work.potential)
        dissipations.append(work.dissipation)
        columns = [scaled(value, gradient(along)) for value, along in work.forces]
        column = columns[0] if len(columns) == 1 else sum(columns, sp.zeros(len(q), 1))
        if work.sliding is not None:
            frictions.append(_friction_term(name, work.sliding, moving))
        for limit in work.contacts:
            grad, slide, bias = moving(limit.along)
            side = limit.side
            contacts.append(ContactTerm(limit.label, name, side * (limit.along - limit.limit),
                                        side * grad, side * slide, side * bias,
                                        limit.restitution))
        forces[name] = column
        powers[name] = sp.Add(*[value * u[i] for (i, _), value in column.todok().items()])

    potential, dissipation = sp.Add(*potentials), sp.Add(*dissipations)
    constraints = _constraint_terms(mechanism, to_plain, gradient, rate, q, u)
    gears = []
    for index, constraint in enumerate(constraints):
        element = elements.get(constraint.name)
        sliding = (checked_work(element, motion, coords).sliding
                   if isinstance(element, Constraint) else None)
        if sliding is not None:        # a lossy gear: its mesh loss slides or sticks
            gears.append(GearTerm(constraint.name, index, len(frictions), sliding.law))
            frictions.append(_friction_term(constraint.name, sliding, moving))
    constrained = {qi for c in constraints for qi, g in zip(q, c.gradient) if g != 0}
    mass, inertial = _lagrange(kinetic, q, u)
    for i, qi in enumerate(q):
        if mass[i, i] == 0 and qi not in constrained:
            raise DerivationError(
                f"mechanism {mechanism.name!r}: no inertia in coordinate {qi}: no link's "
                "mass or moment of inertia moves with it (give a link m or J that moves "
                "with it, or make its spring rigid in the scene)")
    if not constraints:     # with loops M need only be regular on the loops' motions
        check_regular(mass, q, mechanism.name)
    excluded = tuple(n for n, e in elements.items()
                     if not is_structural(e) and n not in element_names)
    return Equations(
        name=mechanism.name, coordinates=tuple(kept), q=q, u=u, a=a,
        mass_matrix=mass, inertial_forcing=inertial, kinetic_energy=kinetic,
        potential_energy=potential, dissipation=dissipation, generalized_forces=forces,
        powers=powers, frictions=tuple(frictions),
        eliminated={c: expr for c, expr in eliminated.items()},
        elements=tuple(n for n in element_names if n not in rigid_names),
        excluded=excluded, rigid=rigid_names, rheonomic=rheonomic, links=link_plain,
        to_plain=to_plain, constraints=constraints,
        independent=tuple(plain_of[c] for c in mechanism.independent if c in frame.index_of),
        contacts=tuple(contacts), gears=tuple(gears), works=works,
        acting={name: elements[name] for name in works},
        coordinate_units={plain_of[c]: mechanism.units.get(c.func.__name__, "rad")
                          for c in kept}, named_values=named_values)


def _printed(mechanism) -> tuple:
    """``(elements, named values)`` as the printed derivation writes them; a symbol
    whose name a parameter of the mechanism has already keeps its number (no two g)."""
    taken = set(mechanism._parameter_names()) | set(mechanism.parameter_units)
    elements, values = {}, {}
    for name, element in mechanism.elements.items():
        shown, named = call(element, "printed")
        if named and not {symbol.name for symbol in named} & taken:
            element = shown
            values.update(named)
        elements[name] = element
    return elements, values


def _foreign(element) -> bool:
    """An element class defined outside mechdyn (its forces are checked against its
    potential; mechdyn's own give both)."""
    return type(element).__module__.split(".")[0] != "mechdyn"


def _constraint_terms(mechanism, to_plain, gradient, rate, q, u) -> tuple:
    """The scalar constraints of the mechanism's loops, with gradients and biases."""
    terms = []
    for element in mechanism.elements.values():
        if not isinstance(element, Constraint):
            continue
        for label, g in zip(element.labels, element.equations):
            expr = to_plain(g)
            grad = gradient(expr)
            if all(entry == 0 for entry in grad):
                raise DerivationError(
                    f"constraint {label} = {g} does not depend on the coordinates "
                    f"{', '.join(map(str, q))} (after rigid springs are eliminated)")
            speed = rate(expr, grad)
            bias = sp.Add(*[_diff(speed, qi) * ui for qi, ui in zip(q, u)],
                          _diff(speed, t))
            terms.append(ConstraintTerm(label, expr, grad, bias))
    return tuple(terms)


def _lagrange(kinetic, q, u):
    """Mass matrix and velocity-dependent inertia forcing from the kinetic energy.

    With ``T = u'M u/2 + b'u + T0`` (``b``, ``T0`` nonzero only for imposed motions):
    ``f_i = -sum_jk G_ijk u_j u_k - sum_j dM_ij/dt u_j + sum_k (db_k/dq_i - db_i/dq_k) u_k
    - db_i/dt + dT0/dq_i`` with the Christoffel symbols
    ``G_ijk = (dM_ij/dq_k + dM_ik/dq_j - dM_jk/dq_i) / 2``: the textbook ``-I'/2 omega^2``
    for one coordinate, every derivative of ``M`` taken once.
    """
    n = len(q)
    at_rest = {ui: sp.S.Zero for ui in u}
    momenta = _momenta(kinetic, u)
    entries = [[sp.S.Zero] * n for _ in range(n)]       # M_ij: only where p_i holds u_j
    column = {uj: j for j, uj in enumerate(u)}
    for i, momentum in enumerate(momenta):
        for uj in momentum.free_symbols & column.keys():
            entries[i][column[uj]] = _diff(momentum, uj)
    mass = sp.Matrix(entries)
    b = [m.xreplace(at_rest) for m in momenta]
    base = kinetic.xreplace(at_rest)
    imposed = [j for j in range(n) if b[j] != 0]     # b: imposed motions only
    # Only entries of M that hold q_k have a slope along it (a chain's M holds none).
    index = {qk: k for k, qk in enumerate(q)}
    slopes = {(i, j, index[qk]): _diff(entry, qk)
              for (i, j), entry in mass.todok().items()
              for qk in entry.free_symbols & index.keys()}
    pairs = [set() for _ in range(n)]     # per i: the (j <= k) with a Christoffel symbol
    for i, j, k in slopes:
        pairs[i].add((min(j, k), max(j, k)))
        pairs[k].add((min(i, j), max(i, j)))
    zero = sp.S.Zero
    inertial = sp.zeros(n, 1)
    for i in range(n):
        terms = []
        for j, k in sorted(pairs[i]):
            parts = (slopes.get((i, j, k), zero), slopes.get((i, k, j), zero),
                     slopes.get((j, k, i), zero))
            christoffel = (parts[0] + parts[1] - parts[2]) / 2
            terms.append(-christoffel * u[j] * u[k] * (1 if j == k else 2))
        for j in range(n):
            if entries[i][j] != 0:
                terms.append(-_diff(entries[i][j], t) * u[j])
        for j in (range(n) if b[i] != 0 else imposed):
            terms.append((_diff(b[j], q[i]) - _diff(b[i], q[j])) * u[j])
        terms += [-_diff(b[i], t), _diff(base, q[i])]
        inertial[i] = sp.Add(*[term for term in terms if term is not zero])
    return mass, inertial


def _momenta(kinetic, u):
    """``dT/du_i`` for every speed, each from the terms of ``T`` that hold ``u_i`` (one
    pass over the terms: a chain of N bodies has N of them)."""
    if not kinetic.is_Add:
        return [_diff(kinetic, ui) for ui in u]
    holding = {ui: [] for ui in u}
    for term in kinetic.args:
        for symbol in term.free_symbols:
            if symbol in holding:
                holding[symbol].append(term)
    return [sp.Add(*[sp.diff(term, ui) for term in holding[ui]]) for ui in u]


def _diff(expr, x):
    """``d expr / d x`` for a plain symbol ``x``: zero at once when ``expr`` does not
    contain it, and term by term over the terms of a sum that contain it (sympy's diff
    costs about as much for a zero as for a term, and a chain of N bodies asks for N^2
    of them)."""
    if x not in expr.free_symbols:
        return sp.S.Zero
    if expr.is_Add:      # a sum of many terms (an energy): only the terms that hold x
        return sp.Add(*[sp.diff(term, x) for term in expr.args if x in term.free_symbols])
    return sp.diff(expr, x)


def element_works(mechanism, names, rigid=()) -> dict:
    """``{name: Work}`` of the named elements, written with the motion :func:`derive`
    gives them (the rigid springs in ``rigid`` eliminated): what they contribute, without
    deriving the equations (the motion is remembered until the mechanism changes)."""
    frame = mechanism._memo.get(("frame", rigid))
    if frame is None:
        frame = mechanism._memo[("frame", rigid)] = _Frame(mechanism, rigid)
    coords = list(mechanism.coordinates)
    return {name: checked_work(mechanism.elements[name], frame.motion, coords)
            for name in names}


class _Frame:
    """A mechanism's plain symbols with the ``rigid`` springs' coordinates eliminated:
    ``q``, ``u``, ``a`` of the kept coordinates, ``to_plain``, ``rate`` (time derivative),
    ``gradient`` (each expression's taken once), the links' plain ``(m, J, x, y,
    angle)`` and the ``motion`` elements write their work with."""

    def __init__(self, mechanism, rigid):
        coords = list(mechanism.coordinates)
        self.plain_of = plain_of = {q: dotted_symbol(q.func.__name__, 0) for q in coords}
        self.speed_of = {sp.Derivative(q, t): dotted_symbol(q.func.__name__, 1)
                         for q in coords}
        self.eliminated = _eliminate(mechanism, rigid, self.plain, coords)
        self.kept = [q for q in coords if q not in self.eliminated]
        self.q = tuple(plain_of[c] for c in self.kept)
        self.u = tuple(dotted_symbol(c.func.__name__, 1) for c in self.kept)
        self.a = tuple(dotted_symbol(c.func.__name__, 2) for c in self.kept)
        self.subs = _substitutions(self.eliminated, plain_of, self.q, self.u)
        self.gradients = {}
        self.index = {qi: i for i, qi in enumerate(self.q)}
        self.index_of = {c: i for i, c in enumerate(self.kept)}
        self.links = {}
        for name, link in mechanism.elements.items():
            if isinstance(link, Link):
                self.links[name] = (link.m, link.J, self.to_plain(link.x),
                                    self.to_plain(link.y), self.to_plain(link.angle))
        self.motion = _Motion(self.to_plain, lambda expr: self.rate(expr, self.gradient(expr)),
                              self.links)

    def plain(self, expr):
        return expr.xreplace(self.speed_of).xreplace(self.plain_of)

    def to_plain(self, expr):
        position_subs, speed_subs = self.subs
        return self.plain(expr).xreplace(speed_subs).xreplace(position_subs)

    def rate(self, expr, grad=None):     # d expr/dt; pass grad if it is already known
        if grad is None:                 # the slopes along the coordinates it holds
            index = self.index
            slopes = [(index[qi], _diff(expr, qi)) for qi in expr.free_symbols & index.keys()]
        else:
            slopes = [(i, g) for (i, _), g in grad.todok().items()]
        return sp.Add(*[g * self.u[i] for i, g in slopes], _diff(expr, t))

    def gradient(self, expr):            # each expression's gradient is taken once
        if expr not in self.gradients:
            present = expr.free_symbols
            self.gradients[expr] = sp.Matrix([_diff(expr, qi) if qi in present else sp.S.Zero
                                              for qi in self.q])
        return self.gradients[expr].copy()


class _Motion:
    """The motion elements write their work with (:mod:`mechdyn.declare.element_base`):
    plain symbols, rigid springs' coordinates eliminated."""

    def __init__(self, to_plain, rate, links):
        self.plain, self.rate, self.links = to_plain, rate, links

    def position(self, expr, owner):
        return self.plain(expr)

    def law(self, expr, along, owner):
        return self.plain(expr)

    def heights(self):
        return [(name, m, y) for name, (m, _, _, y, _) in self.links.items()]


def _friction_term(name, sliding, moving) -> FrictionTerm:
    grad, slide, bias = moving(sliding.along)
    return FrictionTerm(name, sliding.magnitude, grad, slide, bias, sliding.kind,
                        sliding.peak, sliding.release)


def _eliminate(mechanism, rigid, plain, coords):
    """Solve each rigid spring's ``stretch = 0`` for one coordinate (time functions)."""
    eliminated = {}
    by_name = {q.func.__name__: q for q in coords}
    for spring_name, coordinate_name in rigid:
        spring = mechanism.elements[spring_name]
        stretch = spring.stretch.subs(eliminated)
        present = [q for q in coords if q not in eliminated and stretch.has(q)]
        if coordinate_name is not None:
            if coordinate_name not in by_name:
                raise DerivationError(f"rigid {spring_name!r}: {coordinate_name!r} is not a "
                                      f"coordinate of {mechanism.name!r}")
            candidates = [by_name[coordinate_name]]
        else:
            candidates = list(reversed(present))   # eliminate the last-declared first
        solution = None
        for q in candidates:
            roots = sp.solve(sp.Eq(stretch, 0), q) if stretch.has(q) else []
            if len(roots) == 1:
                solution = (q, roots[0])
                break
        if solution is None:
            tried = ", ".join(c.func.__name__ for c in candidates) or "none"
            raise DerivationError(
                f"rigid {spring_name!r}: cannot solve stretch = {spring.stretch} = 0 for a "
                f"unique coordinate (tried: {tried}); rigid springs need a stretch that "
                "fixes one coordinate through the others")
        q, expr = solution
        eliminated = {c: e.subs(q, expr) for c, e in eliminated.items()}
        eliminated[q] = expr
    return eliminated


def _substitutions(eliminated, plain_of, q, u):
    """Plain-symbol substitutions for eliminated coordinates and their speeds."""
    position_subs, speed_subs = {}, {}
    for c, expr in eliminated.items():
        g = expr.xreplace(plain_of)
        position_subs[plain_of[c]] = g
        speed_subs[dotted_symbol(c.func.__name__, 1)] = (
            sum((sp.diff(g, qi) * ui for qi, ui in zip(q, u)), sp.S.Zero) + sp.diff(g, t))
    return position_subs, speed_subs

"""Closed-form solutions of the one-DOF equation of motion, the five-case classification
and inverse dynamics (the driving moment a prescribed motion needs).

``I_red(phi) eps + 1/2 I_red'(phi) omega^2 = M_red`` integrates in closed form when
``I_red`` is constant and ``M_red`` depends on one of ``t``, ``phi``, ``omega`` (cases 1
and 2), or when ``I_red = I(phi)`` and ``M_red = M(phi)`` (case 3, the energy integral).
Cases 4 and 5 (``M_red`` of ``phi`` and ``omega``, or any other mixed dependence) need
numerical integration (``mech.simulate``). Float parameters become exact rationals
(``0.6 -> 3/5``), so the closed forms are exact. Coulomb friction ``-F sign(omega)`` takes
its sign from the initial speed; the closed form then ends where the sliding does.

>>> import sympy as sp, mechdyn as md
>>> phi = md.coordinate("phi")
>>> brake = md.Mechanism("brake", [phi])
>>> _ = brake.link("disc", J=sp.Symbol("I"), angle=phi)
>>> _ = brake.friction("shoe", 0.8, along=phi)
>>> braking = md.Scene("braking", initial={phi: 0, md.speed(phi): 100}, until=md.stopped(phi))
>>> sol = md.closed_form(brake, braking, {sp.Symbol("I"): 0.4})
>>> sol.classification.case, sol["omega(t)"], sol["phi(t)"]
(1, 100 - 2*t, -t**2 + 100*t)
>>> sol.stop.t, sol.stop.phi
(50, 2500)
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import sympy as sp
from scipy.integrate import quad
from scipy.optimize import minimize_scalar

from mechdyn.declare.elements import as_expression
from mechdyn.errors import MechdynError, ParameterError, SceneError
from mechdyn.derive.latex import presentable, readable
from mechdyn.declare.parameters import ParameterSet
from mechdyn.declare.parameters import exact_floats as _exact
from mechdyn.symbols import t

__all__ = ["AnalyticError", "Classification", "classify", "StopPoint", "Solution",
           "closed_form", "Motion", "uniform_rotation", "uniform_acceleration",
           "DrivingMoment", "driving_moment"]

_QUAD = {"epsabs": 0.0, "epsrel": 1e-12, "limit": 400}          # relations
_STATS_QUAD = {"epsabs": 1e-12, "epsrel": 1e-12, "limit": 400}   # mean and RMS
_ROLE_WORDS = {"t": "the time", "phi": "the position", "omega": "the speed"}


class AnalyticError(MechdynError, ValueError):
    """A question the closed-form solver cannot answer (several degrees of freedom, a
    case that needs numerical integration, an integral sympy cannot do)."""


# ------------------------------------------------------------------- the problem
@dataclass(frozen=True)
class _Problem:
    """A one-DOF machine under a scene, in plain symbols, parameters substituted."""
    name: str
    q: sp.Symbol
    u: sp.Symbol
    inertia: sp.Expr
    moment: sp.Expr
    start: dict          # role -> value: "t", "phi", "omega"
    friction: bool       # a friction sign was fixed from the initial speed

    def role(self, name):
        return {"t": t, "phi": self.q, "omega": self.u}[name]


def _substitution(mech, scene, params):
    """Exact values of the given parameters (keys: symbols or names) by symbol."""
    return ParameterSet(params, mechanism=mech, scene=scene).exact()


def _one_dof(mech, scene, what):
    eqs = mech.equations(scene)
    if eqs.dof != 1:
        names = ", ".join(str(q) for q in eqs.q)
        raise AnalyticError(
            f"{what}: {mech.name!r} has {eqs.dof} coordinates ({names}); closed forms and "
            "the five cases are for one-DOF machines. Simulate it with "
            "mech.simulate(scene, params), or make springs rigid in the scene to reduce it")
    return eqs


def _fix_friction_sign(moment, q, u, direction):
    """Replace ``sign(c u)`` (``c`` free of position, speed and time) by its value while
    sliding in ``direction``."""
    fixed = {}
    for s in moment.atoms(sp.sign):
        ratio = sp.simplify(s.args[0] / u)
        if not ratio.has(u, q, t):
            fixed[s] = sp.sign(ratio) * direction
    return moment.xreplace(fixed), bool(fixed)


def _reduced(mech, scene, params, what, drive=None):
    """Equations, parameter substitution, exact I_red and M_red (without ``drive``)."""
    eqs = _one_dof(mech, scene, what)
    subs = _substitution(mech, scene, params)
    moment = eqs.reduced_moment
    if drive is not None:
        left_out = [n for n in eqs.generalized_forces
                    if n == drive or drive in mech.elements[n].tags]
        if not left_out:
            raise AnalyticError(f"{what}: no load named or tagged {drive!r} in "
                                f"{mech.name!r} (loads: {', '.join(eqs.generalized_forces)})")
        moment = moment - sp.Add(*[eqs.generalized_forces[n][0] for n in left_out])
    return (eqs, subs, _exact(eqs.reduced_inertia.xreplace(subs)),
            _exact(moment.xreplace(subs)))


def _problem(mech, scene, params, what):
    eqs, subs, inertia, moment = _reduced(mech, scene, params, what)
    q, u = eqs.q[0], eqs.u[0]
    start = {"t": sp.S.Zero, "phi": sp.S.Zero, "omega": sp.S.Zero}
    direction = sp.S.One
    if scene is not None:
        from mechdyn.declare.scene_units import check_given
        check_given(mech, scene)
        coordinate = eqs.coordinates[0]
        for role, key in (("phi", coordinate), ("omega", sp.Derivative(coordinate, t))):
            if key not in scene.initial:
                raise SceneError(f"scene {scene.name!r} gives no initial value of {key}")
            start[role] = _exact(as_expression(scene.initial[key], f"initial {key}")
                                 .xreplace(subs))
        start["t"] = _exact(sp.Float(scene.t_start))
        direction = sp.sign(start["omega"])
    one_way = [name for name in eqs.switching if name not in
               {f.name for f in eqs.frictions if f.kind == "friction"}]
    if one_way:
        raise AnalyticError(f"{what}: {mech.name!r} has stops or one-way elements "
                            f"({', '.join(one_way)}) whose modes are decided numerically: "
                            "use mech.simulate(scene, params)")
    if direction == 0 and eqs.frictions:
        raise AnalyticError(
            f"{what}: {mech.name!r} starts at rest with friction "
            f"({', '.join(f.name for f in eqs.frictions)}); whether it sticks or slides is "
            "decided numerically: use mech.simulate(scene, params)")
    moment, friction = _fix_friction_sign(moment, q, u, direction)
    return _Problem(mech.name, q, u, inertia, moment, start, friction), eqs


# ------------------------------------------------------------------ classification
@dataclass(frozen=True)
class Classification:
    """Which of the five cases of the one-DOF equation of motion a scene falls in.

    ``case`` 1-5; ``inertia_varies`` (``I_red`` a function of the position);
    ``moment_depends_on``: the roles among ``"t"``, ``"phi"``, ``"omega"`` that
    ``M_red`` depends on; ``closed_form``: cases 1-3; ``description``: in words.
    """
    case: int
    inertia_varies: bool
    moment_depends_on: tuple
    closed_form: bool
    description: str

    def __str__(self):
        return self.description


def _classify(problem):
    varies = problem.inertia.has(problem.q)
    roles = tuple(r for r in ("t", "phi", "omega") if problem.moment.has(problem.role(r)))
    if not varies:
        case = {(): 1, ("t",): 2, ("phi",): 2, ("omega",): 2}.get(roles, 4)
    else:
        case = 3 if roles in ((), ("phi",)) else 5
    inertia = (f"I_red a function of the position {problem.q}" if varies
               else "I_red constant")
    moment = ("M_red constant" if not roles else "M_red a function of " + " and ".join(
        f"{_ROLE_WORDS[r]} {problem.role(r)}" for r in roles))
    if len(roles) > 1:
        moment += " (mixed)"
    how = {1: "uniformly accelerated motion, closed form",
           2: "one quadrature, closed form",
           3: "the energy integral, closed form"}.get(
        case, "needs numerical integration (mech.simulate)")
    return Classification(case, varies, roles, case <= 3,
                          f"case {case}: {inertia}, {moment}: {how}")


def classify(mech, scene=None, params=None) -> Classification:
    """Which of the five cases a one-DOF machine (under a scene) falls in.

    Parameters
    ----------
    mech : Mechanism
    scene : Scene, optional
        Selects the effects; its initial speed fixes the sign of Coulomb friction.
    params : dict, optional
        Parameter values (a zero value can remove a dependence).

    Returns
    -------
    Classification

    Examples
    --------
    >>> import sympy as sp, mechdyn as md
    >>> phi = md.coordinate("phi")
    >>> fan = md.Mechanism("fan", [phi])
    >>> _ = fan.link("rotor", J=2, angle=phi)
    >>> _ = fan.load("air", -sp.Symbol("k") * md.speed(phi)**2, along=phi)
    >>> print(md.classify(fan))
    case 2: I_red constant, M_red a function of the speed phidot: one quadrature, closed form
    """
    problem, _ = _problem(mech, scene, params, "classify")
    return _classify(problem)


# ------------------------------------------------------------------ the solution
@dataclass(frozen=True)
class StopPoint:
    """Where a stop condition is met: time ``t``, position ``phi``, speed ``omega``
    (exact sympy numbers where the closed form gives them, floats from quadrature)."""
    t: object
    phi: object
    omega: object
    label: str


@dataclass
class Solution:
    """The closed-form solution of a one-DOF scene.

    ``relations`` maps names such as ``"omega(t)"``, ``"phi(t)"``, ``"t(omega)"``,
    ``"phi(omega)"``, ``"omega(phi)"``, ``"t(phi)"`` (role names: ``phi`` the coordinate,
    ``omega`` its speed) to sympy expressions in the plain symbols; those listed in
    ``quadrature`` hold an unevaluated ``Integral`` and are evaluated by numeric
    quadrature. ``start`` maps ``"t"``, ``"phi"``, ``"omega"`` to the initial values.
    ``stop`` is the first stop condition met (``None`` if none is met
    before the scene's time limit or it has no closed form); ``notes`` say what was done.
    ``sol[name]`` is the expression, ``sol.function(name)`` a vectorized evaluator.
    """
    classification: Classification
    q: sp.Symbol
    u: sp.Symbol
    start: dict
    relations: dict
    quadrature: tuple
    stop: StopPoint | None
    notes: tuple = ()
    _functions: dict = field(default_factory=dict, repr=False)

    def __getitem__(self, name):
        if name not in self.relations:
            raise KeyError(f"no relation {name!r}; this solution has "
                           f"{', '.join(self.relations)}")
        return self.relations[name]

    def function(self, name):
        """A numpy-vectorized evaluator of the relation ``name`` (quadrature where the
        relation holds an integral)."""
        if name not in self._functions:
            variable = self._symbol(name[name.index("(") + 1:-1])
            self._functions[name] = _evaluator(self[name], variable, name)
        return self._functions[name]

    def _symbol(self, role):
        return {"t": t, "phi": self.q, "omega": self.u}[role]

    def _lhs(self, name, printer):
        dependent, variable = name[:-1].split("(")
        return f"{printer(self._symbol(dependent))}({printer(self._symbol(variable))})"

    def latex(self) -> str:
        """The classification as a comment and the relations as an ``align*`` block
        (written for reading: see :func:`presentable`; stop values with their number)."""
        rows = [f"{self._lhs(n, sp.latex)} &= {sp.latex(presentable(e))}"
                for n, e in self.relations.items()]
        if self.stop is not None:
            rows.append(f"t_{{\\mathrm{{stop}}}} &= {_shown(self.stop.t, sp.latex)}, \\quad "
                        f"{sp.latex(self.q)}_{{\\mathrm{{stop}}}} = "
                        f"{_shown(self.stop.phi, sp.latex)}")
        return "\n".join([f"% {self.classification}", "\\begin{align*}",
                          " \\\\\n".join(rows), "\\end{align*}"])

    def __str__(self):
        lines = [str(self.classification)]
        lines += [f"  {self._lhs(n, str)} = {sp.sstr(presentable(e))}"
                  for n, e in self.relations.items()]
        if self.stop is not None:
            s = self.stop
            lines.append(f"  stop ({s.label}): t = {_shown(s.t)}, {self.q} = {_shown(s.phi)}, "
                         f"{self.u} = {_shown(s.omega)}")
        lines += [f"  note: {n}" for n in self.notes]
        return "\n".join(lines)


def _shown(value, printer=str):
    """An exact value with its decimal value when it is not a plain number; the decimal
    alone when the exact form is not readable (see :func:`presentable`)."""
    value = sp.sympify(value)
    if value.is_Float or not value.is_number or (value.is_Rational and readable(value)):
        return printer(value)
    number = f"{float(value):.12g}"
    if not readable(value):
        return number
    return f"{printer(value)} (= {number})" if printer is str else \
        f"{printer(value)} \\approx {number}"


def _evaluator(expr, variable, name):
    missing = expr.free_symbols - {variable} - _bound_symbols(expr)
    if missing:
        def unavailable(x):
            raise ParameterError(f"{name}: give values of {sorted(map(str, missing))} "
                                 "to evaluate it numerically")
        return unavailable
    integrals = expr.atoms(sp.Integral)
    if not integrals:
        f = sp.lambdify(variable, presentable(expr, 17), "numpy", cse=True)  # no huge ints
        return lambda x: np.broadcast_to(f(np.asarray(x, dtype=float)), np.shape(x)) * 1.0
    (integral,) = integrals
    (s, lower, _), = integral.limits
    integrand = sp.lambdify(s, integral.function, "math")
    offset, a = float(expr - integral), float(lower)

    def one(x):
        try:
            return offset + quad(integrand, a, x, **_QUAD)[0]
        except (ValueError, ZeroDivisionError):   # the motion does not reach x
            return math.nan
    return np.vectorize(one, otypes=[float])


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


# ---------------------------------------------------------------------- stopping
def _conditions(p, eqs, scene, subs):
    """(target expression that is zero at the stop, label) for each stop condition."""
    out = []
    for condition in (scene.until if scene is not None else ()):
        target = eqs.to_plain(condition.expression) - condition.value
        out.append((_exact(target.xreplace(subs)), repr(condition)))
    if p.friction:
        out.append((p.u, "friction: sliding ends (omega = 0)"))
    return out


def _stop(p, relations, quadrature, conditions, time_limit):
    """The earliest stop among ``conditions`` reachable in closed form, and notes."""
    closed = {n: e for n, e in relations.items() if n not in quadrature}
    points, notes = [], []
    for target, label in conditions:
        point, reason = _solve_condition(p, relations, closed, target, label)
        if point is not None and _before(point.t, time_limit) is False:
            point, reason = None, f"reached only after the time limit {time_limit}"
        if point is None:
            notes.append(f"{label}: {reason}")
        else:
            points.append(point)
    return _earliest(points), tuple(notes)


def _earliest(points):
    if len(points) <= 1:
        return points[0] if points else None
    try:
        return min(points, key=lambda pt: float(pt.t))
    except TypeError:   # symbolic times cannot be ordered
        return None


def _solve_condition(p, relations, closed, target, label):
    """(StopPoint or None, reason) for the condition ``target = 0``."""
    for variable in ("t", "phi", "omega"):
        others = [r for r in ("t", "phi", "omega") if r != variable]
        if not all(f"{r}({variable})" in relations for r in others):
            continue
        inside = [r for r in others if target.has(p.role(r))]
        if not all(f"{r}({variable})" in closed for r in inside):
            continue
        expr = _zero_factor(target.subs({p.role(r): closed[f"{r}({variable})"]
                                         for r in inside}), p.role(variable))
        if not _solvable(expr, p.role(variable)):
            break
        try:
            roots = sp.solve(expr, p.role(variable))
        except NotImplementedError:
            break
        points = [_point(p, relations, variable, root, label) for root in roots]
        point = _earliest([pt for pt in points if pt is not None])
        return point, "not reached by the motion" if point is None else ""
    return None, "no closed-form solution of the stop condition"


def _point(p, relations, variable, root, label):
    """The stop point at ``root`` of ``variable``, or None if the motion never gets there."""
    if root.is_real is False or (root.is_number and abs(complex(root).imag) > 1e-12):
        return None
    x = p.role(variable)
    if not _reachable(p, relations, variable, root):
        return None
    values = {variable: root}
    for role in ("t", "phi", "omega"):
        if role != variable:
            expr = relations[f"{role}({variable})"]
            values[role] = (sp.Float(_evaluator(expr, x, role)(float(root)), 17)
                            if expr.has(sp.Integral) else sp.expand(expr.subs(x, root)))
    elapsed = values["t"] - p.start["t"]
    if elapsed.is_number:
        late = complex(elapsed)
        if not (math.isfinite(late.real) and late.real > 0 and abs(late.imag) < 1e-12):
            return None
    elif elapsed.is_positive is False:
        return None
    return StopPoint(values["t"], values["phi"], values["omega"], label)


def _reachable(p, relations, variable, root):
    """Whether the motion gets from the start to ``root`` (sampled where numeric): the
    speed cannot pass a speed where M_red(omega) vanishes, the position cannot pass a
    turning point of omega(phi)."""
    if variable == "t":
        return True
    watched = p.moment if variable == "omega" else relations["omega(phi)"]
    x = p.role(variable)
    if watched.free_symbols - {x} or not root.is_number:
        return True
    f = sp.lambdify(x, watched, "numpy")
    inside = np.linspace(float(p.start[variable]), float(root), 1001)
    if variable == "phi":
        inside = inside[1:-1]          # omega may vanish at the start and at the stop
    with np.errstate(invalid="ignore"):
        values = np.broadcast_to(f(inside), inside.shape)
    signs = np.sign(values)
    return bool(np.all(np.isfinite(values)) and np.all(signs == signs[0]) and signs[0] != 0)


def _before(time, limit):
    try:
        return float(time) <= limit
    except TypeError:
        return None


def closed_form(mech, scene, params=None) -> Solution:
    """The closed-form solution of a one-DOF machine under a scene (cases 1-3).

    Case 1 and case 2 with ``M(t)`` give ``omega(t)``, ``phi(t)``; case 2 with
    ``M(omega)`` gives ``t(omega)``, ``phi(omega)`` (and ``omega(t)``, ``phi(t)`` when
    sympy inverts ``t(omega)``; numeric quadrature where it finds no antiderivative, said
    so in ``quadrature`` and ``notes``); case 2 with ``M(phi)`` and case 3 give
    ``omega(phi)`` from the energy integral and ``t(phi)`` by quadrature. The stop of
    the scene's conditions (and of sliding friction at ``omega = 0``) is solved for.

    Parameters
    ----------
    mech : Mechanism
        One degree of freedom.
    scene : Scene
        Effects, initial state, stop conditions, time limit.
    params : dict, optional
        Parameter values; floats become exact rationals. Missing ones stay symbolic.

    Returns
    -------
    Solution

    Raises
    ------
    AnalyticError
        Several coordinates, case 4 or 5, or an integral sympy cannot do.

    Examples
    --------
    >>> import mechdyn as md
    >>> phi = md.coordinate("phi")
    >>> disc = md.Mechanism("disc", [phi])
    >>> _ = disc.link("disc", J=2, angle=phi)
    >>> _ = disc.load("drive", 4 * md.t, along=phi)
    >>> sol = md.closed_form(disc, md.Scene("spin", initial={phi: 0, md.speed(phi): 1},
    ...                                     t_end=3))
    >>> sol["phi(t)"]
    t**3/3 + t
    """
    if scene is None:
        raise SceneError("closed_form needs a scene (its initial state and stop conditions)")
    problem, eqs = _problem(mech, scene, params, "closed_form")
    classification = _classify(problem)
    if not classification.closed_form:
        raise AnalyticError(
            f"{mech.name!r}, scene {scene.name!r}: {classification.description}; there is "
            "no closed form. Use mech.simulate(scene, params)")
    roles = classification.moment_depends_on
    if classification.case == 3 or roles == ("phi",):
        relations, quadrature, notes = _angle_path(problem)
    elif roles == ("omega",):
        relations, quadrature, notes = _speed_path(problem)
    else:
        relations, quadrature, notes = _time_path(problem)
    conditions = _conditions(problem, eqs, scene, _substitution(mech, scene, params))
    stop, stop_notes = _stop(problem, relations, quadrature, conditions, scene.time_limit)
    if problem.friction:
        notes += ("friction sign taken from the initial speed; valid while sliding",)
    return Solution(classification, problem.q, problem.u, problem.start, relations,
                    quadrature, stop, notes + stop_notes)


# ------------------------------------------------------------------ inverse dynamics
@dataclass(frozen=True)
class Motion:
    """A prescribed motion: the law ``phi(t)`` (an expression of ``md.t`` from t = 0),
    the sense of motion ``direction`` (+1 or -1, fixes the sign of Coulomb friction) and
    the time ``window`` its mean, peak and RMS are taken over (None: no statistics)."""
    law: sp.Expr
    direction: int = 1
    window: object = None


def uniform_rotation(omega, phi0=0, cycle=2 * sp.pi) -> Motion:
    """Rotation at the constant speed ``omega``; statistics over one ``cycle`` of the
    angle (default a revolution, the time ``cycle / omega``).

    >>> uniform_rotation(10).law
    10*t
    """
    omega = as_expression(omega, "uniform_rotation: omega")
    direction = -1 if omega.is_negative else 1
    return Motion(as_expression(phi0, "phi0") + omega * t, direction, cycle / abs(omega))


def uniform_acceleration(eps, omega0=0, phi0=0, duration=None) -> Motion:
    """Constant acceleration ``eps`` from the speed ``omega0``; statistics over
    ``duration`` when given.

    >>> uniform_acceleration(4, omega0=1).law
    2*t**2 + t
    """
    eps = as_expression(eps, "uniform_acceleration: eps")
    omega0 = as_expression(omega0, "uniform_acceleration: omega0")
    first = omega0 if omega0 != 0 else eps
    return Motion(as_expression(phi0, "phi0") + omega0 * t + eps * t**2 / 2,
                  -1 if first.is_negative else 1, duration)


@dataclass
class DrivingMoment:
    """The moment that drives a one-DOF machine through a prescribed motion.

    ``expression``: ``M_drive = I_red eps + 1/2 I_red' omega^2 - M_red,other`` in the
    position (and the speed where it varies; constant speed and acceleration substituted);
    ``of_time``: along the motion, a function of ``t``; ``mean``, ``peak`` (largest
    magnitude) and ``rms`` over the motion's window (numbers; they need every parameter).
    """
    expression: sp.Expr
    of_time: sp.Expr
    window: object

    def latex(self) -> str:
        """``M_{drive} = ...``."""
        return "M_{\\mathrm{drive}} = " + sp.latex(self.expression)

    def _numeric(self):
        missing = self.of_time.free_symbols - {t}
        if missing or self.window is None or not sp.sympify(self.window).is_number:
            why = (f"give values of {sorted(map(str, missing))}" if missing
                   else "the motion has no numeric time window (give duration=)")
            raise ParameterError(f"driving moment statistics: {why}")
        return sp.lambdify(t, self.of_time, "math"), float(self.window)

    @property
    def mean(self) -> float:
        f, window = self._numeric()
        return quad(f, 0.0, window, **_STATS_QUAD)[0] / window

    @property
    def rms(self) -> float:
        f, window = self._numeric()
        return math.sqrt(quad(lambda x: f(x) ** 2, 0.0, window, **_STATS_QUAD)[0] / window)

    @property
    def peak(self) -> float:
        f, window = self._numeric()
        grid = np.linspace(0.0, window, 2001)
        values = np.abs([f(x) for x in grid])
        i = int(np.argmax(values))
        lo, hi = grid[max(i - 1, 0)], grid[min(i + 1, grid.size - 1)]
        best = minimize_scalar(lambda x: -abs(f(x)), bounds=(lo, hi), method="bounded",
                               options={"xatol": 1e-12 * window})
        return max(values[i], -best.fun)


def driving_moment(mech, motion, params=None, scene=None, drive=None,
                   guess=None) -> DrivingMoment:
    """The driving moment a one-DOF machine needs to follow ``motion`` (inverse dynamics).

    ``M_drive = I_red(phi) eps + 1/2 I_red'(phi) omega^2 - M_red,other(phi, omega, t)``,
    where ``M_red,other`` is the reduced moment of every load the scene includes except
    ``drive``.

    Parameters
    ----------
    mech : Mechanism
        One degree of freedom.
    motion : Motion
        From :func:`uniform_rotation`, :func:`uniform_acceleration` or ``Motion(law)``.
    params : dict, optional
        Parameter values (floats become exact rationals); missing ones stay symbolic.
    scene : Scene, optional
        Selects the loads (all when None).
    drive : str, optional
        Name or tag of the drive loads to leave out of ``M_red,other``.
    guess : dict, optional
        With closed loops: the dependent coordinates near the assembly wanted (see
        :mod:`mechdyn.analyse.linkage_drive`; the statistics are evaluated numerically there).

    Returns
    -------
    DrivingMoment

    Examples
    --------
    >>> import sympy as sp, mechdyn as md
    >>> phi = md.coordinate("phi")
    >>> disc = md.Mechanism("disc", [phi])
    >>> _ = disc.link("disc", J=2, angle=phi)
    >>> _ = disc.load("drive", sp.Symbol("M"), along=phi)
    >>> _ = disc.load("brake", -3, along=phi)
    >>> needed = md.driving_moment(disc, md.uniform_acceleration(5, duration=1), drive="drive")
    >>> needed.expression, round(needed.rms, 9)
    (13, 13.0)
    """
    if not isinstance(motion, Motion):
        raise AnalyticError(f"driving_moment: motion must be a md.Motion (from "
                            f"md.uniform_rotation or md.uniform_acceleration), got {motion!r}")
    if mech.constraints:
        raise AnalyticError(f"driving_moment: {mech.name!r} has closed loops; their driving "
                            "moment needs the position analysis: use md.driving_moment")
    eqs, subs, inertia, other = _reduced(mech, scene, params, "driving_moment", drive)
    q, u, a = eqs.q[0], eqs.u[0], eqs.a[0]
    other, _ = _fix_friction_sign(other, q, u, motion.direction)
    needed = inertia * a + sp.diff(inertia, q) / 2 * u**2 - other
    law = _exact(motion.law.xreplace(subs))
    speed, acceleration = sp.diff(law, t), sp.diff(law, t, 2)
    constants = {s: v for s, v in ((u, speed), (a, acceleration)) if not v.has(t)}
    expression = sp.simplify(needed.subs(constants).subs(a, acceleration))
    of_time = sp.simplify(needed.subs({q: law, u: speed, a: acceleration}))
    window = None if motion.window is None else _exact(sp.sympify(motion.window).xreplace(subs))
    return DrivingMoment(expression, of_time, window)

"""Closed-form motion of one-DOF machines (the five cases of
:func:`~mechdyn.derive.analytic.classify`): stop points and conditions on the paths of
:mod:`mechdyn.derive.paths`, and the printed :class:`Solution`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
import numpy as np
import sympy as sp
from scipy.integrate import quad
from mechdyn.errors import ParameterError, SceneError
from mechdyn.derive.latex import presentable, readable
from mechdyn.declare.parameters import exact_floats as _exact
from mechdyn.symbols import t
from mechdyn.derive.analytic import (AnalyticError, Classification, _QUAD, _classify, _problem, _substitution)
from mechdyn.derive.paths import (_angle_path, _bound_symbols, _solvable, _speed_path, _time_path, _zero_factor)

__all__ = ["StopPoint", "Solution", "closed_form"]


# ------------------------------------------------------------------ the solution
@dataclass(frozen=True)
class StopPoint:
    """Where a stop condition is met: time ``t``, position ``phi``, speed ``omega``
    (exact sympy numbers where the closed form gives them, floats from quadrature).

    Examples
    --------
    >>> import mechdyn as md
    >>> phi = md.coordinate("phi")
    >>> brake = md.Mechanism("brake", [phi])
    >>> _ = brake.link("disc", J=0.4, angle=phi)
    >>> _ = brake.friction("shoe", 0.8, along=phi)
    >>> braking = md.Scene("braking", initial={phi: 0, md.speed(phi): 100},
    ...                    until=md.stopped(phi))
    >>> sol = md.closed_form(brake, braking)
    >>> sol.stop
    StopPoint(t=50, phi=2500, omega=0, label='stopped(phi)')
    """
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

    Examples
    --------
    >>> import mechdyn as md
    >>> phi = md.coordinate("phi")
    >>> brake = md.Mechanism("brake", [phi])
    >>> _ = brake.link("disc", J=0.4, angle=phi)
    >>> _ = brake.friction("shoe", 0.8, along=phi)
    >>> braking = md.Scene("braking", initial={phi: 0, md.speed(phi): 100},
    ...                    until=md.stopped(phi))
    >>> sol = md.closed_form(brake, braking)
    >>> sol["omega(t)"], sol["phi(t)"]
    (100 - 2*t, -t**2 + 100*t)
    >>> sol.function("phi(t)")([10.0, 50.0])
    array([ 900., 2500.])
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

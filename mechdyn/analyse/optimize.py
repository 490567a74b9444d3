"""Sizing by optimisation: parameters chosen within bounds to minimise (or maximise) a
measure or an expression of parameters subject to constraints on measures, by scipy's
SLSQP with the exact gradients of :func:`mechdyn.analyse.sensitivities.sensitivities`.

The variables are scaled to ``[0, 1]`` on their bounds and each constraint by its
limit. At the optimum the active constraints (within 1e-6 of their limit, relative)
get Lagrange multipliers from the KKT conditions, ``grad F + sum lambda_i grad c_i = 0``
with ``c_i = value - limit`` for ``<=`` (``limit - value`` for ``>=``) and the active
bounds among them, solved by non-negative least squares: ``lambda_i`` is what the
constraint costs, the objective's decrease per unit the limit is relaxed.

>>> import mechdyn as md
>>> brake = md.load_model("models/shoe_brake.py")
>>> best = md.optimize(brake.mechanism, brake.scenes["braking"], brake.params,
...                    vary={"P": (1, 100)}, minimize="P", subject_to=["t_end <= 25 s"])
>>> round(best.values["P"], 6)          # t = I w0 / (2 f P R) = 25 s at P = 40 N
40.0
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import minimize as scipy_minimize, nnls

from mechdyn.declare.parameters import ParameterSet
from mechdyn.errors import MechdynError, did_you_mean
from mechdyn.tabular import Table
from mechdyn.units import to_si
from mechdyn.analyse.design_goals import OptimizeError, read_constraint, read_goal
from mechdyn.analyse.sensitivities import measure_unit, parameter_symbols, sensitivities

__all__ = ["optimize", "Optimum", "OptimizeError"]

_ACTIVE = 1e-6


@dataclass(frozen=True)
class Optimum:
    """The optimum: ``values`` (varied parameter -> value), ``objective`` (its value,
    ``goal`` its text), ``measures`` (every measure used, at the optimum),
    ``constraints`` (rows: text, value, limit, active, multiplier), ``bounds`` (active
    bounds: parameter -> (side, multiplier)), ``simulations`` (runs of the scene or of
    its steady running, each with its sensitivities),
    ``iterations``, ``success``, ``message``, ``kkt_residual`` (``|grad L| / |grad F|``).

    Examples
    --------
    >>> import mechdyn as md
    >>> brake = md.load_model("shoe_brake")
    >>> best = md.optimize(brake.mechanism, brake.scenes["braking"], brake.params,
    ...                    vary={"P": (1, 100)}, minimize="P", subject_to=["t_end <= 25 s"])
    >>> row = best.constraints[0]
    >>> row["active"], round(row["value"], 6)      # the time limit holds the force up
    (True, 25.0)
    """
    values: dict
    objective: float
    goal: str
    measures: dict
    constraints: list
    bounds: dict
    simulations: int
    iterations: int
    success: bool
    message: str
    kkt_residual: float
    units: dict = field(default_factory=dict)

    def table(self) -> Table:
        rows = [[c["text"], c["value"], c["limit"], "yes" if c["active"] else "no",
                 c["multiplier"]] for c in self.constraints]
        rows += [[f"{name} {side} bound", self.values[name], None, "yes", lam]
                 for name, (side, lam) in self.bounds.items()]
        return Table(["constraint", "value", "limit", "active", "multiplier"], rows)

    def summary(self) -> str:
        chosen = ", ".join(f"{k} = {v:.8g} {self.units.get(k, '')}".rstrip()
                           for k, v in self.values.items())
        lines = [f"optimum: {chosen}", f"  {self.goal} = {self.objective:.8g} "
                 f"({'converged' if self.success else 'NOT converged: ' + self.message}; "
                 f"{self.iterations} iterations, {self.simulations} simulations, "
                 f"KKT residual {self.kkt_residual:.2g})"]
        if self.constraints or self.bounds:
            lines.append(self.table().text())
        return "\n".join(lines)

    __str__ = summary

    def __repr__(self) -> str:
        chosen = ", ".join(f"{k}={v:.6g}" for k, v in self.values.items())
        return f"<Optimum {chosen}: {self.goal} = {self.objective:.6g}>"

    def _repr_html_(self) -> str:
        return self.table()._repr_html_()


def optimize(mechanism, scene, params, vary, minimize=None, subject_to=(), *, maximize=None,
             cycle=None, speed_guess=None, max_iterations=100, tolerance=1e-10) -> Optimum:
    """Choose the parameters ``vary`` ({parameter: (low, high)}) to minimise
    ``minimize`` (or maximise ``maximize``): a measure's name or an expression of
    parameters; ``subject_to``: constraints ``"fluctuation <= 0.05"``, ``"t_end <= 5 s"``,
    ``"P + Q <= 2 kN"``. Starts from ``params``' values (clipped into the bounds).

    Returns
    -------
    Optimum

    Raises
    ------
    OptimizeError
        Bounds, goals or parameters that cannot be used, or a problem not solved.

    Examples
    --------
    The least shoe force that stops the brake within 25 s, ``t = I omega_0 / (2 f P R)``:

    >>> import mechdyn as md
    >>> brake = md.load_model("shoe_brake")
    >>> best = md.optimize(brake.mechanism, brake.scenes["braking"], brake.params,
    ...                    vary={"P": (1, 100)}, minimize="P", subject_to=["t_end <= 25 s"])
    >>> round(best.values["P"], 6), best.success
    (40.0, True)
    """
    if (minimize is None) == (maximize is None):
        raise OptimizeError("optimize: give one of minimize= or maximize=")
    values = ParameterSet(params, mechanism=mechanism, scene=scene)
    eqs = mechanism.equations(scene)
    symbols = parameter_symbols(eqs, scene)
    units = dict(mechanism.parameter_units or {})
    names, low, high = _bounds(vary, symbols, units)
    sense = 1.0 if maximize is None else -1.0
    objective = read_goal(minimize if maximize is None else maximize, symbols)
    constraints = [read_constraint(text, symbols, units | _measure_units(eqs))
                   for text in ([subject_to] if isinstance(subject_to, str) else subject_to)]
    goals = [objective] + [c.goal for c in constraints]
    measures = list(dict.fromkeys(g.measure for g in goals if g.measure))
    options = {} if cycle is None else {"cycle": cycle}
    counts = {"evaluations": 0, "simulations": 0}
    memo = {}

    def evaluate(x):
        key = tuple(np.round(x, 15))
        if key not in memo:
            point = dict(zip(names, x))
            found = {}
            if measures:
                try:
                    s = sensitivities(mechanism, scene, {**values.numbers, **point}, names,
                                      measures, speed_guess=speed_guess, **options)
                except MechdynError as error:
                    chosen = ", ".join(f"{k} = {v:.8g}" for k, v in point.items())
                    raise OptimizeError(f"optimize: the run at {chosen} failed after "
                                        f"{counts['evaluations']} points: {error}") from error
                counts["simulations"] += s.runs
                found = {m: (s.results[m], s.gradients[i]) for i, m in enumerate(measures)}
            counts["evaluations"] += 1
            memo.clear()
            memo[key] = (point, found)
        point, found = memo[key]
        out = []
        for goal in goals:
            if goal.measure:
                out.append(found[goal.measure])
            else:
                numbers = {symbols[n]: v for n, v in {**values.numbers, **point}.items()
                           if n in symbols}
                out.append((float(goal.expression.xreplace(numbers)),
                            np.array([float(goal.expression.diff(symbols[n]).xreplace(numbers))
                                      for n in names])))
        return out

    span = high - low
    start = np.clip([values.numbers[n] for n in names], low, high)
    scale = abs(evaluate(start)[0][0]) or 1.0
    limits = [abs(c.limit) or 1.0 for c in constraints]

    def physical(xi):
        return low + span * np.asarray(xi, dtype=float)

    def f(xi):
        value, grad = evaluate(physical(xi))[0]
        return sense * value / scale, sense * grad * span / scale

    def constraint(k, sign):
        def c(xi):
            return sign * (constraints[k].limit - evaluate(physical(xi))[k + 1][0]) / limits[k]

        def dc(xi):
            return -sign * evaluate(physical(xi))[k + 1][1] * span / limits[k]
        return c, dc
    scipy_constraints = []
    for k, c in enumerate(constraints):
        fun, jac = constraint(k, -1.0 if c.relation == ">=" else 1.0)
        scipy_constraints.append({"type": "eq" if c.relation == "==" else "ineq",
                                  "fun": fun, "jac": jac})
    result = scipy_minimize(f, (start - low) / span, jac=True, method="SLSQP",
                            bounds=[(0.0, 1.0)] * len(names), constraints=scipy_constraints,
                            options={"maxiter": max_iterations, "ftol": tolerance})
    x = physical(np.clip(result.x, 0.0, 1.0))
    final = evaluate(x)
    return _optimum(names, x, low, high, final, objective, constraints, sense, result,
                    counts, units, eqs)


def _bounds(vary, symbols, units) -> tuple:
    if not isinstance(vary, dict) or not vary:
        raise OptimizeError("optimize: vary= must be a dict {parameter: (low, high)}")
    names, low, high = [], [], []
    for key, bounds in vary.items():
        name = str(key)
        if name not in symbols:
            raise OptimizeError(f"optimize: {name!r} is not a parameter of the scene's "
                                f"equations{did_you_mean(name, list(symbols))}")
        try:
            lo, hi = (to_si(b, units.get(name) or None) if isinstance(b, str) else float(b)
                      for b in bounds)
        except (TypeError, ValueError):
            raise OptimizeError(f"optimize: the bounds of {name} must be (low, high), got "
                                f"{bounds!r}") from None
        if not (np.isfinite(lo) and np.isfinite(hi) and lo < hi):
            raise OptimizeError(f"optimize: the bounds of {name} must be finite with low < "
                                f"high, got ({lo}, {hi})")
        names.append(name)
        low.append(lo)
        high.append(hi)
    return names, np.array(low), np.array(high)


def _measure_units(eqs) -> dict:
    names = ["t_end", "stop_angle", "mean_speed", "fluctuation", "cycle_time"]
    names += [f"final:{s}" for s in eqs.q + eqs.u] + [f"stop_angle:{s}" for s in eqs.q]
    return {n: measure_unit(eqs, n) for n in names}


def _optimum(names, x, low, high, final, objective, constraints, sense, result, counts,
             units, eqs) -> Optimum:
    """Active constraints and bounds, and their multipliers from the KKT conditions."""
    grad_f = sense * final[0][1]
    rows, columns, kinds = [], [], []
    for k, c in enumerate(constraints):
        value, grad = final[k + 1]
        active = c.relation == "==" or abs(value - c.limit) <= _ACTIVE * max(1.0, abs(c.limit))
        rows.append({"text": c.text, "value": value, "limit": c.limit, "active": active,
                     "multiplier": 0.0})
        if active:
            columns.append(grad if c.relation != ">=" else -grad)
            kinds.append(("constraint", k))
    for j, name in enumerate(names):
        tol = _ACTIVE * (high[j] - low[j])
        for side, at, sign in (("lower", low[j], -1.0), ("upper", high[j], 1.0)):
            if abs(x[j] - at) <= tol:
                columns.append(sign * np.eye(len(names))[j])
                kinds.append((side, j))
    bounds, residual = {}, float(np.linalg.norm(grad_f))
    if columns:
        lam, residual = nnls(np.array(columns).T, -grad_f)
        for (kind, index), value in zip(kinds, lam):
            if kind == "constraint":
                rows[index]["multiplier"] = float(value)
            else:
                bounds[names[index]] = (kind, float(value))
    norm = float(np.linalg.norm(grad_f))
    measures = {g.measure: v[0] for g, v in zip([objective] + [c.goal for c in constraints],
                                                 final) if g.measure}
    return Optimum(dict(zip(names, map(float, x))), float(final[0][0]), objective.text,
                   measures, rows, bounds, counts["simulations"], int(result.nit),
                   bool(result.success), str(result.message),
                   float(residual / norm) if norm > 0 else float(residual),
                   {n: units.get(n, "") for n in names})

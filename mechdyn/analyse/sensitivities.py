"""Exact sensitivities of a scene's measures with respect to its parameters.

The forward sensitivity equations (:mod:`mechdyn.derive.sensitivity`) are integrated
together with the motion at the scene's tolerances (DOP853 on the compiled kernels, or
scipy's: :mod:`mechdyn.analyse.sensitivity_run`), from the initial
sensitivities ``dy0/dp`` (initial values may be expressions of parameters). A run that
ends at a stop condition ``g(t, y, p) = 0`` ends at ``t*`` with

    dt*/dp = -(g_y S + g_p) / (g_y f + g_t),   dy(t*)/dp = S(t*) + f(t*) dt*/dp

(the event's own sensitivity, not a difference of runs). Measures of a run: ``t_end``,
``stop_angle`` (the coordinate's travel to a stop condition; ``stop_angle:COORDINATE``
of several), ``final:STATE``.
Measures of steady running (one coordinate, equations free of ``t``, no stop
condition; :func:`mechdyn.analyse.fluctuation.steady_running`): ``mean_speed``
(``cycle / cycle_time``), ``fluctuation`` (``(omega_max - omega_min) / omega_mean``)
and ``cycle_time``.
Their derivatives follow from the fixed point ``omega(phi0 + Phi) = omega0`` by the
implicit function theorem, ``d omega0/dp = w / (1 - v)`` (``v``, ``w``: derivatives of
the cycle's end speed by ``omega0`` and ``p``), and at the extremes by the envelope
argument: ``d omega_max/dp`` is the speed's partial derivative at the argmax.

Sliding friction that reverses (its static peak cannot hold it) jumps the sensitivities
by ``(f- - f+) dt*/dp`` (:mod:`mechdyn.analyse.sensitivity_run`); friction that sticks
before the run ends is refused.

>>> import mechdyn as md
>>> brake = md.load_model("models/shoe_brake.py")
>>> s = md.sensitivities(brake.mechanism, brake.scenes["braking"], brake.params,
...                      wrt=["I", "P"], measures=["t_end"])
>>> round(s["t_end", "I"], 9), round(s["t_end", "P"], 9)   # t = I w0 / (2 f P R)
(125.0, -2.5)
"""
from __future__ import annotations

import math

import numpy as np
import sympy as sp
from scipy.integrate import solve_ivp
from scipy.optimize import minimize_scalar

from mechdyn.compile.sensitivity_code import CycleSystem, ForwardSystem, stop_function
from mechdyn.declare.parameters import ParameterSet
from mechdyn.derive.sensitivity import (cycle_equations, forward_equations,
                                        stop_derivatives)
from mechdyn.errors import SceneError, SimulationError, did_you_mean
from mechdyn.symbols import t
from mechdyn.analyse.measures import STEADY_MEASURES
from mechdyn.analyse.sensitivity_result import Sensitivities
from mechdyn.analyse.sensitivity_run import SensitivityError, integrate

__all__ = ["sensitivities", "SensitivityError", "RUN_MEASURES", "CYCLE_MEASURES",
           "measure_unit", "parameter_symbols"]

RUN_MEASURES = ("t_end", "stop_angle")
CYCLE_MEASURES = STEADY_MEASURES        # mean_speed, fluctuation, cycle_time
_CYCLE_RTOL, _CYCLE_ATOL, _GRID, _POLISH = 1e-12, 1e-13, 4001, 4


def sensitivities(mechanism, scene, params, wrt, measures=("t_end",), *, cycle=2 * math.pi,
                  speed_guess=None, backend="auto") -> Sensitivities:
    """Derivatives of ``measures`` with respect to the parameters ``wrt``.

    Parameters
    ----------
    mechanism, scene, params
        As for ``mechanism.simulate``.
    wrt : list
        Parameters (symbols or names) to differentiate for.
    measures : list of str
        ``t_end``, ``stop_angle``, ``final:STATE`` (of a run), ``mean_speed``,
        ``fluctuation`` (of steady running over ``cycle``, from ``speed_guess``).
    backend : str
        ``"auto"``: a run on the compiled kernels where numba is importable (its
        functions compiled once per equations and parameters, about a second);
        ``"scipy"``: lambdified functions on scipy's DOP853.

    Returns
    -------
    Sensitivities

    Raises
    ------
    SensitivityError
        An unknown measure or parameter, or a run that changes mode (friction that
        sticks before the end, stops, loops).

    Examples
    --------
    The shoe brake stops after ``t = I omega_0 / (2 f P R)``:

    >>> import mechdyn as md
    >>> brake = md.load_model("shoe_brake")
    >>> s = md.sensitivities(brake.mechanism, brake.scenes["braking"], brake.params,
    ...                      wrt=["I", "P"], measures=["t_end"])
    >>> round(s.results["t_end"], 9), s.gradients.round(9)   # dt/dI = t/I, dt/dP = -t/P
    (50.0, array([[125. ,  -2.5]]))
    """
    if backend not in ("auto", "scipy"):
        raise SensitivityError(f"sensitivities: backend must be 'auto' or 'scipy', got "
                               f"{backend!r}")
    values = ParameterSet(params, mechanism=mechanism, scene=scene)
    eqs = mechanism.equations(scene)
    measures = [str(m) for m in ([measures] if isinstance(measures, str) else measures)]
    if not measures:
        raise SensitivityError("sensitivities: no measures asked for")
    state_names = [str(s) for s in eqs.q + eqs.u]
    for m in measures:
        if not (m in RUN_MEASURES or m in CYCLE_MEASURES or
                (m.startswith("final:") and m[6:] in state_names) or
                (m.startswith("stop_angle:") and m[11:] in state_names[:eqs.dof])):
            known = list(RUN_MEASURES + CYCLE_MEASURES) + [f"final:{s}" for s in state_names]
            known += [f"stop_angle:{s}" for s in state_names[:eqs.dof]]
            raise SensitivityError(f"sensitivities: no measure {m!r} of scene "
                                   f"{scene.name!r}{did_you_mean(m, known)} (these can be "
                                   f"differentiated: {', '.join(known)})")
    symbols = parameter_symbols(eqs, scene)
    wrt = [_parameter(p, symbols, values) for p in
           ([wrt] if isinstance(wrt, (str, sp.Symbol)) else wrt)]
    if not wrt:
        raise SensitivityError("sensitivities: no parameters (wrt=) to differentiate for")
    replace = _dependent(values, wrt, symbols)
    results, rows, runs = {}, {}, 0
    run = [m for m in measures if m not in CYCLE_MEASURES]
    if run:
        found = _run(mechanism, eqs, scene, values, wrt, replace, run, symbols, backend)
        results.update(found[0])
        rows.update(found[1])
        runs += 1
    if len(run) < len(measures):
        found = _steady(mechanism, scene, values, eqs, wrt, replace, cycle, speed_guess)
        results.update(found[0])
        rows.update(found[1])
        runs += 1
    units = {str(p): (mechanism.parameter_units or {}).get(str(p), "") for p in wrt}
    units.update({m: measure_unit(eqs, m) for m in measures})
    return Sensitivities(f"{eqs.name} — scene {scene.name!r}", tuple(str(p) for p in wrt),
                         {str(p): values.numbers[str(p)] for p in wrt}, tuple(measures),
                         {m: results[m] for m in measures}, [rows[m] for m in measures],
                         units, runs)


# ------------------------------------------------------------------ parameters
def parameter_symbols(eqs, scene) -> dict:
    """Every parameter symbol of the equations and the scene, by name."""
    exprs = [eqs.mass_matrix, eqs.forcing] + [fr.magnitude for fr in eqs.frictions]
    exprs += [sp.sympify(v) for v in scene.initial.values()]
    exprs += [c.expression - c.value for c in scene.until]
    state = set(eqs.q) | set(eqs.u) | set(eqs.a) | {t}
    found = set().union(*(e.free_symbols for e in exprs))
    return {s.name: s for s in found if isinstance(s, sp.Symbol) and s not in state}


def _parameter(p, symbols, values):
    name = str(p)
    if name not in symbols:
        raise SensitivityError(f"sensitivities: {name!r} is not a parameter of the scene's "
                               f"equations{did_you_mean(name, list(symbols))}")
    if name not in values.numbers:
        raise SensitivityError(f"sensitivities: give a value for {name}")
    return symbols[name]


def _dependent(values, wrt, symbols) -> dict:
    """``{symbol: expression of wrt}`` for values given as expressions of ``wrt``."""
    depending = values.depending_on([str(p) for p in wrt])
    if any(str(p) in depending for p in wrt):
        raise SensitivityError("sensitivities: a parameter differentiated for is given as "
                               "an expression of another")
    replace = {}
    for name, expr in depending.items():
        replace[symbols.get(name, sp.Symbol(name))] = expr.xreplace(
            {s: symbols[s.name] for s in expr.free_symbols if s.name in symbols})
    for _ in range(len(replace)):
        replace = {k: v.xreplace(replace) for k, v in replace.items()}
    return replace


def _order(exprs, values, wrt, replace) -> list:
    """The parameter symbols of ``exprs`` with values, ``wrt`` first."""
    known = set().union(*(sp.sympify(e).free_symbols for e in exprs))
    others = sorted((s for s in known if s.name in values.numbers and s not in wrt
                     and s not in replace), key=lambda s: s.name)
    return list(wrt) + others


def _key(wrt, replace, values) -> tuple:
    """What the derived and lambdified functions depend on besides the equations."""
    return (tuple(str(p) for p in wrt), tuple(sorted((str(k), sp.srepr(v))
                                                     for k, v in replace.items())),
            tuple(sorted(values.numbers)))


def _prepared(mechanism, eqs, kind, key, build):
    """``build()`` once per equations, kind and ``key`` (the mechanism's memo is cleared
    by any change to the mechanism)."""
    memo_key = ("sensitivities", kind, id(eqs), key)
    hit = mechanism._memo.get(memo_key)
    if hit is None or hit[0] is not eqs:
        hit = mechanism._memo[memo_key] = (eqs, build())
    return hit[1]


# ------------------------------------------------------------------------- runs
def _kernel(eqs, scene, wrt, signs, replace, order):
    """The compiled functions, or None without numba."""
    try:
        import numba  # noqa: F401
    except ImportError:
        return None
    from mechdyn.compile.sensitivity_kernel import kernel_functions
    watched = [eqs.to_plain(c.expression - c.value).xreplace(replace) for c in scene.until]
    watched += [fr.rate for fr in eqs.frictions]
    return kernel_functions(forward_equations(eqs, wrt, signs, replace), order, watched)


def _run(mechanism, eqs, scene, values, wrt, replace, measures, symbols, backend) -> tuple:
    if eqs.constraints or eqs.contacts or eqs.gears:
        raise SensitivityError(f"scene {scene.name!r}: sensitivities through closed loops, "
                               "stops or lossy gears are not derived (their modes switch)")
    n, k = eqs.dof, len(wrt)
    y0, s0 = _initial(eqs, scene, symbols, replace, wrt, values)
    numbers = {symbols[name]: v for name, v in values.numbers.items() if name in symbols}
    state = dict(zip(list(eqs.q) + list(eqs.u), map(sp.Float, y0)))
    signs = []
    for fr in eqs.frictions:
        rate = float(fr.rate.xreplace(state).xreplace(numbers))
        if rate == 0:
            raise SensitivityError(f"scene {scene.name!r}: friction {fr.name!r} starts "
                                   "stuck (no sliding speed); its sensitivities are not derived")
        signs.append(1 if rate > 0 else -1)
    stops_key = tuple((sp.srepr(c.expression - c.value), c.direction) for c in scene.until)

    def segment(signs):
        """The functions of one friction mode (``signs``), kept in the memo."""
        def build():
            forward = forward_equations(eqs, wrt, signs, replace)
            stops = [stop_derivatives(eqs.to_plain(c.expression - c.value).xreplace(replace),
                                      eqs.q, eqs.u, wrt) for c in scene.until]
            order = _order([forward.mass, forward.forcing, forward.residual_jacobian] +
                           [s[0] for s in stops] + [fr.rate for fr in eqs.frictions],
                           values, wrt, replace)
            rates = [stop_derivatives(fr.rate, eqs.q, eqs.u, wrt) for fr in eqs.frictions]
            return (ForwardSystem(forward, order), order,
                    [stop_function(s, eqs.q, eqs.u, order) for s in stops],
                    [stop_function(r, eqs.q, eqs.u, order) for r in rates])
        key = _key(wrt, replace, values) + (tuple(signs), stops_key)
        prepared = _prepared(mechanism, eqs, "run", key, build)
        compiled = backend != "scipy" and all(abs(x) == 1 for x in signs)
        kernel = None if not compiled else _prepared(
            mechanism, eqs, "kernel", key,
            lambda: _kernel(eqs, scene, wrt, signs, replace, prepared[1]))
        p = np.array([values.numbers[s.name] for s in prepared[1]], dtype=float)
        return prepared, kernel, p
    peaks = [float(sp.sympify(fr.peak).xreplace(numbers)) for fr in eqs.frictions]
    z0 = np.concatenate([y0, s0.ravel()])
    t_end, z_end, i, (system, _, stop_values, _), p = integrate(
        segment, scene, eqs.frictions, peaks, signs, z0)
    dt = np.zeros(k)
    s_end = z_end[2 * n:].reshape(2 * n, k)
    slope = system.rhs(t_end, z_end, p)[:2 * n]
    if i is not None:
        _, g_y, g_t, g_p = stop_values[i](t_end, z_end[:2 * n], p)
        crossing = g_y @ slope + g_t
        if abs(crossing) <= 1e-12 * (np.abs(g_y) @ np.abs(slope) + abs(g_t)):
            raise SensitivityError(f"scene {scene.name!r}: {scene.until[i]!r} is met "
                                   f"tangentially at t = {t_end:.6g} s: its time has no "
                                   "derivative")
        dt = -(g_y @ s_end + g_p[:k]) / crossing
    d_state = s_end + np.outer(slope, dt)
    names = [str(s) for s in eqs.q + eqs.u]
    results, rows = {}, {}
    for m in measures:
        if m == "t_end":
            results[m], rows[m] = float(t_end), dt
        elif m.startswith("stop_angle"):
            if i is None:
                raise SensitivityError(f"{m}: the run did not stop at a stop condition (it "
                                       f"ended at t = {t_end:.6g} s); a stop angle needs until=")
            if m == "stop_angle" and n != 1:
                raise SensitivityError(f"{m}: the run has {n} coordinates; name one: "
                                       f"stop_angle:{names[0]}")
            j = names.index(m[11:]) if ":" in m else 0
            results[m], rows[m] = float(z_end[j] - y0[j]), d_state[j] - s0[j]
        else:
            index = names.index(m[6:])
            results[m], rows[m] = float(z_end[index]), d_state[index]
    return results, rows


def _initial(eqs, scene, symbols, replace, wrt, values) -> tuple:
    """The initial state and its derivatives by ``wrt``."""
    n = eqs.dof
    y0, s0 = np.full(2 * n, np.nan), np.zeros((2 * n, len(wrt)))
    slots = {s: i for i, s in enumerate(list(eqs.q) + list(eqs.u))}
    numbers = {symbols[name]: v for name, v in values.numbers.items() if name in symbols}
    for key, value in scene.initial.items():
        slot = slots.get(eqs.to_plain(key))
        if slot is None:
            continue
        expr = sp.sympify(value)
        expr = expr.xreplace({s: symbols[s.name] for s in expr.free_symbols
                              if s.name in symbols}).xreplace(replace)
        y0[slot] = float(expr.xreplace(numbers))
        s0[slot] = [float(sp.diff(expr, p).xreplace(numbers)) for p in wrt]
    if np.isnan(y0).any():
        missing = [str(s) for s, i in slots.items() if np.isnan(y0[i])]
        raise SceneError(f"scene {scene.name!r}: missing initial values for "
                         f"{', '.join(missing)}")
    return y0, s0


# ---------------------------------------------------------------- steady running
def _steady(mechanism, scene, values, eqs, wrt, replace, cycle, speed_guess) -> tuple:
    from mechdyn.analyse.fluctuation import steady_running
    running = steady_running(mechanism, scene, values, cycle, speed_guess=speed_guess)
    phi0, omega0 = running.initial
    k, cycle = len(wrt), float(cycle)
    def build():
        equations = cycle_equations(eqs, wrt, replace)
        order = _order([equations[0], equations[1], *equations[2]], values, wrt, replace)
        return CycleSystem(equations, eqs.q[0], eqs.u[0], order), order
    system, order = _prepared(mechanism, eqs, "cycle", _key(wrt, replace, values), build)
    p = np.array([values.numbers[s.name] for s in order], dtype=float)
    for _ in range(_POLISH):         # the derivatives amplify an error of omega0
        z0 = np.concatenate([[omega0, 0.0, 1.0, 0.0], np.zeros(2 * k)])
        sol = solve_ivp(system.rhs, (phi0, phi0 + cycle), z0, method="DOP853",
                        rtol=_CYCLE_RTOL, atol=_CYCLE_ATOL * max(1.0, omega0),
                        dense_output=True, args=(p,))
        if sol.status != 0:
            raise SimulationError(f"scene {scene.name!r}: the cycle's sensitivity "
                                  f"integration failed: {sol.message}")
        end = sol.y[:, -1]
        step = (end[0] - omega0) / (1.0 - end[2])
        if abs(step) <= 10 * _CYCLE_RTOL * omega0:
            break
        omega0 += step
    start_slope = end[4:4 + k] / (1.0 - end[2])              # d omega0 / dp
    cycle_time = end[1]
    time_slope = end[4 + k:] + end[3] * start_slope
    mean = cycle / cycle_time
    mean_slope = -cycle / cycle_time ** 2 * time_slope
    extremes = []
    for sign in (-1, 1):                                      # maximum, minimum
        at = _argmin(sol, sign, phi0, cycle)
        z = sol.sol(at)
        extremes.append((z[0], z[4:4 + k] + z[2] * start_slope))
    (high, high_slope), (low, low_slope) = extremes
    delta = (high - low) / mean
    delta_slope = (high_slope - low_slope) / mean - delta / mean * mean_slope
    return ({"mean_speed": float(mean), "fluctuation": float(delta),
             "cycle_time": float(cycle_time)},
            {"mean_speed": mean_slope, "fluctuation": delta_slope, "cycle_time": time_slope})


def _argmin(sol, sign, start, cycle) -> float:
    """Where ``sign * omega`` is least over the cycle (grid, then polished)."""
    grid = np.linspace(start, start + cycle, _GRID)
    values = sign * sol.sol(grid)[0]
    j = int(np.argmin(values))
    lo, hi = grid[max(j - 1, 0)], grid[min(j + 1, len(grid) - 1)]
    best = minimize_scalar(lambda x: sign * sol.sol(x)[0], bounds=(lo, hi), method="bounded",
                           options={"xatol": 1e-12 * max(1.0, abs(hi))})
    return float(best.x) if best.fun <= values[j] else float(grid[j])


def measure_unit(eqs, measure) -> str:
    """The SI unit of a measure of the equations ``eqs`` ("" where unknown)."""
    coordinate = eqs.coordinate_units.get(eqs.q[0], "rad") if eqs.dof == 1 else ""
    if measure in ("t_end", "cycle_time"):
        return "s"
    if measure == "fluctuation":
        return "1"
    if measure in ("stop_angle", "mean_speed"):
        return coordinate + ("/s" if measure == "mean_speed" else "")
    name = measure.partition(":")[2]
    for q, u in zip(eqs.q, eqs.u):
        unit = eqs.coordinate_units.get(q, "")
        if name == str(q):
            return unit
        if name == str(u):
            return f"{unit}/s"
    return ""

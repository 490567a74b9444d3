"""Generated code for closed loops: ``M a = f + G' lambda`` with ``G a = -bias``.

The right-hand side of a mechanism with loop constraints solves the equations of motion
together with the loops' acceleration constraints (index 1). Written out in scalar code:

    A = M + w G'G   (w = trace M / trace G'G: A is positive definite even where M is
                     singular, e.g. a massless coupler, as long as M is on the loops' motions)
    z = A^-1 f,  Y = A^-1 G',  S = G Y,  S nu = -bias - G z,  a = z + Y nu,
    lambda = nu + w bias

``A`` and ``S`` are factored by unrolled Cholesky (``S`` loses rank where the loops do:
a change point). Also generated: ``multipliers`` (lambda), ``closure`` (g, G, dg/dt and
bias, for assembly and projection), ``linear_terms`` (M, df/dq, df/du, for the method
choice), ``loop_minors`` (the ``m x m`` minors of ``G``: all vanish where the loops
lose rank, and a minor changes sign there, so the driver watches the largest as an
event) and ``drift`` (the largest ``|g|``
and ``|G u + dg/dt|``).

>>> import sympy as sp, mechdyn as md
>>> x, y = md.coordinates("x y")
>>> bead = md.Mechanism("bead on a line", [x, y])
>>> _ = bead.link("bead", m=2, x=x, y=y)
>>> _ = bead.load("push", 4, along=x)
>>> _ = bead.constraint("line", y - x)
>>> compiled = bead.compile(md.Scene("run", initial={x: 0, md.speed(x): 0}, t_end=1))
>>> [round(v, 12) for v in compiled.rhs(0.0, [0.0, 0.0, 0.0, 0.0], compiled.parameter_vector({}))]
[0.0, 0.0, 1.0, 1.0]
>>> [round(v, 12) for v in compiled.multipliers(0.0, [0.0] * 4, [])]   # 2 N pushes y up
[2.0]
"""
from __future__ import annotations

import itertools
import math

import numpy as np
import sympy as sp

from .codegen import function_source
from .errors import SimulationError
from .symbols import t

__all__ = ["LoopSingularError", "loop_sources", "numeric_jacobian", "numeric_minors",
           "loop_solve", "LOOP_MARGIN"]

# Smallest pivot of S, relative to its diagonal, the generated rhs accepts (below it the
# loops have lost rank numerically). Where a watched minor changes sign the driver calls
# the loops singular if every minor is below LOOP_MARGIN times its size at the start.
_PIVOT_FLOOR = 1e-14
LOOP_MARGIN = 1e-6


class LoopSingularError(SimulationError):
    """The loop constraints lost rank (a change point or a locked toggle): the motion of
    the linkage is not determined there. ``loop``: the constraint that became dependent
    on the others; ``time``, ``state``."""

    def __init__(self, loop, t_value, state, detail=""):
        self.loop, self.time, self.state = loop, t_value, list(state)
        super().__init__(f"loop {loop} is singular at t = {t_value:.6g} s{detail}: its "
                         "constraints lose rank there (a change point or toggle position "
                         "where the linkage can move more than one way)")


def loop_sources(eqs, mass, forcing, rename, arguments, parameters, doc) -> dict:
    """Sources of ``rhs``, ``multipliers``, ``closure``, ``loop_minors``, ``drift`` and
    ``jac`` for equations with constraints (``mass``, ``forcing`` already renamed to the
    generated names by ``rename``)."""
    n, m = eqs.dof, len(eqs.constraints)
    grads = [[c.gradient[i].xreplace(rename) for i in range(n)] for c in eqs.constraints]
    bias = [c.bias.xreplace(rename) for c in eqs.constraints]
    rate_t = [sp.diff(c.expression, t).xreplace(rename) for c in eqs.constraints]
    values = [c.expression.xreplace(rename) for c in eqs.constraints]
    labels = [c.name for c in eqs.constraints]
    u_names = arguments[n:]
    if n > 8:
        return _numpy_sources(mass, forcing, grads, bias, rate_t, values, n, m, arguments,
                              parameters, doc, labels)
    names = iter(f"_e{k}" for k in range(10 ** 6))
    lower = {(i, j): (None if mass[i, j] == 0 else next(names))
             for i in range(n) for j in range(i + 1)}
    exprs = [mass[i, j] for (i, j), name in lower.items() if name is not None]
    f = [next(names) for _ in range(n)]
    exprs += list(forcing)
    g = [[None if e == 0 else next(names) for e in row] for row in grads]
    exprs += [e for row in grads for e in row if e != 0]
    b = [next(names) for _ in range(m)]
    exprs += bias
    lines, zero = _factor_lines(n, m, lower, g, f, b, labels)
    a = [f"a{i}" for i in range(n)]
    sources = {
        "rhs": function_source("rhs", arguments, parameters, exprs,
                               f"return [{', '.join(u_names + a)}]", doc, lines),
        "multipliers": function_source("multipliers", arguments, parameters, exprs,
                                       "return [" + ", ".join(
                                           f"nu{k} + w * {b[k]}" for k in range(m)) + "]",
                                       doc, lines),
    }
    sources.update(_closure_sources(grads, values, rate_t, bias, arguments, parameters,
                                    doc, n))
    sources["linear_terms"] = linear_source(mass, forcing, arguments, parameters, doc, n)
    sources["loop_minors"] = _minors_source(grads, arguments, parameters, doc)
    return sources


def _minors_source(grads, arguments, parameters, doc):
    """``loop_minors`` -> every m x m minor of G (symbolic up to C(n, m) = 10 minors,
    numpy beyond)."""
    m, n = len(grads), len(grads[0])
    if math.comb(n, m) > 10:
        flat = [e for row in grads for e in row]
        return function_source("loop_minors", arguments, parameters, flat,
                               "return _numeric_minors([" + "{}, " * len(flat)
                               + f"], {m}, {n})", doc)
    matrix = sp.Matrix(grads)
    minors = [matrix[:, list(columns)].det(method="berkowitz")
              for columns in itertools.combinations(range(n), m)]
    return function_source("loop_minors", arguments, parameters, minors,
                           "return [" + "{}, " * len(minors) + "]", doc)


def numeric_minors(flat, m, n):
    """Every m x m minor of the m x n matrix ``flat``."""
    matrix = np.reshape(flat, (m, n))
    return [float(np.linalg.det(matrix[:, list(c)]))
            for c in itertools.combinations(range(n), m)]


def _factor_lines(n, m, lower, g, f, b, labels):
    """Scalar lines computing ``a`` (and ``nu``, ``w``, pivot ratios ``r``) from the names
    of the mass matrix's lower entries, the forcing, the gradients and the biases."""
    from .compile import _cholesky_lines, _solve_lines
    diagonal = [lower[(i, i)] for i in range(n) if lower[(i, i)] is not None]
    squares = [f"{e} * {e}" for row in g for e in row if e is not None]
    lines = [f"w = ({' + '.join(diagonal) or '0.0'}) / ({' + '.join(squares)})"]
    entries = {}
    for i in range(n):
        for j in range(i + 1):
            products = [f"{row[i]} * {row[j]}" for row in g
                        if row[i] is not None and row[j] is not None]
            if not products and lower[(i, j)] is None:
                entries[(i, j)] = None
                continue
            terms = ([lower[(i, j)]] if lower[(i, j)] is not None else []) + (
                [f"w * ({' + '.join(products)})"] if products else [])
            lines.append(f"A{i}_{j} = {' + '.join(terms)}")
            entries[(i, j)] = f"A{i}_{j}"
    cholesky, zero = _cholesky_lines(n, entries, ["(loop constraints)"] * n)
    lines += cholesky
    lines += _solve_lines(n, f, "z", zero)
    for k in range(m):
        lines += _solve_lines(n, [e or "0.0" for e in g[k]], f"y{k}_", zero)
    for k in range(m):
        for l in range(k + 1):
            products = [f"{g[k][i]} * y{l}_{i}" for i in range(n) if g[k][i] is not None]
            lines.append(f"S{k}_{l} = {' + '.join(products) or '0.0'}")
        products = [f"{g[k][i]} * z{i}" for i in range(n) if g[k][i] is not None]
        lines.append(f"s{k} = -{b[k]} - ({' + '.join(products) or '0.0'})")
    for k in range(m):                      # Cholesky of S with pivot ratios r_k
        for l in range(k):
            acc = " - ".join([f"S{k}_{l}"] + [f"K{k}_{j} * K{l}_{j}" for j in range(l)])
            lines.append(f"K{k}_{l} = ({acc}) / K{l}_{l}")
        acc = " - ".join([f"S{k}_{k}"] + [f"K{k}_{j} * K{k}_{j}" for j in range(k)])
        lines.append(f"P{k} = {acc}")
        lines.append(f"r{k} = P{k} / S{k}_{k} if S{k}_{k} > 0 else 0.0")
        lines.append(f"K{k}_{k} = sqrt(P{k}) if P{k} > 0 else 1e-300")
    for k in range(m):
        lines.append(f"if not r{k} > {_PIVOT_FLOOR!r}: "
                     f"raise LoopSingularError({labels[k]!r}, t, y)")
    for k in range(m):
        acc = " - ".join([f"s{k}"] + [f"K{k}_{j} * v{j}" for j in range(k)])
        lines.append(f"v{k} = ({acc}) / K{k}_{k}")
    for k in reversed(range(m)):
        acc = " - ".join([f"v{k}"] + [f"K{j}_{k} * nu{j}" for j in range(k + 1, m)])
        lines.append(f"nu{k} = ({acc}) / K{k}_{k}")
    for i in range(n):
        terms = [f"y{k}_{i} * nu{k}" for k in range(m)]
        lines.append(f"a{i} = z{i} + {' + '.join(terms)}")
    return lines, zero


def _closure_sources(grads, values, rate_t, bias, arguments, parameters, doc, n):
    """``closure`` -> [g..., G (row by row)..., dg/dt..., bias...] and ``drift`` ->
    [max |g|, max |G u + dg/dt|]."""
    flat = [e for row in grads for e in row]
    closure = function_source("closure", arguments, parameters,
                              values + flat + rate_t + bias,
                              "return [" + "{}, " * (len(values) + len(flat) + 2 * len(bias))
                              + "]", doc)
    u = [sp.Symbol(name) for name in arguments[n:]]
    speeds = [sp.Add(*[gi * ui for gi, ui in zip(row, u)], r) for row, r in zip(grads, rate_t)]
    drift = function_source("drift", arguments, parameters, values + speeds,
                            "return [max(" + ", ".join(f"abs({{{k}}})" for k in range(
                                len(values))) + ", 0.0), max(" + ", ".join(
                                f"abs({{{k + len(values)}}})" for k in range(len(values)))
                            + ", 0.0)]", doc)
    return {"closure": closure, "drift": drift,
            "jac": "def jac(t, y, p):\n    return numeric_jacobian(rhs, t, y, p)\n"}


def linear_source(mass, forcing, arguments, parameters, doc, n):
    """``linear_terms`` -> [M, df/dq, df/du] (each n x n, row by row): the analytic
    linearisation the method choice reduces to the loops' motion (a piecewise load
    makes finite differences of the right-hand side useless there)."""
    q = [sp.Symbol(name) for name in arguments[:n]]
    u = [sp.Symbol(name) for name in arguments[n:]]
    exprs = list(mass) + [sp.diff(forcing[i], v) for v in (*q,) for i in range(n)] \
        + [sp.diff(forcing[i], v) for v in (*u,) for i in range(n)]
    return function_source("linear_terms", arguments, parameters, exprs,
                           "return [" + "{}, " * len(exprs) + "]", doc)


def _numpy_sources(mass, forcing, grads, bias, rate_t, values, n, m, arguments, parameters,
                   doc, labels):
    """Beyond the unrolling limit: the pieces in generated code, the solve in numpy."""
    exprs = list(mass) + list(forcing) + [e for row in grads for e in row] + bias
    call = ("_loop_solve([" + "{}, " * len(exprs) + f"], y, {n}, {m}, t, {labels!r}, "
            "LoopSingularError)")
    sources = {
        "rhs": function_source("rhs", arguments, parameters, exprs,
                               f"return list(y[{n}:]) + list({call}[0])", doc),
        "multipliers": function_source("multipliers", arguments, parameters, exprs,
                                       f"return list({call}[1])", doc),
    }
    sources.update(_closure_sources(grads, values, rate_t, bias, arguments, parameters,
                                    doc, n))
    sources["linear_terms"] = linear_source(mass, forcing, arguments, parameters, doc, n)
    sources["loop_minors"] = _minors_source(grads, arguments, parameters, doc)
    return sources


def loop_solve(flat, y, n, m, t_value, labels, error):
    """``(a, lambda)`` from the flattened ``M``, ``f``, ``G``, ``bias`` (numpy)."""
    flat = np.asarray(flat, dtype=float)
    mass = flat[:n * n].reshape(n, n)
    forcing = flat[n * n:n * n + n]
    grads = flat[n * n + n:n * n + n + m * n].reshape(m, n)
    bias = flat[n * n + n + m * n:]
    w = np.trace(mass) / np.sum(grads * grads)
    augmented = mass + w * grads.T @ grads
    z = np.linalg.solve(augmented, forcing)
    y_cols = np.linalg.solve(augmented, grads.T)
    schur = grads @ y_cols
    try:
        factor = np.linalg.cholesky(schur)
    except np.linalg.LinAlgError:
        raise error(labels[-1], t_value, y) from None
    ratios = np.diag(factor) ** 2 / np.diag(schur)
    k = int(np.argmin(ratios))
    if not ratios[k] > _PIVOT_FLOOR:
        raise error(labels[k], t_value, y)
    nu = np.linalg.solve(schur, -bias - grads @ z)
    return z + y_cols @ nu, nu + w * bias


def numeric_jacobian(rhs, t_value, y, p):
    """Central differences of ``rhs`` (constrained systems have no analytic Jacobian)."""
    y = np.asarray(y, dtype=float)
    columns = []
    for j in range(len(y)):
        h = 1e-7 * max(1.0, abs(y[j]))
        up, down = y.copy(), y.copy()
        up[j] += h
        down[j] -= h
        columns.append((np.asarray(rhs(t_value, up, p)) - np.asarray(rhs(t_value, down, p)))
                       / (2 * h))
    return np.array(columns).T

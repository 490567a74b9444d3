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

import sympy as sp

from mechdyn.compile.loop_numeric import (LOOP_MARGIN, PIVOT_FLOOR, LoopSingularError, loop_solve,
                           numeric_jacobian, numeric_minors)
from mechdyn.compile.mass_solve import _cholesky_lines, _solve_lines
from mechdyn.symbols import t

__all__ = ["LoopSingularError", "loop_sources", "numeric_jacobian", "numeric_minors",
           "loop_solve", "LOOP_MARGIN"]

def loop_sources(eqs, mass, forcing, rename, source, states) -> dict:
    """Sources of ``rhs``, ``jac``, ``multipliers``, ``closure``, ``drift``,
    ``linear_terms`` and ``loop_minors`` for equations with constraints (``mass``,
    ``forcing`` already renamed by ``rename``; ``source(name, exprs, body, lines)`` writes
    one generated function, ``states`` the names of the state's entries)."""
    n, m = eqs.dof, len(eqs.constraints)
    grads = [[c.gradient[i].xreplace(rename) for i in range(n)] for c in eqs.constraints]
    bias = [c.bias.xreplace(rename) for c in eqs.constraints]
    rate_t = [sp.diff(c.expression, t).xreplace(rename) for c in eqs.constraints]
    values = [c.expression.xreplace(rename) for c in eqs.constraints]
    speeds = [f"out[{i}] = {states[n + i]}" for i in range(n)]
    if n > 8:
        sources = _numpy_sources(source, mass, forcing, grads, bias, n, m, speeds)
    else:
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
        lines = _factor_lines(n, m, lower, g, f, b)
        sources = {
            "rhs": source("rhs", exprs, speeds + [f"out[{n + i}] = a{i}" for i in range(n)],
                          lines),
            "multipliers": source("multipliers", exprs,
                                  [f"out[{k}] = nu{k} + w * {b[k]}" for k in range(m)], lines),
        }
    sources["jac"] = ("def jac(t, y, p, out):\n"
                      "    numeric_jacobian(rhs, t, y, p, out)\n")
    sources.update(_closure_sources(source, grads, values, rate_t, bias, states, n))
    sources["linear_terms"] = linear_source(source, mass, forcing, states, n)
    sources["loop_minors"] = _minors_source(source, grads)
    return sources


def _minors_source(source, grads):
    """``loop_minors`` -> every m x m minor of G (symbolic up to C(n, m) = 10 minors,
    numpy beyond)."""
    m, n = len(grads), len(grads[0])
    if math.comb(n, m) > 10:
        flat = [e for row in grads for e in row]
        return source("loop_minors", flat, ["numeric_minors([" + "{}, " * len(flat)
                                            + f"], {m}, {n}, out)"])
    matrix = sp.Matrix(grads)
    minors = [matrix[:, list(columns)].det(method="berkowitz")
              for columns in itertools.combinations(range(n), m)]
    return source("loop_minors", minors, [f"out[{k}] = {{{k}}}" for k in range(len(minors))])


def _factor_lines(n, m, lower, g, f, b):
    """Scalar lines computing ``a`` (and ``nu``, ``w``, pivot ratios ``r``) from the names
    of the mass matrix's lower entries, the forcing, the gradients and the biases. Where
    a pivot of ``S`` vanishes (the loops lose rank) the result is NaN: a solver rejects
    the step, and the driver names the loop (:data:`LOOP_MARGIN`)."""
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
    cholesky, zero = _cholesky_lines(n, entries)
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
        lines.append(f"K{k}_{k} = sqrt(P{k}) if r{k} > {PIVOT_FLOOR!r} else nan")
    for k in range(m):
        acc = " - ".join([f"s{k}"] + [f"K{k}_{j} * v{j}" for j in range(k)])
        lines.append(f"v{k} = ({acc}) / K{k}_{k}")
    for k in reversed(range(m)):
        acc = " - ".join([f"v{k}"] + [f"K{j}_{k} * nu{j}" for j in range(k + 1, m)])
        lines.append(f"nu{k} = ({acc}) / K{k}_{k}")
    for i in range(n):
        terms = [f"y{k}_{i} * nu{k}" for k in range(m)]
        lines.append(f"a{i} = z{i} + {' + '.join(terms)}")
    return lines


def _closure_sources(source, grads, values, rate_t, bias, states, n):
    """``closure`` -> [g..., G (row by row)..., dg/dt..., bias...] and ``drift`` ->
    [max |g|, max |G u + dg/dt|]."""
    flat = [e for row in grads for e in row]
    parts = values + flat + rate_t + bias
    closure = source("closure", parts, [f"out[{k}] = {{{k}}}" for k in range(len(parts))])
    u = [sp.Symbol(name, real=True) for name in states[n:]]
    speeds = [sp.Add(*[gi * ui for gi, ui in zip(row, u)], r) for row, r in zip(grads, rate_t)]
    m = len(values)
    drift = source("drift", values + speeds, [
        "out[0] = max(" + ", ".join(f"abs({{{k}}})" for k in range(m)) + ", 0.0)",
        "out[1] = max(" + ", ".join(f"abs({{{k + m}}})" for k in range(m)) + ", 0.0)"])
    return {"closure": closure, "drift": drift}


def linear_source(source, mass, forcing, states, n):
    """``linear_terms`` -> [M, df/dq, df/du] (each n x n, row by row): the analytic
    linearisation the method choice reduces to the loops' motion (a piecewise load
    makes finite differences of the right-hand side useless there)."""
    q = [sp.Symbol(name, real=True) for name in states[:n]]
    u = [sp.Symbol(name, real=True) for name in states[n:]]
    exprs = list(mass) + [sp.diff(forcing[i], v) for v in (*q,) for i in range(n)] \
        + [sp.diff(forcing[i], v) for v in (*u,) for i in range(n)]
    return source("linear_terms", exprs, [f"out[{k}] = {{{k}}}" for k in range(len(exprs))])


def _numpy_sources(source, mass, forcing, grads, bias, n, m, speeds):
    """Beyond the unrolling limit: the pieces in generated code, the solve in numpy."""
    exprs = list(mass) + list(forcing) + [e for row in grads for e in row] + bias
    call = "loop_solve([" + "{}, " * len(exprs) + f"], {n}, {m}, out, "
    return {"rhs": source("rhs", exprs, speeds + [call + f"{n}, 0)"]),
            "multipliers": source("multipliers", exprs, [call + "0, 1)"])}

"""Code for ``M a = f``: the lines of an unrolled Cholesky factorisation and solve (NaN
where ``M`` is not positive definite, so a solver rejects the step), and the sources of
``rhs`` and its analytic Jacobian built on them (see :mod:`mechdyn.compile.generate`).

Up to ``UNROLLED_LIMIT`` coordinates the factorisation is unrolled in scalar code. Beyond
it the generated code writes the structurally non-zero entries of ``M`` into its lower
band (the half-bandwidth read from the derived matrix: 1 for a chain, ``n - 1`` dense)
and factors it with :mod:`mechdyn.compile.band_linalg` (compiled: ``n bw^2`` work, not
``n^3``); a diagonal ``M`` is divided, whatever its size. Only non-zero terms are
generated, so the code grows with the number of non-zero entries, not with ``n^2``.

A mass matrix of the parameters alone (neither coordinates nor time: :func:`is_constant`)
is factored once per parameter vector by the generated ``mass_factor`` (its entries are
appended to ``p`` at ``factor_at``); ``rhs`` and ``jac`` then only solve with it.

>>> import sympy as sp
>>> q = sp.symbols("q0:12")
>>> mass = sp.diag(*[2 + sp.cos(x) for x in q]) + sp.Matrix(12, 12, lambda i, j:
...     1 if abs(i - j) == 1 else 0)
>>> half_bandwidth(mass)
1
"""
from __future__ import annotations

import re

import sympy as sp


__all__ = ["UNROLLED_LIMIT", "MASS_FLOOR", "half_bandwidth", "is_constant",
           "jacobian_pattern", "mass_margin_event"]

UNROLLED_LIMIT = 8          # DOF up to which the Cholesky solve is unrolled in code
MASS_FLOOR = 1e-10          # det M / prod M_ii below which the accelerations keep only
                            # about six digits (rounding eps / MASS_FLOOR): singular


# ------------------------------------------------------------ solving M a = f in code
def _cholesky_lines(n, m):
    """Lines factoring ``M = L L'`` (``m[(i, j)]``: names of the lower entries, ``None``
    where structurally zero); a pivot that is not positive becomes NaN. Returns the lines
    and the set of entries of ``L`` that are structurally zero (a diagonal mass matrix
    costs one division each)."""
    lines, zero = [], set()
    for i in range(n):
        for j in range(i):
            products = [f"L{i}_{k} * L{j}_{k}" for k in range(j)
                        if (i, k) not in zero and (j, k) not in zero]
            if m[(i, j)] is None and not products:
                zero.add((i, j))
                continue
            lines.append(f"L{i}_{j} = ({' - '.join([m[(i, j)] or '0.0'] + products)}) / L{j}_{j}")
        products = [f"L{i}_{k} * L{i}_{k}" for k in range(i) if (i, k) not in zero]
        lines.append(f"L{i}_{i} = {' - '.join([m[(i, i)] or '0.0'] + products)}")
        lines.append(f"L{i}_{i} = sqrt(L{i}_{i}) if L{i}_{i} > 0.0 else nan")
    return lines, zero


def _solve_lines(n, rhs, out, zero):
    """Lines solving ``L L' out = rhs`` with the factor of :func:`_cholesky_lines`."""
    lines = []
    for i in range(n):
        terms = [f"L{i}_{k} * {out}z{k}" for k in range(i) if (i, k) not in zero]
        lines.append(f"{out}z{i} = ({' - '.join([rhs[i]] + terms)}) / L{i}_{i}")
    for i in reversed(range(n)):
        terms = [f"L{k}_{i} * {out}{k}" for k in range(i + 1, n) if (k, i) not in zero]
        lines.append(f"{out}{i} = ({' - '.join([f'{out}z{i}'] + terms)}) / L{i}_{i}")
    return lines


def _lower_names(mass, names):
    """Names of the lower entries of ``mass`` (``None`` for structural zeros)."""
    n, nonzero = mass.shape[0], mass.todok()
    return {(i, j): (next(names) if (i, j) in nonzero else None)
            for i in range(n) for j in range(i + 1)}


def _rhs_source(source, mass, forcing, n, states, coordinates, factor_at=None):
    """dy/dt = [u, M^-1 f] with an unrolled Cholesky solve (banded beyond the limit);
    ``factor_at``: where ``M``'s factor starts in ``p`` (a constant ``M``), else None."""
    speeds = [f"out[{i}] = {states[n + i]}" for i in range(n)]
    bw = half_bandwidth(mass)
    if n > UNROLLED_LIMIT and bw > 0:
        exprs, lines = _banded_lines(mass, forcing, bw, factor_at)
        body = [f"for _i in range({n}):", f"    out[_i] = y[{n} + _i]",
                f"    out[{n} + _i] = _a[_i]"]
        return source("rhs", exprs, body, lines)
    names = iter(f"{{{k}}}" for k in range(n * n + n))
    m = _lower_names(mass, names)
    if all(m[(i, j)] is None for i in range(n) for j in range(i)):     # diagonal: divide
        exprs = [mass[i, j] for (i, j), name in m.items() if name is not None] + list(forcing)
        f = [next(names) for _ in range(n)]
        return source("rhs", exprs, speeds + [
            f"out[{n + i}] = {f[i]} / {m[(i, i)]} if {m[(i, i)]} > 0.0 else nan"
            for i in range(n)])
    exprs, lines, m, zero = _factor_lines(mass, factor_at)
    f = [f"{{{len(exprs) + i}}}" for i in range(n)]
    lines += _solve_lines(n, f, "a", zero)
    return source("rhs", exprs + list(forcing),
                  speeds + [f"out[{n + i}] = a{i}" for i in range(n)], lines)


def _factor_lines(mass, factor_at):
    """The mass entries' expressions and the lines binding the unrolled factor ``L``:
    factored from the entries, or read from ``p`` at ``factor_at`` (a constant ``M``).
    Returns the expressions, lines, entry names and structural zeros of ``L``."""
    n = mass.shape[0]
    m = _lower_names(mass, iter(f"{{{k}}}" for k in range(n * n)))
    exprs = [mass[i, j] for (i, j), name in m.items() if name is not None]
    lines, zero = _cholesky_lines(n, m)
    if factor_at is None:
        return exprs, lines, m, zero
    return [], [f"{name} = p[{factor_at + k}]"
                for k, name in enumerate(_factor_names(n, zero))], m, zero


def _factor_names(n, zero) -> list:
    """The names of the structurally non-zero entries of the unrolled factor, row by row."""
    return [f"L{i}_{j}" for i in range(n) for j in range(i + 1) if (i, j) not in zero]


def is_constant(mass) -> bool:
    """Whether a (renamed) mass matrix with off-diagonal terms depends on the
    parameters ``p0, p1, ...`` alone: it is factored once per parameter vector."""
    if not any(i > j for i, j in mass.todok()):
        return False                                   # diagonal: a division, nothing to save
    return all(re.fullmatch(r"p\d+", s.name) for s in mass.free_symbols)


def mass_margin_event(mass, state):
    """``det M - MASS_FLOOR prod M_ii``, watched falling through zero: negative where
    ``det M / prod M_ii`` (free of the coordinates' units, 1 for a diagonal ``M``, 0
    where it is singular) is below the floor, and never 0/0. For 2 or 3 coordinates
    coupled in a mass matrix that changes with ``state``; else None (a vanishing
    diagonal entry stalls the step: the failure names it)."""
    n = mass.shape[0]
    if n not in (2, 3) or not any(mass[i, j] != 0 for i in range(n) for j in range(i)) \
            or not any(e.free_symbols & state for e in mass):
        return None
    return mass.det(method="berkowitz") - MASS_FLOOR * sp.Mul(*[mass[i, i] for i in range(n)])


def factor_source(source, mass) -> tuple:
    """``mass_factor(t, y, p, out)`` writing the factor of a constant ``M`` (the unrolled
    ``L``'s non-zero entries, or the band ``n x (bw + 1)`` row by row beyond the
    unrolling limit) and the number of its entries."""
    n, bw = mass.shape[0], half_bandwidth(mass)
    if n > UNROLLED_LIMIT:
        exprs, lines = _banded_lines(mass, [], bw)
        size = n * (bw + 1)
        return source("mass_factor", exprs, [f"_f = _m.ravel()", f"for _i in range({size}):",
                                             "    out[_i] = float(_f[_i])"], lines), size
    exprs, lines, _, zero = _factor_lines(mass, None)
    names = _factor_names(n, zero)
    return source("mass_factor", exprs, [f"out[{k}] = {name}" for k, name in enumerate(names)],
                  lines), len(names)


def _jac_source(source, mass, forcing, q_names, u_names, factor_at=None):
    """The analytic Jacobian ``[[0, I], [da/dq, da/du]]`` with ``da/dq = M^-1 (df/dq -
    dM/dq a)`` and ``da/du = M^-1 df/du``, scalar code with the unrolled Cholesky factor
    up to the unrolling limit; beyond it the pieces, assembled with numpy."""
    n = len(q_names)
    identity = ["out[:, :] = 0.0"] + [f"out[{i}, {n + i}] = 1.0" for i in range(n)]
    if n > UNROLLED_LIMIT:
        return _banded_jac_source(source, mass, forcing, q_names, u_names, factor_at)
    exprs, lines, _, zero = _factor_lines(mass, factor_at)
    f = [f"{{{len(exprs) + i}}}" for i in range(n)]
    exprs += list(forcing)
    names = iter(f"{{{k}}}" for k in range(len(exprs), len(exprs) + 2 * n ** 3 + 2 * n * n))
    dm, f_q, f_u = [], [], []                      # f_q[k][i] = df_i/dq_k
    for qk in q_names:
        block = [[sp.diff(mass[i, j], qk) for j in range(n)] for i in range(n)]
        dm.append([[None if e == 0 else next(names) for e in row] for row in block])
        exprs += [e for row in block for e in row if e != 0]
    for derivatives, variables in ((f_q, q_names), (f_u, u_names)):
        for v in variables:
            column = [sp.diff(forcing[i], v) for i in range(n)]
            derivatives.append([None if e == 0 else next(names) for e in column])
            exprs += [e for e in column if e != 0]
    lines += _solve_lines(n, f, "a", zero)
    body = list(identity)
    for k in range(n):
        column = [" - ".join([f_q[k][i] or "0.0"] + [f"{dm[k][i][j]} * a{j}" for j in range(n)
                                                      if dm[k][i][j] is not None])
                  for i in range(n)]
        lines += _solve_lines(n, [f"({c})" for c in column], f"q{k}_", zero)
        lines += _solve_lines(n, [f_u[k][i] or "0.0" for i in range(n)], f"u{k}_", zero)
        body += [f"out[{n + i}, {k}] = q{k}_{i}" for i in range(n)]
        body += [f"out[{n + i}, {n + k}] = u{k}_{i}" for i in range(n)]
    return source("jac", exprs, body, lines)


# ------------------------------------------------------- large models: banded, numeric
def half_bandwidth(mass) -> int:
    """The largest ``|i - j|`` of a structurally non-zero entry of ``mass``."""
    return max((i - j for i, j in mass.todok()), default=0)


def _banded_lines(mass, forcing, bw, factor_at=None):
    """Expressions and lines leaving ``_m`` (the factor of ``M``'s band: computed, or
    viewed in ``p`` from ``factor_at`` for a constant ``M``) and, given the forcing
    ``f``, ``_a`` (the accelerations ``M^-1 f``); the expressions are the non-zero
    entries (none when viewed), then ``f``."""
    n = mass.shape[0]
    if factor_at is not None:
        lower, lines = [], [f"_m = band_view(p, {factor_at}, {n}, {bw})"]
    else:
        lower = [(i, j) for i in range(n) for j in range(max(0, i - bw), i + 1)
                 if mass[i, j] != 0]
        lines = [f"_m = np.zeros(({n}, {bw + 1}))"]
        lines += [f"_m[{i}, {i - j}] = {{{k}}}" for k, (i, j) in enumerate(lower)]
        lines.append(f"band_factor(_m, {bw})")
    exprs = [mass[i, j] for i, j in lower] + list(forcing)
    if len(forcing):
        lines += [f"_a = np.empty({n})"] + [f"_a[{i}] = {{{len(lower) + i}}}" for i in range(n)]
        lines.append(f"band_solve(_m, {bw}, _a)")
    return exprs, lines


def _banded_jac_source(source, mass, forcing, q_names, u_names, factor_at=None):
    """The Jacobian of a large model: ``[df/dq - dM/dq a, df/du]`` from the non-zero
    derivatives only, then ``M^-1`` applied to its lower half by the banded factor."""
    n = len(q_names)
    bw = half_bandwidth(mass)
    varying = bool(mass.free_symbols & set(q_names))               # else dM/dq a is zero
    exprs, lines = _banded_lines(mass, forcing if varying else [], bw, factor_at)
    column = {v: k for k, v in enumerate((*q_names, *u_names))}
    body = ["out[:, :] = 0.0", f"for _i in range({n}):", f"    out[_i, {n} + _i] = 1.0"]
    for i in range(n):
        for v in sorted(forcing[i].free_symbols & column.keys(), key=column.get):
            body.append(f"out[{n + i}, {column[v]}] = {{{len(exprs)}}}")
            exprs.append(_derivative(forcing[i], v))
    for i in range(n):
        for j in range(max(0, i - bw), i + 1):
            if mass[i, j] == 0:
                continue
            for v in sorted(mass[i, j].free_symbols & set(q_names), key=column.get):
                body.append(f"out[{n + i}, {column[v]}] -= {{{len(exprs)}}} * _a[{j}]")
                if i != j:
                    body.append(f"out[{n + j}, {column[v]}] -= {{{len(exprs)}}} * _a[{i}]")
                exprs.append(_derivative(mass[i, j], v))
    body.append(f"band_solve_rows(_m, {bw}, out, {n})")
    return source("jac", exprs, body, lines)


def jacobian_pattern(mass, forcing, q_names, u_names):
    """``[rows, columns]`` of the structurally non-zero entries of a large model's
    Jacobian whose ``M`` is diagonal (row ``n + i`` holds the variables of ``f_i`` and
    ``M_ii``), for the sparse LU of scipy's implicit methods; None for a small model or a
    non-diagonal ``M`` (``M^-1`` couples every row of a chain: the Jacobian is dense)."""
    n = len(q_names)
    if n <= UNROLLED_LIMIT or half_bandwidth(mass) > 0:
        return None
    column = {v: k for k, v in enumerate((*q_names, *u_names))}
    entries = [(i, n + i) for i in range(n)]
    for i in range(n):
        found = (forcing[i].free_symbols | mass[i, i].free_symbols) & column.keys()
        entries += [(n + i, k) for k in sorted(column[v] for v in found)]
    return [[r for r, _ in entries], [c for _, c in entries]]


def _derivative(expr, x):
    """``d expr / d x`` by the sum and product rules down to the terms that hold ``x``
    (sympy's ``diff`` costs milliseconds per call, whatever the size of the term)."""
    if x not in expr.free_symbols:
        return sp.S.Zero
    if expr == x:
        return sp.S.One
    if expr.is_Add:
        return sp.Add(*[_derivative(term, x) for term in expr.args if x in term.free_symbols])
    if expr.is_Mul:
        factors = expr.args
        return sp.Add(*[sp.Mul(*factors[:k], _derivative(factor, x), *factors[k + 1:])
                        for k, factor in enumerate(factors) if x in factor.free_symbols])
    return sp.diff(expr, x)

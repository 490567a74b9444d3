"""Code for ``M a = f``: the lines of an unrolled Cholesky factorisation and solve (NaN
where ``M`` is not positive definite, so a solver rejects the step), and the sources of
``rhs`` and its analytic Jacobian built on them (see :mod:`mechdyn.compile.generate`)."""
from __future__ import annotations

import sympy as sp


__all__ = ["UNROLLED_LIMIT"]

UNROLLED_LIMIT = 8          # DOF up to which the Cholesky solve is unrolled in code


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
    n = mass.shape[0]
    return {(i, j): (None if mass[i, j] == 0 else next(names))
            for i in range(n) for j in range(i + 1)}


def _rhs_source(source, mass, forcing, n, states, coordinates):
    """dy/dt = [u, M^-1 f] with an unrolled Cholesky solve (numpy beyond the limit)."""
    speeds = [f"out[{i}] = {states[n + i]}" for i in range(n)]
    if n > UNROLLED_LIMIT:
        exprs = list(mass) + list(forcing)
        body = speeds + ["spd_solve([" + "{}, " * (n * n) + "], [" + "{}, " * n
                         + f"], {n}, out, {n})"]
        return source("rhs", exprs, body)
    names = iter(f"{{{k}}}" for k in range(n * n + n))
    m = _lower_names(mass, names)
    exprs = [mass[i, j] for (i, j), name in m.items() if name is not None] + list(forcing)
    f = [next(names) for _ in range(n)]
    if all(m[(i, j)] is None for i in range(n) for j in range(i)):     # diagonal: divide
        return source("rhs", exprs, speeds + [
            f"out[{n + i}] = {f[i]} / {m[(i, i)]} if {m[(i, i)]} > 0.0 else nan"
            for i in range(n)])
    lines, zero = _cholesky_lines(n, m)
    lines += _solve_lines(n, f, "a", zero)
    return source("rhs", exprs, speeds + [f"out[{n + i}] = a{i}" for i in range(n)], lines)


def _jac_source(source, mass, forcing, q_names, u_names):
    """The analytic Jacobian ``[[0, I], [da/dq, da/du]]`` with ``da/dq = M^-1 (df/dq -
    dM/dq a)`` and ``da/du = M^-1 df/du``, scalar code with the unrolled Cholesky factor
    up to the unrolling limit; beyond it the pieces, assembled with numpy."""
    n = len(q_names)
    identity = ["out[:, :] = 0.0"] + [f"out[{i}, {n + i}] = 1.0" for i in range(n)]
    if n > UNROLLED_LIMIT:
        exprs = list(mass) + list(forcing)
        exprs += [sp.diff(mass[i, j], qk) for qk in q_names for i in range(n) for j in range(n)]
        exprs += [sp.diff(forcing[i], v) for v in (*q_names, *u_names) for i in range(n)]
        return source("jac", exprs, ["jac_assemble([" + "{}, " * len(exprs) + f"], {n}, out)"])
    names = iter(f"{{{k}}}" for k in range(2 * n ** 3 + 4 * n * n))
    m = _lower_names(mass, names)
    exprs = [mass[i, j] for (i, j), name in m.items() if name is not None] + list(forcing)
    f = [next(names) for _ in range(n)]
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
    lines, zero = _cholesky_lines(n, m)
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

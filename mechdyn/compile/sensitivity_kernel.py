"""The sensitivity equations compiled for the kernels (:mod:`mechdyn.kernels`): numba
functions ``rhs(t, z, p, out)`` of the state with its sensitivities, ``z = [y,
S.ravel()]``, and ``events(t, z, p, out)`` (the stop conditions, then the friction
elements' sliding rates), generated as scalar Python with common subexpressions shared.

>>> import sympy as sp, numpy as np, mechdyn as md
>>> from mechdyn.derive.sensitivity import forward_equations
>>> phi = md.coordinate("phi")
>>> J, M = sp.symbols("J M", positive=True)
>>> disc = md.Mechanism("disc", [phi])
>>> _ = disc.link("disc", J=J, angle=phi)
>>> _ = disc.load("drive", M, along=phi)
>>> functions = kernel_functions(forward_equations(disc.equations(), [J, M]), [J, M], [])
>>> out = np.zeros(6)
>>> functions.rhs(0.0, np.zeros(6), np.array([2.0, 6.0]), out)
>>> out.tolist()                                     # a = M/J, da/dJ = -M/J^2
[0.0, 3.0, 0.0, 0.0, -1.5, 0.5]
"""
from __future__ import annotations

from typing import NamedTuple

import sympy as sp

from mechdyn.symbols import t

__all__ = ["KernelFunctions", "kernel_functions", "solve_in_place"]


class KernelFunctions(NamedTuple):
    """The numba functions and what the kernel takes (:func:`model_functions`)."""
    rhs: object
    events: object
    model: object


def solve_in_place(a, b):
    """Solve ``a x = b`` for the columns of ``b`` (n x m) by Gaussian elimination with
    partial pivoting; ``b`` becomes ``x``, ``a`` is overwritten (compiled by numba).

    >>> import numpy as np
    >>> b = np.array([[1.0], [2.0]])
    >>> solve_in_place(np.array([[0.0, 2.0], [4.0, 1.0]]), b)
    >>> b.ravel().tolist()                     # 2 x1 = 1, 4 x0 + x1 = 2
    [0.375, 0.5]
    """
    n, m = a.shape[0], b.shape[1]
    for col in range(n):
        pivot = col
        for row in range(col + 1, n):
            if abs(a[row, col]) > abs(a[pivot, col]):
                pivot = row
        for c in range(n):
            a[col, c], a[pivot, c] = a[pivot, c], a[col, c]
        for c in range(m):
            b[col, c], b[pivot, c] = b[pivot, c], b[col, c]
        for row in range(col + 1, n):
            factor = a[row, col] / a[col, col]
            for c in range(col, n):
                a[row, c] -= factor * a[col, c]
            for c in range(m):
                b[row, c] -= factor * b[col, c]
    for col in range(n - 1, -1, -1):
        for c in range(m):
            total = b[col, c]
            for row in range(col + 1, n):
                total -= a[col, row] * b[row, c]
            b[col, c] = total / a[col, col]


_COMPILED = {}


def _compiled_solver():
    """:func:`solve_in_place` compiled once per process."""
    if "solve" not in _COMPILED:
        from numba import njit
        _COMPILED["solve"] = njit(error_model="numpy")(solve_in_place)
    return _COMPILED["solve"]


def _assignments(exprs, rename, prefix):
    """Lines computing ``exprs`` (common subexpressions first) into ``prefix0..``."""
    exprs = [sp.sympify(e).xreplace(rename) for e in exprs]
    shared, reduced = sp.cse(exprs, symbols=sp.numbered_symbols(f"_{prefix}c"))
    lines = [f"    {s} = {sp.pycode(v, fully_qualified_modules=True)}" for s, v in shared]
    lines += [f"    {prefix}{i} = {sp.pycode(v, fully_qualified_modules=True)}"
              for i, v in enumerate(reduced)]
    return lines


def kernel_functions(forward, parameters, watched) -> KernelFunctions:
    """Compile ``forward`` (:class:`~mechdyn.derive.sensitivity.ForwardEquations`) and the
    event expressions ``watched`` (of ``q``, ``u``, ``t`` and ``parameters``)."""
    from numba import njit
    import numpy as np

    from mechdyn.kernels import EVENTS_SIGNATURE, RHS_SIGNATURE, model_functions
    n, k = len(forward.q), len(forward.wrt)
    rename = {t: sp.Symbol("_t")}
    rename |= {s: sp.Symbol(f"_q{i}") for i, s in enumerate(forward.q)}
    rename |= {s: sp.Symbol(f"_u{i}") for i, s in enumerate(forward.u)}
    rename |= {s: sp.Symbol(f"_a{i}") for i, s in enumerate(forward.a)}
    rename |= {s: sp.Symbol(f"_p{i}") for i, s in enumerate(parameters)}
    head = ["    _t = t"] + [f"    _q{i} = z[{i}]" for i in range(n)]
    head += [f"    _u{i} = z[{n + i}]" for i in range(n)]
    head += [f"    _p{i} = p[{i}]" for i in range(len(parameters))]
    body = list(head)
    body += _assignments(list(forward.mass) + list(forward.forcing), rename, "m")
    if n == 1:
        body.append("    _a0 = m1 / m0")
    else:
        body.append(f"    mass = np.empty(({n}, {n}))")
        body += [f"    mass[{i}, {j}] = m{i * n + j}" for i in range(n) for j in range(n)]
        body.append(f"    a = np.empty(({n}, 1))")
        body += [f"    a[{i}, 0] = m{n * n + i}" for i in range(n)]
        body.append("    solve(mass.copy(), a)")
        body += [f"    _a{i} = a[{i}, 0]" for i in range(n)]
    width = 2 * n + k
    body += _assignments(list(forward.residual_jacobian), rename, "r")
    body.append(f"    slopes = np.empty(({n}, {width}))")
    body += [f"    slopes[{i}, {j}] = r{i * width + j}" for i in range(n) for j in range(width)]
    body.append("    slopes = slopes / m0" if n == 1 else "    solve(mass, slopes)")
    body += [f"    out[{i}] = _u{i}" for i in range(n)] + [f"    out[{n + i}] = _a{i}" for i in range(n)]
    body += [f"    s = z[{2 * n}:].reshape(({2 * n}, {k}))",
             f"    for j in range({k}):",
             f"        for i in range({n}):",
             f"            out[{2 * n} + i * {k} + j] = s[{n} + i, j]",
             f"            total = slopes[i, {2 * n} + j]",
             f"            for m in range({2 * n}):",
             "                total += slopes[i, m] * s[m, j]",
             f"            out[{2 * n} + ({n} + i) * {k} + j] = total"]
    events = list(head) + (_assignments(watched, rename, "g") if watched else [])
    events += [f"    out[{i}] = g{i}" for i in range(len(watched))] or ["    pass"]
    namespace = {"np": np, "math": __import__("math")}
    if n > 1:
        namespace["solve"] = _compiled_solver()
    source = "def rhs(t, z, p, out):\n" + "\n".join(body) + \
        "\n\ndef events(t, z, p, out):\n" + "\n".join(events) + "\n"
    exec(compile(source, "<mechdyn sensitivity kernel>", "exec"), namespace)
    rhs = njit(RHS_SIGNATURE, error_model="numpy")(namespace["rhs"])
    event_function = njit(EVENTS_SIGNATURE, error_model="numpy")(namespace["events"])
    model = model_functions(rhs, events=event_function if watched else None)
    return KernelFunctions(rhs, event_function, model)

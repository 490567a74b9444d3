"""Printing the derivation: mechdyn's named (textbook) form versus simplifying the
expanded form with sympy.simplify, the obvious alternative (what `mechdyn equations`
did before issue 29: simplify every step of at most 120 operations).

    python benchmarks/equations.py

For the bundled slider-crank and a user's slider-crank with flywheel, Kloss motor, guide
friction and shoe brake (tests/data/slider_crank_flywheel.py), in this process, each
on freshly derived equations with sympy's cache cleared: CPU time
(``time.process_time``: a busy shared machine disturbs it less than wall time) and the
length of the equation-of-motion line of the LaTeX.
"""
from __future__ import annotations

import time
from pathlib import Path

import sympy as sp
from sympy.core.cache import clear_cache

import mechdyn as md
from mechdyn.derive.latex import derivation_latex

ROOT = Path(__file__).resolve().parent.parent
MODELS = {"slider_crank (bundled)": ROOT / "models" / "slider_crank.py",
          "slider-crank with flywheel": ROOT / "tests" / "data" / "slider_crank_flywheel.py"}


def simplified(expr):
    """The old printer's step: simplify when small (at most 120 operations)."""
    if sp.count_ops(expr) > 120:
        return expr
    simpler = sp.simplify(expr)
    return simpler if sp.count_ops(simpler) <= sp.count_ops(expr) else expr


def simplify_expanded(eqs) -> str:
    """The obvious alternative: the expanded derivation, each step through simplify."""
    inertia = simplified(eqs.reduced_inertia)
    q, u, a = eqs.q[0], eqs.u[0], eqs.a[0]
    rows = [sp.latex(simplified(eqs.kinetic_energy)), sp.latex(inertia),
            sp.latex(simplified(eqs.reduced_moment))]
    rows += [sp.latex(simplified(c[0])) for c in eqs.generalized_forces.values()]
    lhs = inertia * a + simplified(sp.diff(inertia, q) / 2) * u ** 2
    rows.append(sp.latex(lhs) + " = " + sp.latex(eqs.reduced_moment))
    return "\n".join(rows)


def timed(work, path, line):
    """CPU seconds of ``work(eqs)`` and the length of its output's ``line``-th line."""
    clear_cache()
    eqs = md.load_model(path).mechanism.equations()
    started = time.process_time()
    text = work(eqs)
    return time.process_time() - started, len(text.splitlines()[line])


def main():
    print("| model | named (mechdyn) s | line chars | simplify(expanded) s | line chars |")
    print("|---|---|---|---|---|")
    for name, path in MODELS.items():
        named, named_line = timed(derivation_latex, path, -2)    # before \end{align*}
        old, old_line = timed(simplify_expanded, path, -1)
        print(f"| {name} | {named:.2f} | {named_line} | {old:.2f} | {old_line} |")


if __name__ == "__main__":
    main()

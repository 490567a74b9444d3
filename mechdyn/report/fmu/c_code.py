"""C from sympy expressions: the C twin of :func:`mechdyn.compile.codegen.function_source`
(the same ``sp.cse`` over the same expressions, locals bound by name), for the FMU.

Every generated function has the signature ``static void name(double t, const double *x,
const double *p, const double *w, double *out)``: ``x`` the state, ``p`` the parameters,
``w`` the switch flags (:class:`mechdyn.compile.generate.Switches`).

>>> import sympy as sp
>>> q0, k = sp.symbols("q0 k")
>>> print(c_function("f", {"q0": "x[0]"}, {"k": "p[0]"}, [k * sp.sin(q0) ** 2]))
static void f(double t, const double *x, const double *p, const double *w, double *out)
{
    const double q0 = x[0];
    const double k = p[0];
    out[0] = k*pow(sin(q0), 2);
    (void)t; (void)x; (void)p; (void)w; (void)out;
}
"""
from __future__ import annotations

import sympy as sp
from sympy.printing.c import C99CodePrinter

from mechdyn.errors import MechdynError

__all__ = ["c_function", "FmuExpressionError"]


class FmuExpressionError(MechdynError):
    """An expression that has no C form (an FMU cannot compute it)."""


class _Printer(C99CodePrinter):
    """C99 whose arithmetic means what the Python code means: a ``Piecewise`` without a
    default is NaN outside its branches; the derivative of a step is zero."""

    def _print_Piecewise(self, expr):
        if expr.args[-1].cond != sp.true:
            expr = sp.Piecewise(*expr.args, (sp.nan, True), evaluate=False)
        return super()._print_Piecewise(expr)

    def _print_DiracDelta(self, expr):
        return "0.0"

    def _print_NaN(self, expr):
        return "NAN"


_PRINTER = _Printer({"strict": True})


def printed(expr, what="expression") -> str:
    """The C text of one expression, or a :class:`FmuExpressionError` naming ``what``."""
    try:
        return " ".join(_PRINTER.doprint(expr).split())
    except (ValueError, NotImplementedError, TypeError) as error:
        raise FmuExpressionError(f"{what}: {expr} has no C form for an FMU ({error})") \
            from None


def c_function(name, states, parameters, expressions, body=None, what=()) -> str:
    """C source of ``name`` computing ``expressions`` with shared subexpressions.

    ``states`` and ``parameters`` map the local names (never ``t``, ``x``, ``p``, ``w``;
    only those the expressions use are bound) the expressions use to the C
    they are read from (``{"q0": "x[0]"}``); ``body`` lists the statements writing the
    results, format strings over the expressions' C (default ``out[i] = {i}``);
    ``what`` names each expression for errors.
    """
    temporaries, reduced = sp.cse(list(expressions), symbols=sp.numbered_symbols("c_"),
                                  order="none")
    names = list(what) + [f"expression {i}" for i in range(len(what), len(reduced))]
    text = [f"static void {name}(double t, const double *x, const double *p, "
            "const double *w, double *out)", "{"]
    used = {s.name for e in list(reduced) + [v for _, v in temporaries]
            for s in sp.sympify(e).free_symbols}
    text += [f"    const double {local} = {source};"
             for local, source in {**states, **parameters}.items() if local in used]
    text += [f"    const double {symbol} = {printed(value, name)};"
             for symbol, value in temporaries]
    values = [printed(expr, label) for expr, label in zip(reduced, names)]
    if body is None:
        body = [f"out[{i}] = {{{i}}}" for i in range(len(values))]
    text += ["    " + line.format(*values) + ";" for line in body]
    text += ["    (void)t; (void)x; (void)p; (void)w; (void)out;", "}"]
    return "\n".join(text)

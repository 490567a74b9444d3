"""Scalar code from sympy expressions: common subexpressions shared, math-module calls,
the state and the parameters read from vectors passed at run time.

Every generated function has the signature ``f(t, y, p, out)``: it reads the state ``y``
and the parameter vector ``p`` by index and writes its results into ``out``. The source
is plain Python on the math module, so it runs as it is and compiles unchanged with
numba. The generated text is mechdyn's own (never user text); it is compiled with
``exec``.

>>> import sympy as sp
>>> x, k = sp.symbols("x k")
>>> src = function_source("f", ["x"], ["k"], [k * sp.sin(x) ** 2, sp.sin(x)],
...                       ["out[0] = {0}", "out[1] = {1}"])
>>> out = [0.0, 0.0]
>>> compile_source(src)["f"](0.0, [0.5], [2.0], out)
>>> out
[0.4596976941318603, 0.479425538604203]
"""
from __future__ import annotations

import re
import string

import sympy as sp
from sympy.printing.pycode import PythonCodePrinter

from mechdyn.compile.generated import compile_source

# sympy's cse() always runs opt_cse, its search for common factors (most of cse's time on a
# large model); the tree pass alone is sympy.simplify.cse_main.tree_cse, which sympy does
# not export. Where a sympy release lacks it, large models take cse() itself: the same
# values, found more slowly (tests/test_third_party_internals.py pins both paths).
try:
    from sympy.simplify.cse_main import tree_cse as _tree_cse
except ImportError:                 # pragma: no cover - sympy outside the tested range
    _tree_cse = None


def _whole_subtrees(expressions, symbols):
    """cse of whole subtrees only, without the search for common factors."""
    if _tree_cse is None:
        return sp.cse(expressions, symbols=symbols, order="none")
    return _tree_cse(expressions, symbols, {}, "none")

__all__ = ["function_source", "compile_source", "safe_symbols", "printed", "list_function"]


class _Printer(PythonCodePrinter):
    """Python code whose arithmetic means the same in CPython and numba: a fractional
    power of a negative number is a domain error (``math.pow``), never a complex number;
    the derivative of a step (``DiracDelta``) is zero wherever it is evaluated."""

    def _print_Pow(self, expr, rational=False):
        base, exponent = expr.as_base_exp()
        if exponent.is_Integer:
            return super()._print_Pow(expr, rational)
        if exponent == sp.S.Half:
            return f"sqrt({self._print(base)})"
        if exponent == -sp.S.Half:
            return f"(1.0/sqrt({self._print(base)}))"
        return f"pow({self._print(base)}, {self._print(exponent)})"

    def _print_DiracDelta(self, expr):
        return "0.0"

    def table_call(self, expr):
        """A long table (:mod:`mechdyn.declare.lookup`): its shared search."""
        from mechdyn.compile.table_code import call_text
        return call_text(expr, self._print(expr.args[0]))


_FORMATTER = string.Formatter()
_NAME = re.compile(r"[A-Za-z_]\w*")
_PRINTER = _Printer({"fully_qualified_modules": False, "standard": "python3"})
_UNSORTED = _Printer({"fully_qualified_modules": False, "standard": "python3", "order": "none"})


def printed(expr) -> str:
    """The Python text of one expression."""
    return _PRINTER.doprint(expr)


def safe_symbols(prefix: str, count: int) -> list:
    """``count`` real symbols named ``prefix0, prefix1, ...`` for generated code."""
    return [sp.Symbol(f"{prefix}{i}", real=True) for i in range(count)]


def function_source(name, states, parameters, expressions, body, doc="", lines=(),
                    large=False) -> str:
    """Source of ``def name(t, y, p, out)`` computing ``expressions`` with shared cse.

    ``states`` and ``parameters`` are the local names bound to ``y[i]`` and ``p[j]``;
    the expressions are bound to the locals ``_e0, _e1, ...``; ``lines`` are extra
    statements placed after them and ``body`` the statements that write ``out``, both
    format strings over the expressions' local names (``"out[0] = {0}"``). ``large``
    (a model of many coordinates): cse shares whole subtrees only, without its search
    for common factors of products and sums (most of its time), and terms are printed
    in sympy's own order.
    """
    symbols = sp.numbered_symbols("_c")
    if large:
        temporaries, reduced = _whole_subtrees(list(expressions), symbols)
        text_of = _UNSORTED.doprint
    else:
        temporaries, reduced = sp.cse(list(expressions), symbols=symbols, order="none")
        text_of = printed
    computed = [f"    {symbol} = {text_of(value)}" for symbol, value in temporaries]
    computed += [f"    _e{i} = {text_of(expr)}" for i, expr in enumerate(reduced)]
    names = [f"_e{i}" for i in range(len(reduced))]
    # vformat reads the names by index: no unpacking of every name for every line
    computed += ["    " + _FORMATTER.vformat(line, names, {}) for line in (*lines, *body)]
    used = set(_NAME.findall("\n".join(computed)))      # read only what is used: numba
    text = [f"def {name}(t, y, p, out):"]               # compiles every statement
    if doc:
        text.append(f'    """{doc}"""')
    text += [f"    {n} = y[{i}]" for i, n in enumerate(states) if n in used]
    text += [f"    {n} = p[{i}]" for i, n in enumerate(parameters) if n in used]
    text += computed
    if len(text) == 1 + bool(doc):
        text.append("    pass")
    return "\n".join(text) + "\n"


def list_function(name, states, parameters, expressions):
    """A compiled ``f(t, y, p) -> list`` of the expressions' values, for analysis code
    that calls generated functions from Python (``y`` a list or an array)."""
    from mechdyn.compile.table_code import table_constants
    source = table_constants(expressions) + function_source(
        name, states, parameters, expressions,
        [f"out[{i}] = {{{i}}}" for i in range(len(expressions))])
    raw = compile_source(source)[name]
    size = len(expressions)

    def evaluate(t, y, p):
        out = [0.0] * size
        raw(t, y.tolist() if hasattr(y, "tolist") else list(y), p, out)
        return out
    return evaluate

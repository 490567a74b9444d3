"""The mode numerics (:mod:`mechdyn.compile.mode_numerics`) as C entry points that a
scene's generated mode functions call by symbol name.

A numba function that calls another numba function links the callee's whole code into
its own and optimises and emits it again: every scene's ``mode_rhs``, ``mode_events``
and ``loop_project`` carried a copy of the constrained equations' solver and cost about
0.8 s more to compile than its own few lines (numba 0.68, measured). Here each numerics
function is compiled once per installation as a ``cfunc`` (cached on disk like the
kernels) whose address is registered with LLVM under a fixed symbol
(``llvmlite.binding.add_symbol``, as numba registers its own C helpers); the generated
code calls it through the intrinsics below, which declare that symbol and pass each
array as its data pointer and length. Nothing is linked, and the cached machine code of
a scene refers to the symbol by name, resolved when the generated module is loaded
(it imports this module first).

Arguments: 1-D contiguous arrays of float64 or int64 (the scene's ``layout`` is one) and
int64 scalars; results are float64 or int64 (a flag is 0 or 1).

>>> import numpy as np
>>> from numba import njit
>>> @njit
... def smallest_step(grads, residual, out):
...     least_change_into(grads, residual, out)
>>> out = np.zeros(2)
>>> smallest_step(np.array([1.0, 1.0]), np.array([2.0]), out)
>>> out.tolist()
[1.0, 1.0]
"""
from __future__ import annotations

from llvmlite import binding, ir
from numba import cfunc, types
from numba.core import cgutils
from numba.extending import intrinsic
from numba.np.numpy_support import carray

from mechdyn.compile import mode_numerics as numerics
from mechdyn.numba_cache import CACHED

__all__ = ["constrained", "frozen_speeds", "group_margins", "rank_margin",
           "least_change_into"]

_F, _I = types.CPointer(types.float64), types.CPointer(types.int64)
_N = types.int64


@cfunc(types.int64(_F, _N, _I, _N, _F, _N, _F, _N), cache=CACHED, error_model="numpy")
def _constrained(buf, nb, lay, nl, p, np_, x, nx):
    ok = numerics.constrained(carray(buf, nb), carray(lay, nl), carray(p, np_),
                              carray(x, nx))
    return 1 if ok else 0


@cfunc(types.int64(_I, _N, _F, _N, _F, _N), cache=CACHED, error_model="numpy")
def _frozen_speeds(lay, nl, p, np_, out, no):
    numerics.frozen_speeds(carray(lay, nl), carray(p, np_), carray(out, no))
    return 0


@cfunc(types.int64(_F, _N, _I, _N, _F, _N, _F, _N, _N, _F, _N), cache=CACHED,
       error_model="numpy")
def _group_margins(buf, nb, lay, nl, p, np_, x, nx, ok, out, no):
    return numerics.group_margins(carray(buf, nb), carray(lay, nl), carray(p, np_),
                                  carray(x, nx), ok != 0, carray(out, no))


@cfunc(types.float64(_F, _N, _I, _N), cache=CACHED, error_model="numpy")
def _rank_margin(buf, nb, lay, nl):
    return numerics.rank_margin(carray(buf, nb), carray(lay, nl))


@cfunc(types.int64(_F, _N, _F, _N, _F, _N), cache=CACHED, error_model="numpy")
def _least_change(grads, ng, residual, nr, out, no):
    m = nr
    step = numerics.least_change(carray(grads, ng).reshape((m, ng // m)),
                                 carray(residual, nr))
    for i in range(no):
        out[i] = step[i]
    return 0


def _codegen(symbol, kinds, result):
    """Lowering of a call of ``symbol``: ``kinds`` are its arguments ("a": a 1-D array,
    passed as pointer and length; "i": an int64), ``result`` its numba type."""
    def codegen(context, builder, signature, values):
        lowered, argument_types = [], []
        for kind, value, typ in zip(kinds, values, signature.args):
            if kind == "a":
                array = context.make_array(typ)(context, builder, value)
                element = context.get_data_type(typ.dtype).as_pointer()
                lowered += [builder.bitcast(array.data, element), array.nitems]
                argument_types += [element, ir.IntType(64)]
            else:
                lowered.append(context.cast(builder, value, typ, types.int64))
                argument_types.append(ir.IntType(64))
        function_type = ir.FunctionType(context.get_value_type(result), argument_types)
        function = cgutils.get_or_insert_function(builder.module, function_type, symbol)
        return builder.call(function, lowered)
    return codegen


def _entry(compiled, kinds, result):
    """The intrinsic that calls ``compiled`` (a cfunc) by its symbol, registered here."""
    symbol = f"mechdyn_mode_{compiled.__name__.lstrip('_')}"
    binding.add_symbol(symbol, compiled.address)
    codegen = _codegen(symbol, kinds, result)
    arity = len(kinds)        # numba's intrinsics take no *args: one wrapper per arity
    if arity == 2:
        def call(typingctx, a, b):
            return result(a, b), codegen
    elif arity == 3:
        def call(typingctx, a, b, c):
            return result(a, b, c), codegen
    elif arity == 4:
        def call(typingctx, a, b, c, d):
            return result(a, b, c, d), codegen
    else:
        def call(typingctx, a, b, c, d, e, f):
            return result(a, b, c, d, e, f), codegen
    call.__name__ = compiled.__name__.lstrip("_")
    return intrinsic(call)


constrained = _entry(_constrained, "aaaa", types.int64)
frozen_speeds = _entry(_frozen_speeds, "aaa", types.int64)
group_margins = _entry(_group_margins, "aaaaia", types.int64)
rank_margin = _entry(_rank_margin, "aa", types.float64)
least_change_into = _entry(_least_change, "aaa", types.int64)

"""The mode numerics (:mod:`mechdyn.compile.mode_numerics`) as C entry points that a
scene's generated mode functions call by symbol name.

A numba function that calls another numba function links the callee's whole code into
its own and optimises and emits it again: every scene's ``mode_rhs``, ``mode_events``
and ``loop_project`` carried a copy of the constrained equations' solver and cost about
0.8 s more to compile than its own few lines (numba 0.68, measured). Here each numerics
function is compiled as a ``cfunc`` (once per installation, cached on disk like the
kernels; only those a scene uses) whose address is registered with LLVM under a fixed
symbol (``llvmlite.binding.add_symbol``, as numba registers its own C helpers); the
generated code calls it through the intrinsics below, which declare that symbol and
pass each array as its data pointer and length. Nothing is linked. The cached machine
code of a scene refers to the symbol by name, so a generated module calls
:func:`require` with the entries it uses before its functions are loaded.

Arguments: 1-D contiguous arrays of float64 ("f") or int64 ("n": the scene's
``layout``) and int64 scalars ("i"); results are float64 or int64 (a flag is 0 or 1).

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

import hashlib
from pathlib import Path

from llvmlite import binding, ir
from numba import cfunc, types
from numba.core import cgutils
from numba.extending import intrinsic
from numba import carray

from mechdyn.compile import mode_numerics as numerics
from mechdyn.kernels import linalg
from mechdyn.numba_cache import CACHED

__all__ = ["require", "constrained", "frozen_speeds", "group_margins", "rank_margin",
           "least_change_into"]


def _implementations(fingerprint) -> dict:
    """name -> (implementation, argument kinds, result type). numba keys a cached
    ``cfunc`` on this file only, though its machine code holds the numerics it calls:
    each implementation closes over ``fingerprint`` (of those sources, :data:`SOURCES`),
    so editing them compiles the entries again instead of loading stale code (as the
    kernels do, :mod:`mechdyn.kernels.loop`)."""
    def _constrained(buf, nb, lay, nl, p, np_, x, nx):
        fingerprint  # noqa: B018 (keys numba's cache on the numerics' sources)
        ok = numerics.constrained(carray(buf, nb), carray(lay, nl), carray(p, np_),
                                  carray(x, nx))
        return 1 if ok else 0

    def _frozen_speeds(lay, nl, p, np_, out, no):
        fingerprint  # noqa: B018
        numerics.frozen_speeds(carray(lay, nl), carray(p, np_), carray(out, no))
        return 0

    def _group_margins(buf, nb, lay, nl, p, np_, x, nx, ok, out, no):
        fingerprint  # noqa: B018
        return numerics.group_margins(carray(buf, nb), carray(lay, nl), carray(p, np_),
                                      carray(x, nx), ok != 0, carray(out, no))

    def _rank_margin(buf, nb, lay, nl):
        fingerprint  # noqa: B018
        return numerics.rank_margin(carray(buf, nb), carray(lay, nl))

    def _least_change(grads, ng, residual, nr, out, no):
        fingerprint  # noqa: B018
        step = numerics.least_change(carray(grads, ng).reshape((nr, ng // nr)),
                                     carray(residual, nr))
        for i in range(no):
            out[i] = step[i]
        return 0

    return {"constrained": (_constrained, "fnff", types.int64),
            "frozen_speeds": (_frozen_speeds, "nff", types.int64),
            "group_margins": (_group_margins, "fnffif", types.int64),
            "rank_margin": (_rank_margin, "fn", types.float64),
            "least_change": (_least_change, "fff", types.int64)}


#: the sources the entries' machine code is compiled from, besides this file
SOURCES = (Path(numerics.__file__), Path(linalg.__file__))


def _fingerprint() -> str:
    digest = hashlib.sha256()
    for path in SOURCES:
        digest.update(path.read_bytes())
    return digest.hexdigest()


_ENTRIES = _implementations(_fingerprint())
_C_ARGUMENTS = {"f": (types.CPointer(types.float64), types.int64),
                "n": (types.CPointer(types.int64), types.int64), "i": (types.int64,)}
_registered: dict = {}          # name -> its cfunc, kept alive while its symbol is used


def _symbol(name) -> str:
    return f"mechdyn_mode_{name}"


def require(*names):
    """Compile (or load from the cache) the entries ``names`` and register their symbols:
    a generated module calls this before its functions that use them are loaded."""
    for name in names:
        if name not in _registered:
            implementation, kinds, result = _ENTRIES[name]
            arguments = [t for kind in kinds for t in _C_ARGUMENTS[kind]]
            compiled = cfunc(result(*arguments), cache=CACHED,
                             error_model="numpy")(implementation)
            binding.add_symbol(_symbol(name), compiled.address)
            _registered[name] = compiled


def _codegen(name):
    """Lowering of a call of entry ``name``: arrays as data pointer and length."""
    _, kinds, result = _ENTRIES[name]

    def codegen(context, builder, signature, values):
        require(name)
        lowered, argument_types = [], []
        for kind, value, typ in zip(kinds, values, signature.args):
            if kind == "i":
                lowered.append(context.cast(builder, value, typ, types.int64))
                argument_types.append(ir.IntType(64))
            else:
                array = context.make_array(typ)(context, builder, value)
                element = context.get_data_type(typ.dtype).as_pointer()
                lowered += [builder.bitcast(array.data, element), array.nitems]
                argument_types += [element, ir.IntType(64)]
        function_type = ir.FunctionType(context.get_value_type(result), argument_types)
        function = cgutils.get_or_insert_function(builder.module, function_type,
                                                  _symbol(name))
        return builder.call(function, lowered)
    return codegen


def _entry(name):
    """The intrinsic that calls entry ``name`` by its symbol."""
    _, kinds, result = _ENTRIES[name]
    codegen = _codegen(name)
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
    call.__name__ = name
    return intrinsic(call)


constrained = _entry("constrained")
frozen_speeds = _entry("frozen_speeds")
group_margins = _entry("group_margins")
rank_margin = _entry("rank_margin")
least_change_into = _entry("least_change")

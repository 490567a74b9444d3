"""Model functions handed to the compiled kernel as addresses.

A model's right-hand side, Jacobian and event functions are numba functions compiled
with these exact signatures (``error_model="numpy"`` recommended, so a division by zero
gives inf/NaN, which the kernel handles, rather than an exception)::

    rhs(t, y, p, out)      "void(float64, float64[::1], float64[::1], float64[::1])"
    jac(t, y, p, out)      "void(float64, float64[::1], float64[::1], float64[:, ::1])"
    events(t, y, p, out)   "void(float64, float64[::1], float64[::1], float64[::1])"

:func:`model_functions` turns them into a :class:`ModelFunctions`: six addresses
(C wrapper and numba entry point of each) that the kernel takes as one ``int64`` array
and turns back into callable first-class functions (:func:`as_rhs`, :func:`as_jac`).
The kernel is therefore compiled once for every model. Passing the numba functions
themselves as ``FunctionType`` arguments works too, but numba then looks their
addresses up on every call of the kernel (about 35 us per function argument, measured
with numba 0.68); an ``int64`` array costs nothing. Exceptions raised inside a model
function propagate (the call goes through the numba entry point).

>>> from numba import njit
>>> @njit(RHS_SIGNATURE)
... def decay(t, y, p, out):
...     out[0] = -p[0] * y[0]
>>> fns = model_functions(decay)
>>> fns.addresses.shape, fns.has_jac, fns.has_events
((6,), False, False)
"""
from numba import types
from numba.core import cgutils
from numba.core.dispatcher import Dispatcher
from numba.extending import intrinsic
import numpy as np

from ..errors import DependencyError, MechdynError

# numba has no public API for a first-class function's addresses: these two helpers and
# the FunctionType struct's fields c_addr/py_addr/jit_addr (numba >= 0.61) are its
# internals. A numba without them stops here with a DependencyError naming what is
# missing, not deep inside a kernel's compilation (tests/test_third_party_internals.py
# pins both).
try:
    from numba.experimental.function_type import _get_jit_address, _get_wrapper_address
except ImportError:                     # pragma: no cover - numba outside the tested range
    raise DependencyError("numba", "numba.experimental.function_type._get_jit_address",
                          "the compiled kernels' model function addresses") from None
FUNCTION_FIELDS = ("c_addr", "py_addr", "jit_addr")   #: numba's FunctionType struct

__all__ = ["RHS_SIGNATURE", "JAC_SIGNATURE", "EVENTS_SIGNATURE", "ModelFunctions",
           "model_functions"]

RHS_SIGNATURE = "void(float64, float64[::1], float64[::1], float64[::1])"
JAC_SIGNATURE = "void(float64, float64[::1], float64[::1], float64[:, ::1])"
EVENTS_SIGNATURE = RHS_SIGNATURE

_vector = types.Array(types.float64, 1, "C")
_matrix = types.Array(types.float64, 2, "C")
RHS_TYPE = types.FunctionType(types.void(types.float64, _vector, _vector, _vector))
JAC_TYPE = types.FunctionType(types.void(types.float64, _vector, _vector, _matrix))


def _from_addresses(function_type):
    @intrinsic
    def build(typingctx, c_address, jit_address):
        def codegen(context, builder, signature, args):
            function = cgutils.create_struct_proxy(function_type)(context, builder)
            pointer = context.get_value_type(types.voidptr)
            try:
                function.c_addr = builder.inttoptr(args[0], pointer)
                function.py_addr = pointer(None)
                function.jit_addr = builder.inttoptr(args[1], pointer)
            except (AttributeError, KeyError):     # pragma: no cover - numba out of range
                raise DependencyError("numba", f"FunctionType fields {FUNCTION_FIELDS}",
                                      "calling model functions from the kernels") from None
            return function._getvalue()
        return function_type(types.int64, types.int64), codegen
    return build


as_rhs = _from_addresses(RHS_TYPE)   #: (c_address, jit_address) -> callable rhs/events
as_jac = _from_addresses(JAC_TYPE)   #: (c_address, jit_address) -> callable jac


class ModelFunctions:
    """The compiled functions of one model and their addresses for the kernel.

    Holds references to the numba functions: their machine code lives as long as this
    object does. ``addresses`` = [rhs C, rhs jit, jac C, jac jit, events C, events jit],
    zeros where a function is absent.
    """

    def __init__(self, rhs, jac=None, events=None):
        self.rhs, self.jac, self.events = rhs, jac, events
        self.addresses = np.zeros(6, dtype=np.int64)
        for slot, (role, function, function_type) in enumerate(
                (("rhs", rhs, RHS_TYPE), ("jac", jac, JAC_TYPE),
                 ("events", events, RHS_TYPE))):
            if function is not None:
                self.addresses[2 * slot:2 * slot + 2] = _addresses(role, function,
                                                                   function_type)

    @property
    def has_jac(self):
        return self.jac is not None

    @property
    def has_events(self):
        return self.events is not None


def model_functions(rhs, jac=None, events=None):
    """Check the model's numba functions and collect their addresses (see module doc)."""
    return ModelFunctions(rhs, jac, events)


def _addresses(role, function, function_type):
    signature = function_type.signature
    if isinstance(function, Dispatcher):
        compiled = [tuple(s) for s in function.signatures]
        if tuple(signature.args) not in compiled and getattr(function, "_can_compile", 0):
            try:                  # a lazy @njit function: compile it for the kernels
                function.compile(signature.args)
                compiled.append(tuple(signature.args))
            except Exception as error:
                raise MechdynError(f"the model's {role} function {function.__name__!r} "
                                   f"does not compile for {signature}: {error}") from error
        if tuple(signature.args) not in compiled:
            raise MechdynError(
                f"the model's {role} function {function.__name__!r} is not compiled with "
                f"the signature the kernels call: {signature} (it has "
                f"{[str(types.void(*s)) for s in compiled] or 'none'}); decorate it with "
                f"@njit({RHS_SIGNATURE if role != 'jac' else JAC_SIGNATURE!r})")
    elif not hasattr(function, "__wrapper_address__") and not hasattr(function, "address"):
        raise MechdynError(f"the model's {role} function must be a numba function "
                           f"(@njit or @cfunc), got {type(function).__name__}")
    return (_get_wrapper_address(function, signature),
            _get_jit_address(function, signature))

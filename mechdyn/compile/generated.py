"""Generated code brought to life: a scene's generated functions executed as Python and
the :class:`CompiledScene` that calls them by name.

Nothing here needs sympy: a run whose scene is compiled already (a cache hit, the warm
start of the command line) integrates without importing it.

>>> source = "def f(t, y, p, out):" + chr(10) + "    out[0] = sqrt(y[0]) * p[0]"
>>> out = [0.0]
>>> compile_source(source)["f"](0.0, [4.0], [3.0], out)
>>> out
[6.0]
"""
from __future__ import annotations

import math

import numpy as np

from mechdyn.errors import SimulationError

__all__ = ["compile_source", "CompiledScene", "SingularMassError", "TABLE_HELPERS"]

# The binary search of long tables (:mod:`mechdyn.compile.table_code`): plain Python
# that numba compiles as it is.
TABLE_HELPERS = '''
def table_segment(x, xs):
    lo = 0
    hi = len(xs) - 2
    while lo < hi:
        mid = (lo + hi + 1) // 2
        if x >= xs[mid]:
            lo = mid
        else:
            hi = mid - 1
    return lo


def table_slope(x, xs, ys):
    i = table_segment(x, xs)
    return (ys[i + 1] - ys[i]) / (xs[i + 1] - xs[i])


def table_value(x, xs, ys):
    i = table_segment(x, xs)
    return ys[i] + (ys[i + 1] - ys[i]) / (xs[i + 1] - xs[i]) * (x - xs[i])
'''


def compile_source(source: str, extra=None) -> dict:
    """Execute generated source in a namespace holding the math module's names
    (``pow`` is ``math.pow``: a domain error where a power has no real value)."""
    namespace = {name: getattr(math, name) for name in dir(math) if not name.startswith("_")}
    if "table_points(" in source:
        namespace["table_points"] = tuple
        exec(TABLE_HELPERS, namespace)
    namespace.update(extra or {})
    exec(compile(source, "<mechdyn generated>", "exec"), namespace)
    return namespace


class SingularMassError(SimulationError):
    """The mass matrix (reduced inertia) is not positive definite at a state.

    Examples
    --------
    A Scotch yoke without crank inertia, ``I_red = m l^2 sin(phi)^2``, started at the dead
    centre:

    >>> import sympy as sp, mechdyn as md
    >>> phi = md.coordinate("phi")
    >>> yoke = md.Mechanism("yoke", [phi])
    >>> _ = yoke.link("yoke", m=2, x=0.1 * sp.cos(phi))
    >>> start = md.Scene("start", initial={phi: 0, md.speed(phi): 1}, t_end=1, backend="scipy")
    >>> try:
    ...     yoke.simulate(start)
    ... except md.SingularMassError as error:
    ...     print(type(error).__name__)
    SingularMassError
    """

    def __init__(self, coordinate, t_value, state):
        self.coordinate, self.time, self.state = coordinate, t_value, list(state)
        super().__init__(f"the mass matrix is singular or not positive definite in "
                         f"coordinate {coordinate} at t = {t_value:.6g} s (the reduced inertia "
                         "vanishes there, e.g. a dead centre of the driving coordinate)")


def _flat_call(name, doc):
    """A :class:`CompiledScene` method calling its generated function ``name``."""
    def call(self, t_value, y, p) -> list:
        return self._call(name, t_value, y, p)
    call.__name__, call.__doc__ = name, doc
    return call


class CompiledScene:
    """The generated functions of one scene and the names that give them meaning.

    Attributes: ``coordinates`` (names), ``state_names``, ``param_names`` (user
    parameters, sorted), ``frictions`` (names), ``frozen`` (per friction: index of the
    coordinate it fixes when stuck, or -1), ``stop_labels``, ``output_labels``,
    ``event_kinds`` (``("stop" | "rate" | "switch", label)`` per entry of ``events``),
    ``meta``, ``source`` (the generated code), ``key`` (the cache key), ``raw`` (the
    generated functions by name, each ``f(t, y, p, out)``).
    """

    def __init__(self, meta: dict, source: str, key: str = ""):
        self.meta, self.source, self.key = meta, source, key
        self.coordinates = meta["coordinates"]
        self.dof = len(self.coordinates)
        self.state_names = meta["state_names"]
        self.param_names = meta["param_names"]
        self.frictions = meta["frictions"]
        self.frozen = meta["frozen"]
        self.stop_labels = meta["stop_labels"]
        self.output_labels = meta["output_labels"]
        self.event_kinds = [tuple(kind) for kind in meta["events"]]
        self.flags = sum(1 for kind, _ in self.event_kinds if kind == "switch")
        self.layout = {name: (offset, tuple(shape)) for name, offset, shape in meta["terms"]}
        self._slices = [(name, slice(offset, offset + int(np.prod(shape))),
                         shape if len(shape) != 1 else None)
                        for name, (offset, shape) in self.layout.items()]
        lower = np.tril_indices(self.dof)      # M from its lower triangle, by one take
        self._symmetric = np.empty((self.dof, self.dof), dtype=np.intp)
        self._symmetric[lower] = self._symmetric[lower[::-1]] = np.arange(len(lower[0]))
        self._sizes = {"terms": sum(int(np.prod(shape)) for _, shape in self.layout.values()),
                       "events": len(self.event_kinds), "outputs": len(self.output_labels)}
        from mechdyn.compile import loop_numeric
        self.raw = compile_source(source, {**_band_helpers(source),
                                           "numeric_jacobian": loop_numeric.numeric_jacobian,
                                           "numeric_minors": loop_numeric.numeric_minors,
                                           "loop_solve": loop_numeric.loop_solve})
        # Closed loops (empty without): constraint labels, the independent coordinates,
        # outputs that are loop multipliers; loop functions in loop_code's docstring.
        self.constraints = meta.get("constraints", [])
        self.independent = meta.get("independent", list(range(self.dof)))
        self.multiplier_outputs = meta.get("multiplier_outputs", {})
        n, m = self.dof, len(self.constraints)
        self.factor_at, self.factor_size = meta.get("mass_factor", (None, 0))
        self._pattern = tuple(np.array(index) for index in meta.get("jac_sparsity", ([], [])))
        self._sizes.update({"multipliers": m, "closure": 3 * m + m * n, "drift": 2,
                            "loop_minors": math.comb(n, m) if m else 0,
                            "linear_terms": 3 * n * n})

    # -------------------------------------------------------- Python-level calls
    def rhs(self, t_value, y, p) -> list:
        """``dy/dt`` at a state (list of floats); ``p`` from :meth:`parameter_vector`."""
        out = [0.0] * (2 * self.dof)
        self.raw["rhs"](t_value, _floats(y), p, out)
        return out

    def jac(self, t_value, y, p) -> np.ndarray:
        """Analytic Jacobian d(dy/dt)/dy of :meth:`rhs` (a ``2n x 2n`` array)."""
        out = np.zeros((2 * self.dof, 2 * self.dof))
        self.raw["jac"](t_value, _floats(y), p, out)
        return out

    def sparse_jac(self, t_value, y, p):
        """:meth:`jac` as a ``scipy.sparse`` CSC matrix of its structurally non-zero
        entries (``meta["jac_sparsity"]``: a large model with a diagonal mass matrix),
        so scipy's implicit methods factor it with a sparse LU."""
        from scipy.sparse import csc_matrix
        rows, columns = self._pattern
        size = 2 * self.dof
        return csc_matrix((self.jac(t_value, y, p)[rows, columns], (rows, columns)),
                          shape=(size, size))

    def terms(self, t_value, y, p) -> dict:
        """The friction modes' pieces by name (:mod:`mechdyn.compile.generate`): ``mass``
        (n x n), ``forcing``, ``friction_gradient`` (k x n), ``friction_bias``,
        ``friction_magnitude``, ``friction_rate``, ``friction_peak``, ``friction_release``,
        the stops' ``contact_*``, the lossy gears' ``gear_law``, the loops'
        ``constraint_*``."""
        flat = np.array(self._call("terms", t_value, y, p))
        out = {name: flat[part] if shape is None else flat[part].reshape(shape)
               for name, part, shape in self._slices}      # a vector: the slice
        out["mass"] = out["mass"][self._symmetric]
        return out

    # Functions returning a flat list of ``_sizes[name]`` values at ``(t, y, p)``.
    events = _flat_call("events", "Values of the event functions (stops, friction rates, "
                        "switching functions).")
    outputs = _flat_call("outputs", "Values of the requested outputs.")
    multipliers = _flat_call("multipliers", "Closed loops: the constraint forces "
                             "``lambda`` (``M a = f + G' lambda``).")
    closure = _flat_call("closure", "Closed loops: ``[g..., G row by row..., dg/dt..., "
                         "bias...]``.")
    drift = _flat_call("drift", "Closed loops: ``[max |g|, max |G u + dg/dt|]``.")
    loop_minors = _flat_call("loop_minors", "Closed loops: every ``m x m`` minor of ``G``.")
    linear_terms = _flat_call("linear_terms", "``[M, df/dq, df/du]``, each ``n x n`` row "
                              "by row.")

    def energy(self, t_value, y, p) -> list:
        """Kinetic and potential energy ``[T, V]``."""
        out = [0.0, 0.0]
        self.raw["energy"](t_value, _floats(y), p, out)
        return out

    def _call(self, name, t_value, y, p) -> list:
        out = [0.0] * self._sizes[name]
        self.raw[name](t_value, _floats(y), p, out)
        return out

    # ---------------------------------------------------------------- parameters
    def parameter_vector(self, params, signs=None) -> list:
        """``p`` from parameter values (a dict by symbol or name, or a checked
        :class:`~mechdyn.declare.parameters.ParameterSet`), with the friction ``signs``
        (default 0) and every branch unlocked."""
        from mechdyn.declare.parameters import ParameterSet        # sympy: only where values are checked
        values = params if isinstance(params, ParameterSet) else ParameterSet(params)
        signs = [0.0] * len(self.frictions) if signs is None else list(signs)
        base = values.vector(self.param_names)
        return base + signs + [0.0] * self.flags + self.mass_factor(base)

    def mass_factor(self, base) -> list:
        """The factor of a constant mass matrix at the parameter values ``base`` (``p``
        without signs and flags), appended to ``p`` after the flags; ``[]`` where ``M``
        depends on the state or time (factored at every call) or is diagonal."""
        if self.factor_at is None:
            return []
        out = [0.0] * self.factor_size
        p = list(base) + [0.0] * (self.factor_at - len(base))
        self.raw["mass_factor"](0.0, [0.0] * (2 * self.dof), p, out)
        return out

    def __getstate__(self):
        """Pickled as its metadata and source (sweep workers, results), compiled again
        when unpickled."""
        return {"meta": self.meta, "source": self.source, "key": self.key}

    def __setstate__(self, state):
        self.__init__(state["meta"], state["source"], state["key"])

    def __repr__(self):
        return (f"CompiledScene(states {self.state_names}, parameters {self.param_names}, "
                f"frictions {self.frictions})")


def _floats(y):
    """The state as a list of Python floats (2-3x faster arithmetic than numpy scalars)."""
    return y.tolist() if type(y) is np.ndarray else y


def _band_helpers(source) -> dict:
    """The compiled banded solves a large model's code calls (numba is imported only for
    such a model), and numpy for its work arrays."""
    if "band_factor(" not in source:
        return {}
    from mechdyn.compile import band_linalg
    return {"np": np, "band_factor": band_linalg.band_factor, "band_view": _BandView(),
            "band_solve": band_linalg.band_solve,
            "band_solve_rows": band_linalg.band_solve_rows}


class _BandView:
    """``band_view(p, first, n, bw)`` for generated code run by Python, where ``p`` is a
    list: the factored band of a constant mass matrix as an array, converted once per
    parameter vector (``p`` is built once per segment and never changed in place)."""

    def __init__(self):
        self.last = (None, None)

    def __call__(self, p, first, n, bw):
        if type(p) is np.ndarray:
            return p[first:first + n * (bw + 1)].reshape((n, bw + 1))
        last = self.last                     # one read: safe when threads share a scene
        if last[0] is not p:
            last = self.last = (p, np.array(p[first:first + n * (bw + 1)]).reshape((n, bw + 1)))
        return last[1]

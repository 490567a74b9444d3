"""Method choice: which integrator a segment takes, when to change it, what to try next.

``method="auto"`` decides from measurements of the problem, never once for all:

- **At the start of every segment** (the run's start and after every event: a friction
  mode change, a switch of a ``Piecewise``) the eigenvalues of the analytic Jacobian are
  measured against the run's slowest time scale (:func:`choose_method`; above
  64 states estimated, :mod:`mechdyn.simulate.spectrum`): damped fast
  modes are stiff; undamped fast modes are real oscillations, resolved by the explicit
  method at tight tolerances and stepped over by the stiff one at loose tolerances.
- **During a segment** a :class:`StiffnessMonitor` compares ``h rho(J)`` with the
  explicit method's stability limit every few steps: an explicit method held at 70 % of
  its limit is switched to the stiff method; a stiff method whose steps stay within
  reach of the explicit one (``h rho < 1``) for many checks is switched back. The gap
  between the two thresholds keeps the switches from ping-ponging.
- **The stiff method is Radau** (L-stable, order 5: lightly damped fast modes, whose
  eigenvalues lie close to the imaginary axis, defeat the BDF orders 3-5 of LSODA and
  BDF, measured 77,000-176,000 steps where Radau takes 3,300). Its Newton iteration is
  fragile at very tight tolerances (501,227 steps on one CPU where another took 550, at
  rtol 1e-10), so stiff segments run at ``rtol >= STIFF_RTOL_FLOOR``; Radau's order
  keeps their error well below that (``benchmarks/hard_case_matrix.py``).
- **A failure is retried** from the last accepted state with the next method of
  :func:`fallbacks` before anything is reported.
"""
from __future__ import annotations

import numpy as np

from mechdyn.simulate.spectrum import DENSE_LIMIT, measures, spectral_radius

__all__ = ["choose_method", "explicit_for", "stiff_for", "STIFF", "StiffnessMonitor",
           "fallbacks", "STABILITY_LIMIT", "STIFF_RTOL_FLOOR", "segment_tolerances",
           "motion_jacobian", "backend_plan", "BackendPlan", "BACKENDS", "KERNEL_ONLY",
           "uses_kernels", "has_modes", "compiled_functions",
           "mode_compilable"]

STIFF = "Radau"
STIFF_RTOL_FLOOR = 1e-8
BACKENDS = ("auto", "scipy", "compiled")
COMPARED = ("RK45", "DOP853", "LSODA", "Radau", "BDF")     # a precision report's methods
COMPARED_RTOLS = (1e-4, 1e-6, 1e-8, 1e-10)                # ... and tolerances
KERNEL_ONLY = ("Rodas5P",)                 # methods only the compiled kernels have
_KERNEL = ("DOP853", "Rodas5P")            # methods the compiled kernels have
REMEASURE = 16             # segments of a mode per measurement of its stiffness (choose)
_STIFFNESS_LIMIT = 2000.0   # explicit steps forced by stability alone before it is stiff
# Where the stability region of each explicit method crosses the negative real axis.
STABILITY_LIMIT = {"DOP853": 6.0, "RK45": 3.3, "RK23": 2.5}


def explicit_for(rtol) -> str:
    """DOP853 at tight tolerances, RK45 at loose ones (fewer stages per step)."""
    return "DOP853" if rtol < 1e-6 else "RK45"


def stiff_for(backend) -> str:
    """The stiff method of a backend: Radau on scipy, Rodas5P compiled."""
    return "Rodas5P" if backend == "compiled" else STIFF


def motion_jacobian(compiled, t, y, p):
    """The Jacobian whose eigenvalues judge stiffness: the analytic one, or with closed
    loops the linearised motion the loops allow (the full one has spurious eigenvalues
    along the constraints: :func:`mechdyn.simulate.assembly.manifold_jacobian`)."""
    if compiled.constraints:
        from mechdyn.simulate.assembly import manifold_jacobian
        return manifold_jacobian(compiled, t, y, p)
    if "jac_sparsity" in compiled.meta and 2 * compiled.dof > DENSE_LIMIT:
        return compiled.sparse_jac(t, y, p)      # its non-zeros: no scan of n^2 entries
    return compiled.jac(t, y, p)


def choose_method(compiled, p, y0, t0, t_limit, rtol) -> tuple:
    """``(method, why)`` for a segment starting at ``(t0, y0)``: the eigenvalues of the
    analytic Jacobian there against the slowest time scale of the run.

    - Damped fast modes (large negative real parts): stiff, once stability alone would
      cost an explicit method more than ``_STIFFNESS_LIMIT`` steps.
    - Undamped fast modes (large imaginary parts only) are real oscillations: at tight
      tolerances they must be resolved, which the explicit method does; at rtol >= 1e-6
      the stiff method steps over them.
    - Otherwise the explicit method.

    The slow scale is the smallest non-zero eigenvalue magnitude, or the run length when
    the motion has a rigid-body (zero) mode.
    """
    explicit = explicit_for(rtol)
    try:
        jacobian = motion_jacobian(compiled, t0, y0, p)
    except (ArithmeticError, ValueError, np.linalg.LinAlgError):
        return explicit, "the Jacobian cannot be evaluated at the start"
    values = jacobian.data if hasattr(jacobian, "tocoo") else jacobian   # sparse: its entries
    if not np.all(np.isfinite(values)):
        return explicit, "the Jacobian is not finite at the start"
    fastest, damped, slow = measures(jacobian)
    magnitude = np.abs(slow)
    # A rigid-body mode is a double zero eigenvalue (a Jordan block): eig perturbs it by
    # about sqrt(eps) * |J|, far above eps, so "zero" is judged near sqrt(eps).
    nonzero = magnitude[magnitude > max(fastest, 1.0) * 1e-7]
    slowest = 1.0 / max(t_limit - t0, 1e-300)
    if len(nonzero) == len(magnitude) and len(nonzero):
        slowest = nonzero.min()
    elif len(nonzero):
        slowest = max(slowest, min(nonzero.min(), 1.0))
    if damped / slowest > _STIFFNESS_LIMIT:
        return STIFF, f"damped modes {damped / slowest:.3g} times faster than the motion"
    if fastest / slowest > _STIFFNESS_LIMIT and rtol >= 1e-6:
        return STIFF, (f"oscillations {fastest / slowest:.3g} times faster than the motion, "
                       "below the tolerance")
    return explicit, "no stiff modes"


class StiffnessMonitor:
    """Whether a segment's method no longer fits the problem: every ``every`` steps
    ``h rho(J)`` (``rho`` the spectral radius of the Jacobian ``jacobian(t, y)``) is
    compared with the explicit method's stability limit. For an explicit ``method``:
    ``count`` checks in a row at 70 % of the limit or more mean the problem is stiff
    there. For a stiff ``method``: ``relax`` checks in a row with ``h rho < 1`` mean it
    is not (the explicit method would take such steps)."""

    def __init__(self, method, jacobian, rtol, every=10, count=3, relax=50):
        self.explicit = method not in (STIFF, "LSODA", "BDF")
        self.limit = 0.7 * STABILITY_LIMIT[method if self.explicit else explicit_for(rtol)]
        self.jacobian, self.every = jacobian, every
        self.needed = count if self.explicit else relax
        self.steps, self.run, self.last = 0, 0, 0.0

    def __call__(self, t, y, h) -> bool:
        self.steps += 1
        if self.steps % self.every:
            return False
        try:
            matrix = self.jacobian(t, y)
            rho = spectral_radius(matrix)
        except (ArithmeticError, ValueError, np.linalg.LinAlgError):
            return False
        self.last = h * rho
        changed = self.last >= self.limit if self.explicit else self.last < 1.0
        self.run = self.run + 1 if changed else 0
        return self.run >= self.needed


def segment_tolerances(method, rtol, atol) -> tuple:
    """The tolerances a segment of ``method="auto"`` runs at: the scene's, except that
    stiff segments keep ``rtol >= STIFF_RTOL_FLOOR`` (``atol`` scaled alike). A method
    named in the scene runs at the scene's tolerances."""
    if method != STIFF or rtol >= STIFF_RTOL_FLOOR:
        return rtol, atol
    return STIFF_RTOL_FLOOR, np.asarray(atol) * (STIFF_RTOL_FLOOR / rtol)


def fallbacks(method, rtol, compiled=False) -> list:
    """The methods to try, in order, after ``method`` failed at some state (with the
    compiled kernels in use, their Rodas5P first)."""
    ladder = (["Rodas5P"] if compiled else []) + [STIFF, "LSODA", "BDF", explicit_for(rtol)]
    return [m for m in ladder if m != method]


def mode_compilable(compiled, mode) -> bool:
    """Whether a segment with ``mode`` has a compiled form: not where a lossy gear is
    stuck together with other elements (the share of their holding force is a linear
    programme, solved on scipy)."""
    kinds = compiled.meta.get("friction_kinds", [])
    return not any(len(group) > 1 and any(k < len(kinds) and kinds[k] == "gear"
                                          for k, _ in group) for group in mode.groups)


def has_modes(compiled) -> bool:
    """Whether a scene's segments run on its mode functions
    (:mod:`mechdyn.compile.mode_code`) rather than its plain ``rhs``: friction elements
    (which may stick), stop limits (whose gaps are watched from an offset), lossy gears
    or closed loops (their drift and singular positions watched)."""
    return bool(compiled.frictions or compiled.meta.get("contacts") or compiled.constraints)


def uses_kernels(compiled, method) -> bool:
    """Whether ``backend="auto"`` puts a scene with ``method`` on the compiled kernels:
    numba is importable, the scene has a compiled form and the method runs there (the
    rule of :class:`BackendPlan`; the first call may compile the scene, about 0.5 s,
    cached in memory and on disk)."""
    if method not in ("auto", *_KERNEL):
        return False
    return compiled_functions(compiled) is not None


def compiled_functions(compiled):
    """The scene's compiled form: its mode functions where it has modes
    (:func:`has_modes`), else its plain functions; None where it has none."""
    from mechdyn.compile.numba_model import mode_functions, numba_functions
    return mode_functions(compiled) if has_modes(compiled) else numba_functions(compiled)


def backend_plan(compiled, method, backend) -> "BackendPlan":
    """The :class:`BackendPlan` of a run; names the culprit of a backend that cannot
    serve the scene."""
    from mechdyn.errors import SceneError
    if backend not in BACKENDS:
        raise SceneError(f"backend {backend!r}: use one of {', '.join(BACKENDS)}")
    plan = BackendPlan(compiled, method, backend)
    if (backend == "compiled" or method in KERNEL_ONLY) and not plan.load():
        from mechdyn.compile.numba_model import available
        why = ("numba is not installed (pip install numba)" if not available() else
               f"the scene's equations ({compiled.dof} coordinates) have no compiled form")
        raise SceneError(f"backend {backend!r} with method {method!r}: {why}; use "
                         "backend='scipy'")
    return plan


class BackendPlan:
    """Where a run's segments integrate: scipy's solvers or the compiled kernels.

    One rule, from the scene and the installation only (never from what ran before in
    the process, nor from elapsed time), so the same call gives the same answer:

    - ``backend="scipy"`` never compiles;
    - ``"compiled"`` compiles (or loads) the scene at once and refuses a scene without
      a compiled form;
    - ``"auto"`` (the default) uses the compiled kernels whenever numba is importable,
      the scene has a compiled form (:func:`~mechdyn.compile.numba_model.numba_functions`)
      and its method may run on them (``"auto"``, DOP853 or Rodas5P: :func:`uses_kernels`);
      otherwise scipy.

    Scenes with friction elements, one-way clutches, lossy gears, stop limits or closed
    loops run on their mode functions (:func:`compiled_functions`); the mode
    decisions, impacts and projections onto the loops stay in Python, between
    segments. A segment where a lossy gear is stuck together with other elements runs
    on scipy (:func:`mode_compilable`).
    """

    def __init__(self, compiled, method, option):
        self.c, self.named, self.option = compiled, method, option
        self.functions = None
        self.why = ""
        self.measured = {}       # mode -> (t measured, segments since): see choose
        if option == "auto" and uses_kernels(compiled, method):
            self.load()

    @property
    def active(self) -> bool:
        return self.functions is not None and self.option != "scipy"

    def load(self) -> bool:
        """Compile or load the scene for the kernels; True when it has a compiled form."""
        if self.option == "scipy":
            return False
        if self.functions is None:
            self.functions = compiled_functions(self.c)
        return self.functions is not None

    def compilable(self, mode) -> bool:
        return not mode.groups or mode_compilable(self.c, mode)

    def method(self, name, mode) -> str:
        """The method a segment runs for a requested one: the kernels' own where they
        are in use, scipy's where not."""
        compiled = self.active and self.compilable(mode)
        if self.named == "auto" and compiled:
            return "Rodas5P" if name in (STIFF, "Rodas5P") else \
                "DOP853" if name in ("DOP853", "RK45") else name
        if name == "Rodas5P" and not compiled:
            return STIFF
        return name

    def functions_for(self, mode, method):
        """The compiled functions a segment with ``mode`` and ``method`` steps: Rodas5P's
        with the analytic Jacobian (compiled when first needed), DOP853's without; of a
        scene with modes, its mode functions (the Jacobian only where nothing is
        stuck)."""
        from mechdyn.compile.numba_model import mode_functions, numba_functions
        if has_modes(self.c):
            pair = mode_functions(self.c, jac=method == "Rodas5P")
            return pair[1 if mode.groups else 0]
        if method != "Rodas5P":
            return self.functions
        return numba_functions(self.c, jac=True)

    def backend(self, method, mode) -> str:
        return "compiled" if (self.active and method in _KERNEL and self.compilable(mode)) \
            else "scipy"

    def stiff(self, method) -> bool:
        return method in (STIFF, "BDF", "LSODA", "Rodas5P")

    def choose(self, p, mode, t, y, scene) -> str:
        """The method of a segment starting at ``(t, y)`` (sets ``why``). A mode whose
        start was measured free of stiff modes keeps the explicit method for its next
        ``REMEASURE - 1`` segments without measuring again, where the compiled kernel's
        stiffness test watches them (nothing stuck): a stiff stretch ends such a
        segment with status "stiff", and :meth:`forget` drops what was measured."""
        if self.named != "auto":
            self.why = "named in the scene"
            return self.method(self.named, mode)
        explicit = explicit_for(scene.rtol)
        key = self._guarded(mode)
        known = self.measured.get(key) if key is not None else None
        if known is not None and known[1] < REMEASURE:
            self.measured[key] = (known[0], known[1] + 1)
            self.why = (f"no stiff modes (measured at t = {known[0]:.6g} s in this mode; "
                        "the kernel's stiffness test watches the segment)")
            return self.method(explicit, mode)
        name, self.why = choose_method(self.c, p, y, t, scene.time_limit, scene.rtol)
        if key is not None and name == explicit and self.why == "no stiff modes":
            self.measured[key] = (float(t), 1)
        elif key is not None:
            self.measured.pop(key, None)
        return self.method(name, mode)

    def forget(self):
        """Measure every mode again (the kernel found a segment stiff, or it failed)."""
        self.measured.clear()

    def _guarded(self, mode):
        """The key under which a mode's measurement is kept, None where its segments
        would run without the kernel's stiffness test (on scipy, or something stuck)."""
        if mode.groups or not self.active:
            return None
        return (mode.signs, mode.free, mode.flags)

"""Work-precision reports: what accuracy costs in time, per scene and integrator.

For each method and tolerance the scene is simulated and compared with a reference:
the closed form where :func:`mechdyn.closed_form` gives ``phi(t)`` and ``omega(t)`` over
the whole run, otherwise an explicit and an implicit high-accuracy solution (DOP853 and
Radau) whose disagreement is reported, so a bad reference cannot go unnoticed.

Errors are relative: each state's deviation divided by the largest magnitude that state
reaches in the reference (1 for a state that stays zero), the largest over the states.
``final_error`` is that at the final state; ``l2_error`` the Euclidean norm of it over
``points`` evenly spaced dense-output times ending at the final state (so it is never
below the final error nor below any single point's error); ``event_errors`` the error of
each event time (a stop, a stick) divided by the reference's duration. Run times are the
minimum of repeated calls of ``simulate`` as a user makes them (``backend="auto"``, the
scene's own: the compiled kernels for DOP853 and ``"auto"`` where numba is installed,
scipy's solvers for the others); the scene's compilation, for scipy and for the kernels,
happens once before any timing. Each row names the backend its steps took.

>>> import mechdyn as md
>>> model = md.load_model("models/shoe_brake.py")    # stops after 50 s: closed form
>>> table = md.work_precision(model.mechanism, model.scenes["braking"], model.params,
...                           methods=["RK45", "Radau"], rtols=[1e-6], repeats=1)
>>> table.reference.kind, [row.method for row in table.rows]
('closed form', ['RK45', 'Radau'])
>>> all(error < 1e-9 for row in table.rows for _, error in row.event_errors)
True
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace

import numpy as np

from mechdyn.errors import MechdynError, SimulationError
from mechdyn.simulate.methods import COMPARED, COMPARED_RTOLS
from mechdyn.declare.parameters import ParameterSet
from mechdyn.tabular import Table

__all__ = ["work_precision", "WorkPrecision", "Row", "Reference", "DEFAULT_METHODS",
           "DEFAULT_RTOLS"]

DEFAULT_METHODS, DEFAULT_RTOLS = COMPARED, COMPARED_RTOLS
_REPEAT_BUDGET = 1.0      # s: stop repeating a run once its runs took this long ...
_SHORT = 0.1              # ... but repeat short runs up to 5x as often within this
_FLOOR = 1e-16            # errors below this are drawn at it on log axes


@dataclass(frozen=True)
class Row:
    """One run: ``method`` (as requested; ``used`` the one run, e.g. for ``"auto"``),
    ``rtol``, ``atol``, ``final_error``, ``l2_error``, ``event_errors`` (``(label,
    error)`` pairs), ``time`` (the minimum over ``runs`` runs, s), ``nfev``, ``njev``,
    ``steps``, ``backend`` (``"compiled"``, ``"scipy"`` or both joined by ``+``: where
    the steps ran) and ``failure`` (the error message; empty when the run succeeded)."""
    method: str
    rtol: float
    atol: object
    final_error: float = math.nan
    l2_error: float = math.nan
    event_errors: tuple = ()
    time: float = math.nan
    runs: int = 0
    nfev: int = 0
    njev: int = 0
    steps: int = 0
    used: str = ""
    backend: str = ""
    failure: str = ""

    @property
    def failed(self) -> bool:
        return bool(self.failure)

    @property
    def error(self) -> float:
        """The worst of the L2, final-state and event-time errors (NaN if failed)."""
        if self.failed:
            return math.nan
        return max([self.l2_error, self.final_error] + [e for _, e in self.event_errors])


@dataclass(frozen=True)
class Reference:
    """What runs are measured against: ``kind`` ("closed form" or "numerical"),
    ``description``, ``agreement`` (error of the second numerical solution against the
    first; ``None`` for a closed form or when the check failed), ``t_start``, ``t_end``,
    ``events`` (``(kind, name)`` -> list of times), ``scale`` (per state), ``notes``."""
    kind: str
    description: str
    agreement: float | None
    t_start: float
    t_end: float
    events: dict
    scale: np.ndarray
    states: object          # times -> array (states x times)
    notes: tuple = ()


class WorkPrecision:
    """A work-precision table: ``rows`` (:class:`Row`), the ``reference``, and the
    ``mechanism_name`` and ``scene`` it measured. ``str(table)`` prints it.

    Examples
    --------
    >>> import mechdyn as md
    >>> brake = md.load_model("shoe_brake")
    >>> table = md.work_precision(brake.mechanism, brake.scenes["braking"], brake.params,
    ...                           methods=["DOP853", "RK45"], rtols=[1e-8], repeats=1)
    >>> [(row.method, row.rtol, row.failed) for row in table.rows]
    [('DOP853', 1e-08, False), ('RK45', 1e-08, False)]
    """

    def __init__(self, mechanism_name, scene, reference, rows):
        self.mechanism_name, self.scene = mechanism_name, scene
        self.reference, self.rows = reference, list(rows)

    def cheapest(self, target_error) -> Row | None:
        """The fastest successful row whose :attr:`Row.error` meets ``target_error``, or
        ``None``. A target below what a numerical reference can vouch for (its
        ``agreement``) raises :class:`~mechdyn.MechdynError`."""
        agreement = self.reference.agreement
        if agreement is not None and target_error < agreement:
            raise MechdynError(f"target {target_error:.1e} lies below the reference's own "
                               f"accuracy (its two solutions agree to {agreement:.1e}); "
                               "tighten reference_rtol or loosen the target")
        meeting = [r for r in self.rows if not r.failed and r.error <= target_error]
        return min(meeting, key=lambda r: r.time) if meeting else None

    def table(self) -> Table:
        """The rows as a :class:`~mechdyn.tabular.Table` (times in ms; a failed run's
        message in the last column, a method run for another, e.g. ``auto``, there too)."""
        rows = []
        for r in self.rows:
            start = [r.method, r.backend or "-", r.rtol,
                     float(r.atol) if isinstance(r.atol, (int, float)) else "per state"]
            if r.failed:
                rows.append(start + [None] * 8 + [f"FAILED: {r.failure[:90]}"])
                continue
            worst = max((e for _, e in r.event_errors), default=None)
            rows.append(start + [r.final_error, r.l2_error, worst, r.time * 1e3, r.runs,
                                 r.nfev, r.njev, r.steps,
                                 f"({r.used})" if r.used != r.method else ""])
        caption = [f"Work-precision: {self.mechanism_name} — scene {self.scene.name!r}",
                   f"reference: {self.reference.description}"]
        caption += [f"  note: {n}" for n in self.reference.notes]
        return Table(["method", "backend", "rtol", "atol", "final err", "L2 err",
                      "event err", "time ms", "runs", "nfev", "njev", "steps", ""], rows,
                     "\n".join(caption), (None, None, ".0e", ".0e", ".1e", ".1e", ".1e", ".2f"))

    def __repr__(self):
        return (f"<WorkPrecision {self.mechanism_name!r} / {self.scene.name!r}: "
                f"{len(self.rows)} runs>")

    def __str__(self):
        lines = [self.table().text()]
        labels = sorted({label for r in self.rows for label, _ in r.event_errors})
        if labels:
            lines.append(f"event err: relative to the run's duration; events: "
                         f"{', '.join(labels)}")
        lines.append("errors: relative to each state's largest reference magnitude")
        return "\n".join(lines)

    def plot(self, path=None):
        """Log-log error (:attr:`Row.error`) against run time, one labelled curve per
        method, points marked by rtol; the reference agreement as a dashed line. Saves
        to ``path`` if given and returns the figure."""
        from mechdyn.plotting import finish, pyplot
        plt = pyplot()
        fig, ax = plt.subplots(figsize=(7, 5))
        for method in dict.fromkeys(r.method for r in self.rows):
            rows = sorted((r for r in self.rows if r.method == method and not r.failed),
                          key=lambda r: -r.rtol)
            failed = sum(r.failed for r in self.rows if r.method == method)
            label = method + (f" ({failed} failed)" if failed else "")
            if not rows:
                ax.plot([], [], marker="x", label=label)
                continue
            times = [r.time for r in rows]
            errors = [max(r.error, _FLOOR) for r in rows]
            (line,) = ax.loglog(times, errors, marker="o", label=label)
            for r, x, y in zip(rows, times, errors):
                ax.annotate(f"{r.rtol:.0e}", (x, y), fontsize=6, color=line.get_color(),
                            xytext=(3, 3), textcoords="offset points")
        if self.reference.agreement:
            ax.axhline(self.reference.agreement, color="grey", ls="--", lw=0.8,
                       label="reference agreement")
        ax.set_xlabel("run time [s] (minimum of repeated runs)")
        ax.set_ylabel("error (worst of L2, final state, event times; relative)")
        ax.set_title(f"{self.mechanism_name} — {self.scene.name}: work-precision\n"
                     f"reference: {self.reference.kind}", fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
        return finish(fig, path)


# ------------------------------------------------------------------------- entry
def work_precision(mech, scene, params, methods=DEFAULT_METHODS, rtols=DEFAULT_RTOLS,
                   repeats=3, points=100, reference_rtol=1e-13, check_rtol=1e-11):
    """Measure error against run time for each method and tolerance on a scene.

    Parameters
    ----------
    mech : Mechanism
    scene : Scene
    params : dict
        Parameter values.
    methods : sequence of str
        ``solve_ivp`` method names (or ``"auto"``). A method that fails gives a row
        with ``failure`` set, not an exception.
    rtols : sequence of float
        Relative tolerances; each run's ``atol`` is the scene's scaled by
        ``rtol / scene.rtol`` (per-state atol dicts keep their proportions).
    repeats : int
        Runs per row; the time is their minimum (fewer once they took 1 s, up to five
        times more while they take under 0.1 s in all).
    points : int
        Dense-output points of the L2 error.
    reference_rtol, check_rtol : float
        Tolerances of the numerical reference (DOP853) and of its implicit check
        (Radau, which costs far more per step in scipy), used when no closed form
        covers the scene.

    Returns
    -------
    WorkPrecision

    Raises
    ------
    SimulationError
        When neither numerical reference can be computed.

    Examples
    --------
    >>> import mechdyn as md
    >>> model = md.load_model("models/shoe_brake.py")
    >>> table = md.work_precision(model.mechanism, model.scenes["braking"], model.params,
    ...                           methods=["DOP853"], rtols=[1e-8], repeats=1)
    >>> table.cheapest(1e-9).method
    'DOP853'
    """
    from mechdyn.simulate.methods import uses_kernels
    params = ParameterSet(params, mechanism=mech, scene=scene)     # before any compiling
    compiled = mech.compile(scene)     # compile (or load) once, outside the timing
    params.vector(compiled.param_names)                            # none missing
    if uses_kernels(compiled, "auto"):
        from mechdyn.compile.numba_model import numba_functions
        numba_functions(compiled, jac=True)          # Rodas5P's, too
    reference = _reference(mech, scene, params, points, reference_rtol, check_rtol)
    rows = [_row(mech, scene, params, method, rtol, repeats, reference, points)
            for method in methods for rtol in rtols]
    return WorkPrecision(mech.name, scene, reference, rows)


# -------------------------------------------------------------------- one row
def _scaled(scene, rtol, **changes):
    """The scene at ``rtol``, its atol scaled alike."""
    factor = rtol / scene.rtol
    atol = ({k: v * factor for k, v in scene.atol.items()} if isinstance(scene.atol, dict)
            else scene.atol * factor)
    return replace(scene, rtol=rtol, atol=atol, **changes)


def _row(mech, scene, params, method, rtol, repeats, reference, points):
    atol = None
    try:
        run_scene = _scaled(scene, rtol, method=method)
        atol = run_scene.atol
        times, result = [], None
        while len(times) < max(repeats, 1) and sum(times) < _REPEAT_BUDGET or \
                len(times) < 5 * repeats and sum(times) < _SHORT:
            started = time.perf_counter()
            result = mech.simulate(run_scene, params)
            times.append(time.perf_counter() - started)
    except MechdynError as error:
        partial = getattr(error, "partial", None) if isinstance(error, SimulationError) \
            else None
        counts = _counts(partial.stats) if partial is not None else {}
        return Row(method, rtol, atol, failure=str(error), **counts)
    final, l2, events = _errors(result, reference, points)
    return Row(method, rtol, atol, final, l2, events, min(times), len(times),
               **_counts(result.stats))


def _counts(stats):
    return {"nfev": int(stats.get("nfev", 0)), "njev": int(stats.get("njev", 0)),
            "steps": int(stats.get("steps", 0)), "used": str(stats.get("method", "")),
            "backend": "+".join(stats.get("backends", {}))}


def _errors(result, reference, points):
    """(final error, L2 error, event errors) of a result against the reference."""
    times = np.linspace(result.t[0], result.t[-1], points)
    run = np.array(list(result.at(times).values()), dtype=float)
    run[:, -1] = result.y[:, -1]                  # the final state itself
    exact = reference.states(np.minimum(times, reference.t_end))
    pointwise = np.max(np.abs(run - exact) / reference.scale[:, None], axis=0)
    return (float(pointwise[-1]), float(np.sqrt(np.sum(pointwise ** 2))),
            _event_errors(result.events, reference))


def _event_times(events):
    out = {}
    for event in events:
        out.setdefault((event.kind, event.name), []).append(event.time)
    return out


def _event_errors(events, reference):
    """Per reference event: |t - t_ref| / duration (inf if the run misses it). Against
    a numerical reference, events it does not have count as inf too."""
    duration = max(reference.t_end - reference.t_start, np.finfo(float).tiny)
    got = _event_times(events)
    out = []
    for key, expected in reference.events.items():
        found = got.get(key, [])
        for k in range(max(len(expected), len(found) if reference.kind == "numerical" else 0)):
            label = (key[1] if key[0] == "end" else f"{key[0]} {key[1]}") + (
                f" #{k + 1}" if k else "")
            error = (abs(found[k] - expected[k]) / duration
                     if k < len(found) and k < len(expected) else math.inf)
            out.append((label, error))
    if reference.kind == "numerical":
        out += [(f"{kind} {name} (not in reference)", math.inf)
                for (kind, name) in got if (kind, name) not in reference.events]
    return tuple(out)


# ------------------------------------------------------------------ references
def _reference(mech, scene, params, points, reference_rtol, check_rtol):
    closed, reason = _closed_form_reference(mech, scene, params, points)
    if closed is not None:
        return closed
    return _numerical_reference(mech, scene, params, points, reference_rtol, check_rtol,
                                reason)


def _scale(states):
    """Per state: the largest magnitude reached (1 where the state stays zero)."""
    scale = np.max(np.abs(states), axis=1)
    return np.where(scale > 0, scale, 1.0)


def _closed_form_reference(mech, scene, params, points):
    """A closed-form reference, or ``(None, why not)``."""
    from mechdyn.derive.closed_form import closed_form
    compiled = mech.compile(scene)
    try:
        solution = closed_form(mech, scene, params)
    except (MechdynError, NotImplementedError) as error:
        return None, f"no closed form: {error}"
    if not {"phi(t)", "omega(t)"} <= set(solution.relations):
        return None, ("the closed form gives no phi(t), omega(t) "
                      f"(only {', '.join(solution.relations)})")
    if [str(solution.q)] != list(compiled.coordinates):
        return None, "the closed form is in another coordinate than the simulation"
    stops = {repr(c) for c in scene.until}
    stop = solution.stop
    if stop is not None and stop.label not in stops:
        return None, (f"the closed form ends at {stop.label} (t = {float(stop.t):.6g} s) "
                      "but the scene goes on")
    phi_t, omega_t = solution.function("phi(t)"), solution.function("omega(t)")

    def states(times):
        times = np.asarray(times, dtype=float)
        return np.vstack([phi_t(times), omega_t(times)]).astype(float)

    t_start = float(scene.t_start)
    t_end = float(stop.t) if stop is not None else float(scene.time_limit)
    events = {("end", stop.label): [t_end]} if stop is not None else {}
    scale = _scale(states(np.linspace(t_start, t_end, points)))
    return Reference("closed form", f"closed form ({solution.classification})", None,
                     t_start, t_end, events, scale, states, tuple(solution.notes)), ""


def _numerical_reference(mech, scene, params, points, reference_rtol, check_rtol, why):
    """DOP853 at ``reference_rtol``, checked by Radau at ``check_rtol``."""
    results, failures = {}, []
    for method, rtol in (("DOP853", reference_rtol), ("Radau", check_rtol)):
        try:
            results[method] = mech.simulate(_scaled(scene, rtol, method=method), params)
        except SimulationError as error:
            failures.append(f"{method} at rtol {rtol:.0e} failed: {error}")
    if not results:
        raise SimulationError("work_precision: no reference solution: " +
                              "; ".join(failures))
    method, primary = next(iter(results.items()))
    trajectory = primary.trajectory

    def states(times):
        return trajectory.at(times)

    t_start, t_end = float(primary.t[0]), float(primary.t[-1])
    scale = _scale(states(np.linspace(t_start, t_end, points)))
    reference = Reference("numerical", "", None, t_start, t_end,
                          _event_times(primary.events), scale, states,
                          (why,) + tuple(failures))
    rtol = reference_rtol if method == "DOP853" else check_rtol
    description = f"{method} ({'+'.join(primary.stats['backends'])}) at rtol {rtol:.0e}"
    if len(results) == 2:
        final, l2, events = _errors(results["Radau"], reference, points)
        agreement = max([final, l2] + [e for _, e in events])
        description += (f"; Radau at rtol {check_rtol:.0e} agrees to {agreement:.1e} "
                        "(rows below that are not verified)")
        return replace(reference, description=description, agreement=agreement)
    return replace(reference, description=description + " (unchecked: the implicit "
                   "check failed)")

"""Stepping with scipy's solvers: one segment at a time, events located on each step.

A :class:`ScipySegment` drives one of scipy's solver classes (``RK45``, ``RK23``,
``DOP853``, ``Radau``, ``BDF``, ``LSODA``) step by step. After each accepted step it turns
the step's interpolant into the polynomial form of :mod:`mechdyn.simulate.trajectory`, records the
step, and looks for events on it (:class:`~mechdyn.simulate.events.EventWatch`); it returns at the
first event, when the segment ends, when stiffness is detected, when the solver fails, or
after a given number of steps (so the caller can report progress and keep a budget).

>>> import numpy as np
>>> from mechdyn.simulate.trajectory import Segment
>>> segment = Segment(0.0, [1.0], mode=(), method="DOP853")
>>> run = ScipySegment("DOP853", lambda t, y: -y, None, 0.0, np.ones(1), 1.0, 1e-10, 1e-12,
...                    segment)
>>> outcome = run.advance(10_000)
>>> outcome.status, round(float(outcome.y[0]), 10)
('finished', 0.3678794412)
"""
from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import numpy as np

__all__ = ["METHODS", "WITH_JACOBIAN", "EXPLICIT", "ScipySegment", "Outcome",
           "step_polynomial"]

METHODS = ("RK45", "RK23", "DOP853", "Radau", "BDF", "LSODA")    # scipy's solver classes
WITH_JACOBIAN = {"Radau", "BDF", "LSODA"}
EXPLICIT = {"RK45", "RK23", "DOP853"}


def _solver_class(method):
    """scipy's solver class of ``method``; explicit ones with mechdyn's error control.
    Imported here, not at the top: a run on the compiled kernels needs no scipy.integrate
    (a third of a second of a fresh process)."""
    if method in EXPLICIT:
        from mechdyn.simulate.error_control import guarded
        return guarded(method)
    import scipy.integrate
    return getattr(scipy.integrate, method)


@dataclass
class Outcome:
    """How an :meth:`ScipySegment.advance` call ended.

    ``status``: ``"finished"`` (reached the segment's end), ``"event"`` (``fired`` lists
    the indices of the events at ``t``), ``"chunk"`` (the step allowance is used up),
    ``"stiff"`` (the stiffness monitor says the method no longer fits), ``"drift"`` (the
    state left its constraints), ``"failed"`` (``message`` says why). ``t``, ``y`` the state where it ended."""
    status: str
    t: float
    y: np.ndarray
    fired: list = field(default_factory=list)
    message: str = ""


class ScipySegment:
    """One segment integrated by a scipy solver class.

    ``fun(t, y)`` and ``jac(t, y)`` in solve_ivp's form; ``segment`` the
    :class:`~mechdyn.simulate.trajectory.Segment` the steps are recorded into; ``watch`` an
    :class:`~mechdyn.simulate.events.EventWatch` or None; ``monitor(t, y, h)`` a stiffness test
    called after each step (true: stop with status ``"stiff"``) or None. Ten steps in a
    row shorter than ``min_step`` are a collapse (status ``"failed"``): the solution runs
    into a singularity, or the method cannot cope. ``drift(t, y)``: true when the state
    has left its constraints too far (status ``"drift"``: the caller projects it back).
    The explicit methods take mechdyn's error control
    (:mod:`mechdyn.simulate.error_control`; ``revolving``: the states weighed on one
    revolution).
    """

    def __init__(self, method, fun, jac, t0, y0, t_bound, rtol, atol, segment, watch=None,
                 monitor=None, first_step=None, max_step=np.inf, min_step=0.0, drift=None,
                 revolving=()):
        options = {"rtol": rtol, "atol": atol, "max_step": max_step}
        solver_class = _solver_class(method)     # scipy.integrate: imported when used
        if method in EXPLICIT:
            options["revolving"] = revolving
        if first_step:
            options["first_step"] = min(first_step, abs(t_bound - t0))
        if jac is not None and method in WITH_JACOBIAN:
            options["jac"] = jac
        self.method, self.segment, self.watch, self.monitor = method, segment, watch, monitor
        self.min_step, self.short, self.drift = min_step, 0, drift
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            self.solver = solver_class(fun, t0, np.array(y0, dtype=float), t_bound,
                                       **options)
        self.steps = 0
        if watch is not None:
            watch.start(t0, np.array(y0, dtype=float))

    def hold_switching(self):
        """Keep the method whatever the stiffness monitor says; returns the function that
        lets it act again."""
        monitor, self.monitor = self.monitor, None

        def release():
            self.monitor = monitor
        return release

    @property
    def h(self) -> float:
        """The size of the last step taken (the next segment's first step)."""
        return self.solver.t - self.solver.t_old if self.solver.t_old is not None else 0.0

    @property
    def counts(self) -> dict:
        s = self.solver
        return {"steps": self.steps, "nfev": s.nfev, "njev": getattr(s, "njev", 0),
                "nlu": getattr(s, "nlu", 0)}

    def advance(self, max_steps) -> Outcome:
        """Take up to ``max_steps`` steps; see :class:`Outcome`."""
        solver = self.solver
        for _ in range(max_steps):
            if solver.status != "running":
                return Outcome("finished", solver.t, solver.y)
            t_old, y_old = solver.t, solver.y
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                try:
                    message = solver.step()
                except (ArithmeticError, ValueError, np.linalg.LinAlgError) as error:
                    return Outcome("failed", t_old, y_old, message="the solver's linear "
                                   f"algebra overflowed ({error})")
            if solver.status == "failed":
                return Outcome("failed", t_old, y_old, message=str(message or "step failed"))
            if not np.all(np.isfinite(solver.y)):       # a solver that accepted NaN
                return Outcome("failed", t_old, y_old, message="the state became non-finite")
            self.steps += 1
            coefficients = step_polynomial(solver.dense_output())
            if self.watch is not None:
                fired = self.watch.check(t_old, solver.t, solver.y, coefficients)
                if fired is not None:
                    t_event, y_event, indices = fired
                    self._record_part(t_old, t_event, y_event, coefficients)
                    return Outcome("event", t_event, y_event, indices)
            self.segment.add(solver.t, solver.y, coefficients)
            self.short = self.short + 1 if self.h < self.min_step else 0
            if self.short >= 10 and solver.status == "running":
                return Outcome("failed", solver.t, solver.y,
                               message=f"the step size collapsed to {self.h:.3g} s")
            if self.drift is not None and self.drift(solver.t, solver.y):
                return Outcome("drift", solver.t, solver.y)
            if self.monitor is not None and self.monitor(solver.t, solver.y, self.h):
                return Outcome("stiff", solver.t, solver.y)
        if solver.status != "running":
            return Outcome("finished", solver.t, solver.y)
        return Outcome("chunk", solver.t, solver.y)

    def _record_part(self, t_old, t_event, y_event, coefficients):
        """Record the step cut at the event: its polynomial rescaled to [t_old, t_event]."""
        h = self.solver.t - t_old
        fraction = (t_event - t_old) / h if h else 0.0
        scaled = coefficients * fraction ** np.arange(len(coefficients))[:, None]
        self.segment.add(t_event, y_event, scaled)


# --------------------------------------------------------- dense output as polynomials
# scipy's DenseOutput has a public call, but the polynomial behind it is kept in fields
# of each subclass that are its internals (RkDenseOutput.Q, Dop853DenseOutput.F, ...).
# No public API gives the coefficients, so they are read here; a scipy without one of
# them is a DependencyError naming it, and tests/test_third_party_internals.py checks,
# for each method, that the polynomial read matches the solver's own dense output.
_DENSE_FIELDS = {"ConstantDenseOutput": ("value",), "RkDenseOutput": ("y_old", "Q"),
                 "RadauDenseOutput": ("y_old", "Q"), "Dop853DenseOutput": ("y_old", "F"),
                 "BdfDenseOutput": ("D", "t_shift", "denom"),
                 "LsodaDenseOutput": ("h", "yh")}


def step_polynomial(dense) -> np.ndarray:
    """Coefficients ``(d + 1, n)`` of ``y(x) = sum_j c_j x^j``, ``x = (t - t_old)/h``,
    of the interpolant of one step of a scipy solver (exact re-expansions of each
    solver's own form)."""
    name = type(dense).__name__
    fields = _DENSE_FIELDS.get(name, ())
    missing = [f"{name}.{field}" for field in fields if not hasattr(dense, field)]
    if missing or not fields:
        from mechdyn.errors import DependencyError
        raise DependencyError("scipy", missing[0] if missing else f"dense output mechdyn "
                              f"knows (its solver gave a {name})",
                              "turning a solver's steps into mechdyn's trajectories")
    if name == "ConstantDenseOutput":
        return np.asarray(dense.value, dtype=float)[None, :]
    H = dense.t - dense.t_old
    if name == "RkDenseOutput":
        return np.vstack([dense.y_old, H * dense.Q.T])
    if name == "RadauDenseOutput":
        return np.vstack([dense.y_old, dense.Q.T])
    if name == "Dop853DenseOutput":
        poly = np.zeros((1, len(dense.y_old)))
        for i, f in enumerate(reversed(dense.F)):
            poly[0] += f
            poly = _times_linear(poly, 0.0, 1.0) if i % 2 == 0 else _times_linear(poly, 1.0, -1.0)
        poly[0] += dense.y_old
        return poly
    if name == "BdfDenseOutput":
        n = dense.D.shape[1]
        poly = np.vstack([dense.D[0], np.zeros((0, n))])
        product = np.ones((1, 1))
        for shift, denom, d in zip(dense.t_shift, dense.denom, dense.D[1:]):
            product = _times_linear(product, (dense.t_old - shift) / denom, H / denom)
            poly = _add(poly, product * d)
        return poly
    if name == "LsodaDenseOutput":
        ratio = H / dense.h
        poly = np.zeros((1, dense.yh.shape[0]))
        power = np.ones((1, 1))
        for j in range(dense.yh.shape[1]):
            poly = _add(poly, power * dense.yh[:, j])
            power = _times_linear(power, -ratio, ratio)
        return poly
    raise AssertionError(name)  # pragma: no cover - every name in _DENSE_FIELDS is handled


def _times_linear(poly, a, b):
    """``poly(x) * (a + b x)`` for coefficient rows ``poly[j]`` of ``x^j``."""
    out = np.zeros((len(poly) + 1, poly.shape[1]))
    out[:-1] += a * poly
    out[1:] += b * poly
    return out


def _add(p, q):
    if len(p) < len(q):
        p, q = q, p
    out = p.copy()
    out[:len(q)] = out[:len(q)] + q
    return out

"""Stepping: scipy's solvers driven step by step, each accepted step handed to a callback.

The explicit Dormand-Prince methods (``DOP853``, ``RK45``) with a scalar ``atol`` run in
scipy's Fortran back end (``scipy.integrate.ode``: Hairer's DOP853 and DOPRI5), which calls
back after every accepted step: about 4x less overhead per step than scipy's Python
solver classes, which drive every other case. A step's dense output is rebuilt on demand
by replaying the step with the Python class of the same method (:func:`replay`), so runs
keep only their step points and interpolate anywhere later.

>>> import numpy as np
>>> seen = []
>>> status, _, t, y, counts = run_steps("DOP853", lambda t, y: -y, None, 0.0, np.ones(1),
...                                     1.0, 1e-10, 1e-12, lambda *step: seen.append(step[2]))
>>> status, round(float(y[0]), 10), counts["steps"] == len(seen)
('finished', 0.3678794412, True)
"""
from __future__ import annotations

import threading
import warnings

import numpy as np
from scipy.integrate import BDF, DOP853, LSODA, RK23, RK45, Radau, ode

__all__ = ["METHODS", "run_steps", "replay"]

METHODS = {"RK45": RK45, "RK23": RK23, "DOP853": DOP853, "Radau": Radau, "BDF": BDF,
           "LSODA": LSODA}
WITH_JACOBIAN = {"Radau", "BDF", "LSODA"}
_FORTRAN = {"DOP853": "dop853", "RK45": "dopri5"}
_FORTRAN_LOCK = threading.Lock()     # Hairer's codes keep state between calls
_MAX_STEPS = 2_000_000_000


def run_steps(method, fun, jac, t0, y0, t_bound, rtol, atol, on_step):
    """Integrate from ``t0`` towards ``t_bound``.

    After each accepted step ``on_step(t_old, y_old, t, y, dense)`` is called, where
    ``dense()`` returns the step's interpolant; a true return value stops the run.
    Returns ``(status, message, t, y, counts)``: status ``"finished"``, ``"stopped"`` or
    ``"failed"``; counts ``steps``, ``nfev``, ``njev``, ``nlu``.
    """
    if method in _FORTRAN and np.ndim(atol) == 0:
        return _run_fortran(method, fun, t0, y0, t_bound, rtol, atol, on_step)
    return _run_python(method, fun, jac, t0, y0, t_bound, rtol, atol, on_step)


def replay(method, fun, jac, t_old, y_old, t_new, rtol, atol):
    """The interpolant over ``[t_old, t_new]``, from the Python solver class of ``method``
    started at ``(t_old, y_old)`` with the step ``t_new - t_old`` (if it rejects that step
    it takes several, and the interpolant covers them all)."""
    options = {"rtol": rtol, "atol": atol, "first_step": t_new - t_old}
    if jac is not None and method in WITH_JACOBIAN:
        options["jac"] = jac
    solver = METHODS[method](fun, t_old, np.array(y_old, dtype=float), t_new, **options)
    pieces = []
    while solver.status == "running":
        solver.step()
        if solver.status == "failed":
            break
        pieces.append((solver.t, solver.dense_output()))
    return _Pieces(pieces)


class _Pieces:
    """Interpolants of consecutive sub-steps, called like one."""

    def __init__(self, pieces):
        self.ends = [end for end, _ in pieces]
        self.interpolants = [interpolant for _, interpolant in pieces]

    def __call__(self, t):
        k = min(int(np.searchsorted(self.ends, t, side="left")), len(self.ends) - 1)
        return self.interpolants[k](t)


def _run_python(method, fun, jac, t0, y0, t_bound, rtol, atol, on_step):
    options = {"rtol": rtol, "atol": atol}
    if jac is not None and method in WITH_JACOBIAN:
        options["jac"] = jac
    solver = METHODS[method](fun, t0, np.array(y0, dtype=float), t_bound, **options)
    status, message, steps = "finished", "", 0
    while solver.status == "running":
        t_old, y_old = solver.t, solver.y
        message = solver.step() or ""
        if solver.status == "failed":
            status = "failed"
            break
        steps += 1
        if on_step(t_old, y_old, solver.t, solver.y, solver.dense_output):
            status = "stopped"
            break
    counts = {"steps": steps, "nfev": solver.nfev, "njev": getattr(solver, "njev", 0),
              "nlu": getattr(solver, "nlu", 0)}
    return status, message, solver.t, solver.y, counts


def _run_fortran(method, fun, t0, y0, t_bound, rtol, atol, on_step):
    integrator = ode(fun).set_integrator(_FORTRAN[method], rtol=rtol, atol=atol,
                                         nsteps=_MAX_STEPS)
    previous = {"t": t0, "y": np.array(y0, dtype=float), "steps": 0}
    outcome = {"stopped": False, "error": None}

    def solout(t, y):
        if t == previous["t"]:
            return 0                       # the call at the start point
        y = np.array(y)                    # the Fortran buffer is reused
        t_old, y_old = previous["t"], previous["y"]

        def dense():
            return replay(method, fun, None, t_old, y_old, t, rtol, atol)
        try:
            stop = on_step(t_old, y_old, t, y, dense)
        except BaseException as error:     # re-raised after the Fortran code returns
            outcome["error"] = error
            return -1
        previous.update(t=t, y=y, steps=previous["steps"] + 1)
        if stop:
            outcome["stopped"] = True
            return -1
        return 0

    integrator.set_solout(solout)
    integrator.set_initial_value(np.array(y0, dtype=float), t0)
    with _FORTRAN_LOCK, warnings.catch_warnings():
        warnings.simplefilter("ignore")
        integrator.integrate(t_bound)
    if outcome["error"] is not None:
        raise outcome["error"]
    backend = integrator._integrator
    counts = {"steps": previous["steps"], "nfev": int(backend.iwork[16]), "njev": 0, "nlu": 0}
    istate = backend.istate
    if outcome["stopped"]:
        return "stopped", "", previous["t"], previous["y"], counts
    if istate < 0:
        message = backend.messages.get(istate, f"error code {istate}")
        return "failed", message, previous["t"], previous["y"], counts
    return "finished", "", previous["t"], previous["y"], counts

"""One run of a scene with its sensitivities, to the first stop condition or the time
limit: on the compiled kernels' DOP853 (numba functions of
:mod:`mechdyn.compile.sensitivity_kernel`) or on scipy's ``solve_ivp`` (lambdified
functions of :mod:`mechdyn.compile.sensitivity_code`), both at the scene's tolerances.

Returns ``(t_end, z_end, stop)``: the end time, the state with its sensitivities there,
and the index of the stop condition met (None at the time limit). A friction element
whose sliding rate reaches zero before the run ends is a mode change the sensitivities
do not follow: :class:`SensitivityError`.
"""
from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp

from mechdyn.errors import SceneError, SimulationError

__all__ = ["integrate", "SensitivityError"]

_CHUNK = 100_000


class SensitivityError(SceneError):
    """Sensitivities that cannot be derived: an unknown measure or parameter, or a
    scene whose run changes mode (friction sticking or reversing, stops, loops)."""


def integrate(prepared, scene, frictions, z0, p, kernel=None) -> tuple:
    """``prepared``: ``(system, order, stop functions, rate functions)``; ``kernel``:
    :class:`~mechdyn.compile.sensitivity_kernel.KernelFunctions` or None (scipy)."""
    if kernel is not None:
        return _on_kernel(prepared, scene, frictions, z0, p, kernel)
    return _on_scipy(prepared, scene, frictions, z0, p)


def _atol(scene):
    return scene.atol if isinstance(scene.atol, float) else 1e-12


def _on_kernel(prepared, scene, frictions, z0, p, kernel):
    from mechdyn.kernels import CHUNK_FULL, DOP853, EVENT, FINISHED, Integration
    from mechdyn.kernels.layout import STATUS_NAMES
    stops, n_stops = prepared[2], len(scene.until)
    directions = [c.direction for c in scene.until] + [0] * len(frictions)
    run = Integration(kernel.model, p, scene.t_start, z0, method=DOP853, rtol=scene.rtol,
                      atol=_atol(scene), directions=directions, detect_switch=False,
                      dense=False)
    while True:
        chunk = run.advance(scene.time_limit, _CHUNK)
        if chunk.status == CHUNK_FULL:
            continue
        if chunk.status == FINISHED:
            return run.t, run.y, None
        if chunk.status != EVENT:
            raise SimulationError(f"scene {scene.name!r}: the sensitivity integration "
                                  f"stopped at t = {run.t:.6g} s: "
                                  f"{STATUS_NAMES[chunk.status]}")
        fired = [int(i) for i in np.flatnonzero(chunk.fired)]
        met = [i for i in fired if i < n_stops] or _stops_at(stops, prepared[0], run, p)
        if met:
            return run.t, run.y, met[0]
        _refuse(scene, frictions[fired[0] - n_stops], run.t)


def _stops_at(stops, system, run, p) -> list:
    """The stop conditions that a friction event met within rounding (the same root
    located a few units of rounding apart): a linear estimate of their time to zero."""
    size = _state_size(system)
    z = run.y
    slope = system.rhs(run.t, z, p)[:size]
    met = []
    for i, stop in enumerate(stops):
        g, g_y, g_t, _ = stop(run.t, z[:size], p)
        rate = g_y @ slope + g_t
        if rate != 0 and abs(g / rate) <= 1e-9 * max(1.0, abs(run.t)):
            met.append(i)
    return met


def _state_size(system) -> int:
    return 2 * system.n


def _on_scipy(prepared, scene, frictions, z0, p):
    system, _, stops, rates = prepared
    size = _state_size(system)

    def event(function, terminal, direction):
        def g(t, z, pp):
            return function(t, z[:size], pp)[0]
        g.terminal, g.direction = terminal, direction
        return g
    events = [event(f, True, c.direction) for f, c in zip(stops, scene.until)]
    events += [event(f, False, 0) for f in rates]
    try:
        sol = solve_ivp(system.rhs, (scene.t_start, scene.time_limit), z0, method="DOP853",
                        rtol=scene.rtol, atol=_atol(scene), events=events or None,
                        args=(p,))
    except (ArithmeticError, ValueError, np.linalg.LinAlgError) as error:
        raise SimulationError(f"scene {scene.name!r}: the sensitivity integration failed: "
                              f"{type(error).__name__}: {error}") from error
    if sol.status == -1:
        raise SimulationError(f"scene {scene.name!r}: the sensitivity integration failed "
                              f"at t = {sol.t[-1]:.6g} s: {sol.message}")
    t_end, z_end, stop = sol.t[-1], sol.y[:, -1], None
    stopped = [i for i in range(len(stops)) if len(sol.t_events[i])]
    if stopped:
        stop = min(stopped, key=lambda j: sol.t_events[j][0])
        t_end, z_end = sol.t_events[stop][0], sol.y_events[stop][0]
    for j, friction in enumerate(frictions):
        early = [x for x in sol.t_events[len(stops) + j]
                 if x < t_end - 1e-9 * max(1.0, abs(t_end))]
        if early:
            _refuse(scene, friction, early[0], t_end)
    return t_end, z_end, stop


def _refuse(scene, friction, time, t_end=None):
    end = f", before the run ends (t = {t_end:.6g} s)" if t_end is not None else \
        ", before the run ends"
    raise SensitivityError(f"scene {scene.name!r}: friction {friction.name!r} stops "
                           f"sliding at t = {time:.6g} s{end}; sensitivities across a "
                           "friction mode change are not derived")

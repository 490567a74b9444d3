"""One run of a scene with its sensitivities, to the first stop condition or the time
limit: on the compiled kernels' DOP853 (numba functions of
:mod:`mechdyn.compile.sensitivity_kernel`) or on scipy's ``solve_ivp`` (lambdified
functions of :mod:`mechdyn.compile.sensitivity_code`), both at the scene's tolerances.

A friction element whose sliding speed reaches zero slides on the other way where even
its static peak cannot hold it (the rate still moves that way); the sensitivities jump
there, ``S+ = S- + (f- - f+) dt*/dp`` with ``dt*/dp = -(g_y S- + g_p) / (g_y f-)``
(``g`` its sliding speed). One that would stick is a mode change the sensitivities do
not follow: :class:`SensitivityError`.
"""
from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp

from mechdyn.errors import SceneError, SimulationError

__all__ = ["integrate", "SensitivityError"]

_CHUNK = 100_000


class SensitivityError(SceneError):
    """Sensitivities that cannot be derived: an unknown measure or parameter, or a
    scene whose run changes mode (friction sticking, stops, loops).

    Examples
    --------
    >>> import mechdyn as md
    >>> brake = md.load_model("shoe_brake")
    >>> try:
    ...     md.sensitivities(brake.mechanism, brake.scenes["braking"], brake.params,
    ...                      wrt=["P"], measures=["stop_time"])
    ... except md.SensitivityError as error:
    ...     print(type(error).__name__)
    SensitivityError
    """


def integrate(segment, scene, frictions, peaks, signs, z0) -> tuple:
    """Run from ``z0`` with the frictions sliding the ways ``signs`` say, through every
    reversal, to a stop condition or the time limit. ``segment(signs)`` gives
    ``(prepared, kernel, p)`` of one mode: ``prepared`` = ``(system, order, stop
    functions, rate functions)``, ``kernel`` the compiled functions or None (scipy).
    Returns ``(t_end, z_end, stop, prepared, p)``, ``stop`` the index of the stop
    condition met (None at the time limit), ``prepared`` and ``p`` of the last mode."""
    t0, signs = scene.t_start, tuple(signs)
    while True:
        prepared, kernel, p = segment(signs)
        run = _on_kernel if kernel is not None else _on_scipy
        t, z, stop, slid = run(prepared, kernel, scene, signs, t0, z0, p)
        if slid is None:
            return t, z, stop, prepared, p
        z0, signs = _reversed(segment, prepared, p, scene, frictions, peaks, signs, slid, t, z)
        t0 = t


def _reversed(segment, prepared, p, scene, frictions, peaks, signs, j, t, z) -> tuple:
    """Friction ``j`` reaches zero sliding speed at ``(t, z)``: the state with the
    sensitivities' jump and the new signs, or :class:`SensitivityError` if it sticks."""
    system, _, _, rates = prepared
    size = 2 * system.n
    new = list(signs)
    new[j] = -signs[j]
    holding = list(new)
    holding[j] = new[j] * peaks[j]                 # its static peak, against the new way
    hold_system, _, _, _ = segment(tuple(holding))[0]
    _, g_y, g_t, g_p = rates[j](t, z[:size], p)
    if not (g_y @ hold_system.rhs(t, z, p)[:size] + g_t) * new[j] > 0:
        _refuse(scene, frictions[j], t)
    before = system.rhs(t, z, p)[:size]
    s = z[size:].reshape(size, -1)
    dt = -(g_y @ s + g_p) / (g_y @ before + g_t)
    after_prepared, _, after_p = segment(tuple(new))
    after = after_prepared[0].rhs(t, z, after_p)[:size]
    jumped = s + np.outer(before - after, dt)
    return np.concatenate([z[:size], jumped.ravel()]), tuple(new)


def _atol(scene):
    return scene.atol if isinstance(scene.atol, float) else 1e-12


def _on_kernel(prepared, kernel, scene, signs, t0, z0, p):
    """``(t, z, stop, slid)``: the end, the stop condition met and the friction element
    whose sliding speed reached zero (each None if not)."""
    from mechdyn.kernels import CHUNK_FULL, DOP853, EVENT, FINISHED, Integration
    from mechdyn.kernels.layout import STATUS_NAMES
    stops, n_stops = prepared[2], len(scene.until)
    directions = [c.direction for c in scene.until] + [-s for s in signs]
    run = Integration(kernel.model, p, t0, z0, method=DOP853, rtol=scene.rtol,
                      atol=_atol(scene), directions=directions, detect_switch=False,
                      dense=False)
    while True:
        chunk = run.advance(scene.time_limit, _CHUNK)
        if chunk.status == CHUNK_FULL:
            continue
        if chunk.status == FINISHED:
            return run.t, run.y, None, None
        if chunk.status != EVENT:
            raise SimulationError(f"scene {scene.name!r}: the sensitivity integration "
                                  f"stopped at t = {run.t:.6g} s: "
                                  f"{STATUS_NAMES[chunk.status]}")
        fired = [int(i) for i in np.flatnonzero(chunk.fired)]
        met = [i for i in fired if i < n_stops] or \
            _stops_at(stops, prepared[0], run.t, run.y, p)
        if met:
            return run.t, run.y, met[0], None
        return run.t, run.y, None, fired[0] - n_stops


def _stops_at(stops, system, t, z, p) -> list:
    """The stop conditions that a friction event met within rounding (the same root
    located a few units of rounding apart): a linear estimate of their time to zero."""
    size = 2 * system.n
    slope = system.rhs(t, z, p)[:size]
    met = []
    for i, stop in enumerate(stops):
        g, g_y, g_t, _ = stop(t, z[:size], p)
        rate = g_y @ slope + g_t
        if rate != 0 and abs(g / rate) <= 1e-9 * max(1.0, abs(t)):
            met.append(i)
    return met


def _on_scipy(prepared, kernel, scene, signs, t0, z0, p):
    system, _, stops, rates = prepared
    size = 2 * system.n

    def event(function, direction):
        def g(t, z, pp):
            return function(t, z[:size], pp)[0]
        g.terminal, g.direction = True, direction
        return g
    events = [event(f, c.direction) for f, c in zip(stops, scene.until)]
    events += [event(f, -s) for f, s in zip(rates, signs)]
    try:
        sol = solve_ivp(system.rhs, (t0, scene.time_limit), z0, method="DOP853",
                        rtol=scene.rtol, atol=_atol(scene), events=events or None,
                        args=(p,))
    except (ArithmeticError, ValueError, np.linalg.LinAlgError) as error:
        raise SimulationError(f"scene {scene.name!r}: the sensitivity integration failed: "
                              f"{type(error).__name__}: {error}") from error
    if sol.status == -1:
        raise SimulationError(f"scene {scene.name!r}: the sensitivity integration failed "
                              f"at t = {sol.t[-1]:.6g} s: {sol.message}")
    fired = [i for i in range(len(events)) if len(sol.t_events[i])]
    if not fired:
        return sol.t[-1], sol.y[:, -1], None, None
    first = min(sol.t_events[i][0] for i in fired)
    i = min(i for i in fired if sol.t_events[i][0] <= first + 1e-9 * max(1.0, abs(first)))
    t, z = sol.t_events[i][0], sol.y_events[i][0]
    met = [i] if i < len(stops) else _stops_at(stops, system, t, z, p)
    if met:
        return t, z, met[0], None
    return t, z, None, i - len(stops)


def _refuse(scene, friction, time):
    raise SensitivityError(f"scene {scene.name!r}: friction {friction.name!r} sticks at "
                           f"t = {time:.6g} s, before the run ends; sensitivities through "
                           "sticking are not derived")

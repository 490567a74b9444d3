"""Assembling closed loops: positions by Newton's method, speeds by the velocity equation.

A scene of a linkage gives the independent coordinates (a crank angle) and their speeds,
and a *guess* for each dependent coordinate, which picks the assembly branch (a four-bar
assembles open or crossed). Newton's method with the analytic constraint Jacobian solves
``g(q, t) = 0`` for the dependent coordinates; ``G u = -dg/dt`` gives their speeds.
:func:`project` pulls a state that has drifted back onto the loops (least change).

>>> import sympy as sp, mechdyn as md
>>> phi, x = md.coordinates("phi x")
>>> crank = md.Mechanism("slider on a crank", [phi, x])
>>> _ = crank.link("crank", J=1, angle=phi)
>>> _ = crank.link("slider", m=1, x=x)
>>> _ = crank.constraint("rod", (x - sp.cos(phi)) ** 2 + sp.sin(phi) ** 2 - 4)
>>> scene = md.Scene("run", initial={phi: 0, md.speed(phi): 1, x: 2.5}, t_end=1)
>>> from mechdyn.simulate.simulation import initial_state
>>> [round(float(v), 12) + 0.0 for v in initial_state(crank.compile(scene), crank, scene, {})]
[0.0, 3.0, 1.0, 0.0]
"""
from __future__ import annotations

import numpy as np

from mechdyn.errors import SceneError

__all__ = ["AssemblyError", "assemble", "solve_positions", "project", "closure_parts"]

_NEWTON_STEPS = 60
_TOLERANCE = 1e-13        # |g| relative to the coordinates' scale
_SPEED_AGREEMENT = 1e-8   # given dependent speeds must agree with the loops this well


class AssemblyError(SceneError):
    """The loops cannot be closed at the given independent coordinates (links that do
    not reach), or close only at a toggle position. ``independent``: the values of the
    independent coordinates by name.

    Examples
    --------
    A triple rocker (ground 2, crank 3, coupler 3.5, rocker 5) does not close at
    ``phi = 0`` (its crank reaches only 0.46 rad to ``2 pi - 0.46`` rad):

    >>> import mechdyn as md
    >>> phi, th2, th3 = md.coordinates("phi theta_2 theta_3")
    >>> rocker = md.Mechanism("triple rocker", [phi, th2, th3])
    >>> _ = rocker.link("crank", J=1, angle=phi)
    >>> _ = rocker.link("coupler", J=1, angle=th2)
    >>> _ = rocker.link("rocker", J=1, angle=th3)
    >>> _ = rocker.loop("ABCD", (3, phi), (3.5, th2), (-5, th3), (-2, 0))
    >>> start = md.Scene("start", initial={phi: 0, th2: 0.5, th3: 1, md.speed(phi): 1},
    ...                  t_end=1, backend="scipy")
    >>> try:
    ...     rocker.simulate(start)
    ... except md.AssemblyError as error:
    ...     print(type(error).__name__, error.independent)
    AssemblyError {'phi': 0.0}
    """

    def __init__(self, message, independent=None):
        super().__init__(message)
        self.independent = dict(independent or {})


def closure_parts(compiled, t, y, p):
    """``(g, G, dg/dt, bias)`` of the loops at the state ``y`` (numpy arrays)."""
    n, m = compiled.dof, len(compiled.constraints)
    v = np.asarray(compiled.closure(t, y, p), dtype=float)
    return v[:m], v[m:m + m * n].reshape(m, n), v[m + m * n:2 * m + m * n], v[2 * m + m * n:]


def solve_positions(compiled, t, y, p, where=""):
    """Close the loops by moving the dependent coordinates of ``y`` (Newton's method,
    analytic Jacobian, halving steps that do not reduce ``|g|``). Returns the new state;
    raises :class:`AssemblyError` naming the independent coordinates."""
    y = np.array(y, dtype=float)
    n = compiled.dof
    dependent = [i for i in range(n) if i not in compiled.independent]
    scale = 1.0 + float(np.max(np.abs(y[:n]), initial=0.0))
    g, grads, _, _ = closure_parts(compiled, t, y, p)
    norm = float(np.max(np.abs(g), initial=0.0))
    for _ in range(_NEWTON_STEPS):
        if norm <= _TOLERANCE * scale:
            break
        jacobian = grads[:, dependent]
        step = np.linalg.lstsq(jacobian, -g, rcond=None)[0]
        for _ in range(30):                    # damped: halve until |g| decreases
            trial = y.copy()
            trial[dependent] += step
            g_trial, grads_trial, _, _ = closure_parts(compiled, t, trial, p)
            trial_norm = float(np.max(np.abs(g_trial), initial=0.0))
            if np.isfinite(trial_norm) and trial_norm < norm:
                break
            step = step / 2
        else:
            break
        y, g, grads, norm = trial, g_trial, grads_trial, trial_norm
    if not norm <= _TOLERANCE * scale * 1e3:
        worst = compiled.constraints[int(np.argmax(np.abs(g)))]
        raise AssemblyError(
            f"{where}the loops cannot be closed at {_independent_text(compiled, y)}: "
            f"constraint {worst} stays at {np.max(np.abs(g)):.3g} after Newton's method "
            "from the guesses (the links do not reach there, or the guesses are too far "
            "off)", _independent_values(compiled, y))
    _check_regular(compiled, grads[:, dependent], y, where)
    return y


def _check_regular(compiled, jacobian, y, where):
    singular = np.linalg.svd(jacobian, compute_uv=False)
    if singular[-1] <= 1e-9 * max(singular[0], 1e-300):
        raise AssemblyError(
            f"{where}the loops close at a toggle (dead-centre) position at "
            f"{_independent_text(compiled, y)}: the dependent coordinates are not "
            "determined by the independent ones there; start elsewhere",
            _independent_values(compiled, y))


def solve_speeds(compiled, t, y, p):
    """The dependent speeds from ``G u + dg/dt = 0`` with the independent speeds kept."""
    y = np.array(y, dtype=float)
    n = compiled.dof
    dependent = [i for i in range(n) if i not in compiled.independent]
    independent = list(compiled.independent)
    _, grads, rate_t, _ = closure_parts(compiled, t, y, p)
    rhs = -rate_t - grads[:, independent] @ y[[n + i for i in independent]]
    y[[n + i for i in dependent]] = np.linalg.solve(grads[:, dependent], rhs)
    return y


def assemble(compiled, y0, p, t, scene_name, given_speeds=()):
    """The initial state: dependent positions closed, dependent speeds solved.

    ``y0`` holds the independent coordinates and speeds, guesses for the dependent
    coordinates and NaN (or given values) for the dependent speeds; ``given_speeds``:
    indices of dependent speeds the scene gave, checked against the loops."""
    where = f"scene {scene_name!r}: "
    given = {i: y0[i] for i in given_speeds}
    y = np.array(y0, dtype=float)
    n = compiled.dof
    y[n:][np.isnan(y[n:])] = 0.0
    y = solve_positions(compiled, t, y, p, where)
    y = solve_speeds(compiled, t, y, p)
    for i, value in given.items():
        if abs(value - y[i]) > _SPEED_AGREEMENT * (1.0 + abs(y[i])):
            raise SceneError(
                f"{where}the initial speed of {compiled.state_names[i]} = {value:.6g} "
                f"disagrees with the loops, which give {y[i]:.6g} at "
                f"{_independent_text(compiled, y)}; leave dependent speeds out (they are "
                "solved from the independent ones)")
    return y


def project(compiled, t, y, p):
    """The nearest state on the loops (least-squares change of all coordinates, then of
    all speeds): removes the drift of integrating ``G a = -bias``."""
    y = np.array(y, dtype=float)
    n = compiled.dof
    for _ in range(3):
        g, grads, _, _ = closure_parts(compiled, t, y, p)
        y[:n] -= np.linalg.lstsq(grads, g, rcond=None)[0]
    _, grads, rate_t, _ = closure_parts(compiled, t, y, p)
    y[n:] -= np.linalg.lstsq(grads, grads @ y[n:] + rate_t, rcond=None)[0]
    return y


def _independent_values(compiled, y):
    return {compiled.coordinates[i]: float(y[i]) for i in compiled.independent}


def _independent_text(compiled, y):
    return ", ".join(f"{name} = {value:.6g} ({np.degrees(value):.2f} deg)"
                     for name, value in _independent_values(compiled, y).items())


def manifold_jacobian(compiled, t, y, p):
    """The linearised motion the loops allow, for the choice of integrator: with the
    loops' speed basis ``S`` (``u = S u_i``), reduced mass ``S'MS``, stiffness
    ``-S' df/dq S`` and damping ``-S' df/du S`` (analytic derivatives), the matrix
    ``[[0, I], [-M_r^-1 K_r, -M_r^-1 C_r]]``. (The full Jacobian adds spurious
    eigenvalues along the constraints; the terms from the curvature of the loops are
    left out, they do not make a linkage stiff.)"""
    n, m = compiled.dof, len(compiled.constraints)
    grads = np.array(compiled.closure(t, y, p)[m:m + m * n]).reshape(m, n)
    independent = list(compiled.independent)
    dependent = [i for i in range(n) if i not in independent]
    k = len(independent)
    basis = np.zeros((n, k))
    basis[independent, range(k)] = 1.0
    basis[dependent] = -np.linalg.solve(grads[:, dependent], grads[:, independent])
    v = np.array(compiled.linear_terms(t, y, p)).reshape(3, n, n)
    mass = v[0]                                 # df/dq, df/du: generated column by column
    forces = np.hstack([basis.T @ v[1].T @ basis, basis.T @ v[2].T @ basis])
    out = np.zeros((2 * k, 2 * k))
    out[:k, k:] = np.eye(k)
    out[k:] = np.linalg.solve(basis.T @ mass @ basis, forces)   # stiffness, damping
    return out

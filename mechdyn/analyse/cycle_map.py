"""Steady running's cycle map: one cycle of a one-DOF machine in its crank angle,

    d omega/dphi = a / omega,   dt/dphi = 1 / omega,   dv/dphi = d(a/omega)/domega v,

from ``omega0`` at ``phi0`` (``a`` the angular acceleration of the compiled equations,
``v`` the derivative of ``omega`` by ``omega0``), with its dense output. It runs on the
compiled kernels' DOP853 where the scene runs there (numba installed, a compiled form
with its Jacobian, ``backend`` not "scipy": the backend rule of ``simulate``; a cycle
then costs about half a millisecond, the per-scene function compiled once per process
in about a second), else on scipy's DOP853 over the generated Python (a few
milliseconds). The machine stalling (``omega`` falling to ``1e-9 omega0``, or the
steps shrinking to nothing below 1 % of ``omega0``: ``omega ~ sqrt(phi_stop - phi)``)
ends the cycle with a :class:`~mechdyn.analyse.shooting.PeriodicError` saying so.
"""
from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp

from mechdyn.analyse.shooting import PeriodicError

__all__ = ["CycleMap", "RTOL", "ATOL"]

RTOL, ATOL = 1e-10, 1e-12
_CHUNK = 2048                 # kernel steps per call
_SLOW = 0.01                  # a failure below this share of omega0: a stall
_compiled_maps: dict = {}     # scene key -> the kernels' functions of its cycle map


class CycleMap:
    """``CycleMap(compiled, scene, p)(phi0, cycle, omega0)`` -> ``(omega(end), v(end),
    time(end), dense)``; ``dense(phi)`` is ``[omega, time, v]`` there, ``dense.ts`` the
    steps' angles."""

    def __init__(self, compiled, scene, p):
        self.functions = _kernel_functions(compiled) if scene.backend != "scipy" else None
        self.compiled, self.p = compiled, p

    def __call__(self, phi0, cycle, omega0) -> tuple:
        run = self._on_kernels if self.functions is not None else self._on_scipy
        return run(float(phi0), float(cycle), float(omega0))

    def _on_kernels(self, phi0, cycle, omega0):
        from mechdyn.kernels import Integration
        from mechdyn.kernels.layout import EVENT, FINISHED, CHUNK_FULL, STATUS_NAMES
        p = np.append(np.asarray(self.p, dtype=float), 1e-9 * omega0)   # + the stall speed
        run = Integration(self.functions, p, phi0, [omega0, 0.0, 1.0], rtol=RTOL,
                          atol=ATOL * max(1.0, omega0), directions=[-1], detect_switch=False)
        ts, coefs = [np.array([phi0])], []
        while True:
            chunk = run.advance(phi0 + cycle, _CHUNK)
            ts.append(chunk.ts[1:])
            coefs.append(chunk.coefs)
            if chunk.status != CHUNK_FULL:
                break
        if chunk.status == EVENT or (chunk.status != FINISHED and run.y[0] < _SLOW * omega0):
            _stalled(run.t, omega0)
        if chunk.status != FINISHED:
            raise PeriodicError(f"integration over one cycle failed at phi = {run.t:.6g} rad: "
                                f"{STATUS_NAMES[chunk.status]}")
        omega, time, v = run.y
        return omega, v, time, _Dense(np.concatenate(ts), np.concatenate(coefs))

    def _on_scipy(self, phi0, cycle, omega0):
        rhs, jac, p = self.compiled.raw["rhs"], self.compiled.raw["jac"], self.p
        y, rates, slopes = [0.0, 0.0], [0.0, 0.0], np.zeros((2, 2))

        def fun(phi, z):
            omega, v = float(z[0]), float(z[2])
            y[0], y[1] = float(phi), omega
            rhs(0.0, y, p, rates)
            jac(0.0, y, p, slopes)
            a = rates[1]
            return [a / omega, 1 / omega, (float(slopes[1, 1]) / omega - a / omega ** 2) * v]

        def stall(phi, z):
            return z[0] - 1e-9 * omega0
        stall.terminal = True
        try:
            sol = solve_ivp(fun, (phi0, phi0 + cycle), [omega0, 0.0, 1.0], method="DOP853",
                            rtol=RTOL, atol=ATOL * max(1.0, omega0), events=stall,
                            dense_output=True)
        except (ArithmeticError, ValueError) as error:
            raise PeriodicError(f"integration over one cycle failed: "
                                f"{type(error).__name__}: {error}") from error
        if sol.status == 1:
            _stalled(sol.t_events[0][0], omega0)
        if sol.status != 0 and sol.y[0][-1] < _SLOW * omega0:
            _stalled(sol.t[-1], omega0)
        if sol.status != 0:
            raise PeriodicError(f"integration over one cycle failed: {sol.message}")
        omega, time, v = sol.y[:, -1]
        return omega, v, time, sol.sol


def _stalled(phi, omega0):
    raise PeriodicError(f"the machine stalls at phi = {phi:.6g} rad (starting the cycle at "
                        f"omega = {omega0:.6g} rad/s): the driving moment cannot pull it "
                        "through the cycle")


class _Dense:
    """The kernels' dense output over the cycle: ``dense(phi)`` as scipy's OdeSolution
    gives it (``(3,)`` at one angle, ``(3, m)`` at ``m``), ``ts`` the steps."""

    def __init__(self, ts, coefs):
        self.ts, self.coefs = ts, coefs

    def __call__(self, phi):
        from mechdyn.kernels import dense_values
        values = dense_values(self.ts, self.coefs, phi).T
        return values[:, 0] if np.ndim(phi) == 0 else values


def _kernel_functions(compiled):
    """The kernels' functions of the scene's cycle map (compiled once per process and
    scene), or None where the scene has no compiled form with a Jacobian."""
    if compiled.key not in _compiled_maps:
        from mechdyn.compile.numba_model import numba_functions
        scene_functions = numba_functions(compiled, jac=True)
        _compiled_maps[compiled.key] = None if scene_functions is None or \
            not scene_functions.has_jac else _compile(scene_functions.rhs, scene_functions.jac)
    return _compiled_maps[compiled.key]


def _compile(rhs, jac):
    from numba import njit

    from mechdyn.kernels import RHS_SIGNATURE, model_functions

    @njit(RHS_SIGNATURE)
    def cycle(phi, z, p, out):          # the scene's p, then the stall speed
        y = np.empty(2)
        y[0], y[1] = phi, z[0]
        rates = np.empty(2)
        rhs(0.0, y, p, rates)
        slopes = np.zeros((2, 2))
        jac(0.0, y, p, slopes)
        omega, a = z[0], rates[1]
        out[0] = a / omega
        out[1] = 1.0 / omega
        out[2] = (slopes[1, 1] / omega - a / omega ** 2) * z[2]

    @njit(RHS_SIGNATURE)
    def stall(phi, z, p, out):
        out[0] = z[0] - p[p.size - 1]
    return model_functions(cycle, None, stall)

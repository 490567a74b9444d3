"""Motor characteristics: torque as a function of the speed.

Each function returns a :class:`Characteristic`. Give it to ``load`` as the value (the
load calls it with the speed of its ``along``), or call it with a speed expression to
get the moment as an expression.

Examples
--------
>>> import sympy as sp, mechdyn as md
>>> phi = md.coordinate("phi")
>>> motor = md.motors.dc_shunt(M_0=100, omega_0=150)
>>> motor
dc_shunt(M_0=100, omega_0=150)
>>> motor(md.speed(phi)).subs(md.speed(phi), 75)
50
>>> drive = md.Mechanism("drive", [phi])
>>> drive.load("motor", motor, along=phi).value
100 - 2*Derivative(phi(t), t)/3
"""
from __future__ import annotations

import numpy as np
import sympy as sp

from mechdyn.declare.element_base import as_expression
from mechdyn.errors import DeclarationError

__all__ = ["Characteristic", "kloss", "dc_shunt", "table"]


class Characteristic:
    """A motor's moment as a function of its speed: ``characteristic(speed)`` gives the
    expression; ``load(name, characteristic, along=...)`` calls it with the speed of
    ``along``."""

    def __init__(self, name, moment):
        self.name, self._moment = name, moment

    def __call__(self, speed):
        return self._moment(as_expression(speed, f"{self.name}: speed"))

    def __repr__(self):
        return self.name


def _described(function, **arguments) -> str:
    return f"{function}({', '.join(f'{k}={v}' for k, v in arguments.items())})"


def kloss(M_k, s_k, omega_sync):
    """Induction motor by the Kloss formula ``M = 2 M_k / (s/s_k + s_k/s)``, slip
    ``s = (omega_sync - omega) / omega_sync`` (``M_k`` breakdown moment at slip ``s_k``).

    Written as ``2 M_k s s_k / (s^2 + s_k^2)``, which is finite (zero) at synchronous
    speed.

    >>> import mechdyn as md
    >>> omega = md.speed(md.coordinate("phi"))
    >>> md.motors.kloss(100, 0.2, 157)(omega).subs(omega, 157 * 0.8)
    100.000000000000
    """
    label = _described("kloss", M_k=M_k, s_k=s_k, omega_sync=omega_sync)
    M_k = as_expression(M_k, "kloss: M_k")
    s_k = as_expression(s_k, "kloss: s_k")
    omega_sync = as_expression(omega_sync, "kloss: omega_sync")
    for name, value in (("M_k", M_k), ("s_k", s_k), ("omega_sync", omega_sync)):
        if value.is_number and not value > 0:
            raise DeclarationError(f"kloss: {name} must be positive, got {value}")

    def characteristic(speed):
        slip = (omega_sync - speed) / omega_sync
        return 2 * M_k * slip * s_k / (slip ** 2 + s_k ** 2)
    return Characteristic(label, characteristic)


def dc_shunt(M_0, omega_0):
    """DC shunt motor, linear: ``M = M_0 (1 - omega/omega_0)`` (stall moment ``M_0``,
    no-load speed ``omega_0``)."""
    label = _described("dc_shunt", M_0=M_0, omega_0=omega_0)
    M_0 = as_expression(M_0, "dc_shunt: M_0")
    omega_0 = as_expression(omega_0, "dc_shunt: omega_0")
    if omega_0.is_number and not omega_0 > 0:
        raise DeclarationError(f"dc_shunt: omega_0 must be positive, got {omega_0}")

    def characteristic(speed):
        return M_0 * (1 - speed / omega_0)
    return Characteristic(label, characteristic)


def table(speeds, moments):
    """A measured characteristic: monotone piecewise-cubic (Fritsch-Carlson, as scipy's
    PCHIP) through the points ``(speeds[i], moments[i])``, held constant outside.

    >>> import mechdyn as md
    >>> omega = md.speed(md.coordinate("phi"))
    >>> M = md.motors.table([0, 100, 150], [80, 60, 0])(omega)
    >>> round(float(M.subs(omega, 100)), 9), round(float(M.subs(omega, 200)), 9)
    (60.0, 0.0)
    """
    x = np.asarray(speeds, dtype=float)
    y = np.asarray(moments, dtype=float)
    if x.ndim != 1 or len(x) < 2 or len(x) != len(y):
        raise DeclarationError("table: give at least two speeds and as many moments")
    if not np.all(np.diff(x) > 0):
        raise DeclarationError("table: speeds must increase strictly")
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(y))):
        raise DeclarationError("table: speeds and moments must be finite")
    slopes = _pchip_slopes(x, y)

    def characteristic(speed):
        pieces = [(float(y[0]), speed < x[0])]
        for i in range(len(x) - 1):
            h = x[i + 1] - x[i]
            s = (speed - x[i]) / h
            cubic = ((2 * s**3 - 3 * s**2 + 1) * y[i] + (s**3 - 2 * s**2 + s) * h * slopes[i]
                     + (-2 * s**3 + 3 * s**2) * y[i + 1] + (s**3 - s**2) * h * slopes[i + 1])
            pieces.append((cubic, speed <= x[i + 1]))
        pieces.append((float(y[-1]), True))
        return sp.Piecewise(*pieces)
    return Characteristic(f"table({len(x)} points)", characteristic)


def _pchip_slopes(x, y):
    """Fritsch-Carlson slopes: monotone data give a monotone interpolant."""
    from scipy.interpolate import PchipInterpolator
    return PchipInterpolator(x, y).derivative()(x)

"""Inverse dynamics of open chains: prescribed motions (:func:`uniform_rotation`,
:func:`uniform_acceleration`) and the driving moment they need, in closed form.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
import numpy as np
import sympy as sp
from scipy.integrate import quad
from scipy.optimize import minimize_scalar
from mechdyn.declare.elements import as_expression
from mechdyn.errors import ParameterError
from mechdyn.declare.parameters import exact_floats as _exact
from mechdyn.symbols import t
from mechdyn.derive.analytic import (AnalyticError, _STATS_QUAD, _fix_friction_sign, _reduced)

__all__ = ["Motion", "uniform_rotation", "uniform_acceleration", "DrivingMoment", "driving_moment"]


# ------------------------------------------------------------------ inverse dynamics
@dataclass(frozen=True)
class Motion:
    """A prescribed motion: the law ``phi(t)`` (an expression of ``md.t`` from t = 0),
    the sense of motion ``direction`` (+1 or -1, fixes the sign of Coulomb friction) and
    the time ``window`` its mean, peak and RMS are taken over (None: no statistics).

    Examples
    --------
    >>> import sympy as sp, mechdyn as md
    >>> swing = md.Motion(sp.sin(md.t), window=2 * sp.pi)
    >>> swing.law, swing.direction
    (sin(t), 1)
    """
    law: sp.Expr
    direction: int = 1
    window: object = None


def uniform_rotation(omega, phi0=0, cycle=2 * sp.pi) -> Motion:
    """Rotation at the constant speed ``omega``; statistics over one ``cycle`` of the
    angle (default a revolution, the time ``cycle / omega``).

    Examples
    --------
    >>> uniform_rotation(10).law
    10*t
    """
    omega = as_expression(omega, "uniform_rotation: omega")
    direction = -1 if omega.is_negative else 1
    return Motion(as_expression(phi0, "phi0") + omega * t, direction, cycle / abs(omega))


def uniform_acceleration(eps, omega0=0, phi0=0, duration=None) -> Motion:
    """Constant acceleration ``eps`` from the speed ``omega0``; statistics over
    ``duration`` when given.

    Examples
    --------
    >>> uniform_acceleration(4, omega0=1).law
    2*t**2 + t
    """
    eps = as_expression(eps, "uniform_acceleration: eps")
    omega0 = as_expression(omega0, "uniform_acceleration: omega0")
    first = omega0 if omega0 != 0 else eps
    return Motion(as_expression(phi0, "phi0") + omega0 * t + eps * t**2 / 2,
                  -1 if first.is_negative else 1, duration)


@dataclass
class DrivingMoment:
    """The moment that drives a one-DOF machine through a prescribed motion.

    ``expression``: ``M_drive = I_red eps + 1/2 I_red' omega^2 - M_red,other`` in the
    position (and the speed where it varies; constant speed and acceleration substituted);
    ``of_time``: along the motion, a function of ``t``; ``mean``, ``peak`` (largest
    magnitude) and ``rms`` over the motion's window (numbers; they need every parameter).

    Examples
    --------
    >>> import sympy as sp, mechdyn as md
    >>> phi = md.coordinate("phi")
    >>> yoke = md.Mechanism("yoke", [phi])
    >>> _ = yoke.link("crank", J=1, angle=phi)
    >>> _ = yoke.link("yoke", m=2, x=sp.cos(phi))
    >>> needed = md.driving_moment(yoke, md.uniform_rotation(3))
    >>> needed.expression                  # 1/2 I_red' omega^2, I_red = 1 + 2 sin^2
    9*sin(2*phi)
    >>> round(needed.mean, 12), round(float(needed.peak), 12)    # over a revolution
    (0.0, 9.0)
    """
    expression: sp.Expr
    of_time: sp.Expr
    window: object

    def latex(self) -> str:
        """``M_{drive} = ...``."""
        return "M_{\\mathrm{drive}} = " + sp.latex(self.expression)

    def _numeric(self):
        missing = self.of_time.free_symbols - {t}
        if missing or self.window is None or not sp.sympify(self.window).is_number:
            why = (f"give values of {sorted(map(str, missing))}" if missing
                   else "the motion has no numeric time window (give duration=)")
            raise ParameterError(f"driving moment statistics: {why}")
        return sp.lambdify(t, self.of_time, "math"), float(self.window)

    @property
    def mean(self) -> float:
        f, window = self._numeric()
        return quad(f, 0.0, window, **_STATS_QUAD)[0] / window

    @property
    def rms(self) -> float:
        f, window = self._numeric()
        return math.sqrt(quad(lambda x: f(x) ** 2, 0.0, window, **_STATS_QUAD)[0] / window)

    @property
    def peak(self) -> float:
        f, window = self._numeric()
        grid = np.linspace(0.0, window, 2001)
        values = np.abs([f(x) for x in grid])
        i = int(np.argmax(values))
        lo, hi = grid[max(i - 1, 0)], grid[min(i + 1, grid.size - 1)]
        best = minimize_scalar(lambda x: -abs(f(x)), bounds=(lo, hi), method="bounded",
                               options={"xatol": 1e-12 * window})
        return max(values[i], -best.fun)


def driving_moment(mech, motion, params=None, scene=None, drive=None,
                   guess=None) -> DrivingMoment:
    """The driving moment a one-DOF machine needs to follow ``motion`` (inverse dynamics).

    ``M_drive = I_red(phi) eps + 1/2 I_red'(phi) omega^2 - M_red,other(phi, omega, t)``,
    where ``M_red,other`` is the reduced moment of every load the scene includes except
    ``drive``.

    Parameters
    ----------
    mech : Mechanism
        One degree of freedom.
    motion : Motion
        From :func:`uniform_rotation`, :func:`uniform_acceleration` or ``Motion(law)``.
    params : dict, optional
        Parameter values (floats become exact rationals); missing ones stay symbolic.
    scene : Scene, optional
        Selects the loads (all when None).
    drive : str, optional
        Name or tag of the drive loads to leave out of ``M_red,other``.
    guess : dict, optional
        With closed loops: the dependent coordinates near the assembly wanted (see
        :mod:`mechdyn.analyse.linkage_drive`; the statistics are evaluated numerically there).

    Returns
    -------
    DrivingMoment

    Examples
    --------
    >>> import sympy as sp, mechdyn as md
    >>> phi = md.coordinate("phi")
    >>> disc = md.Mechanism("disc", [phi])
    >>> _ = disc.link("disc", J=2, angle=phi)
    >>> _ = disc.load("drive", sp.Symbol("M"), along=phi)
    >>> _ = disc.load("brake", -3, along=phi)
    >>> needed = md.driving_moment(disc, md.uniform_acceleration(5, duration=1), drive="drive")
    >>> needed.expression, round(needed.rms, 9)
    (13, 13.0)
    """
    if not isinstance(motion, Motion):
        raise AnalyticError(f"driving_moment: motion must be a md.Motion (from "
                            f"md.uniform_rotation or md.uniform_acceleration), got {motion!r}")
    if mech.constraints:
        raise AnalyticError(f"driving_moment: {mech.name!r} has closed loops; their driving "
                            "moment needs the position analysis: use md.driving_moment")
    eqs, subs, inertia, other = _reduced(mech, scene, params, "driving_moment", drive)
    q, u, a = eqs.q[0], eqs.u[0], eqs.a[0]
    other, _ = _fix_friction_sign(other, q, u, motion.direction)
    needed = inertia * a + sp.diff(inertia, q) / 2 * u**2 - other
    law = _exact(motion.law.xreplace(subs))
    speed, acceleration = sp.diff(law, t), sp.diff(law, t, 2)
    constants = {s: v for s, v in ((u, speed), (a, acceleration)) if not v.has(t)}
    expression = sp.simplify(needed.subs(constants).subs(a, acceleration))
    of_time = sp.simplify(needed.subs({q: law, u: speed, a: acceleration}))
    window = None if motion.window is None else _exact(sp.sympify(motion.window).xreplace(subs))
    return DrivingMoment(expression, of_time, window)

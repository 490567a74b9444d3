"""Inverse dynamics of one-DOF linkages with closed loops: the driving moment a prescribed
crank motion needs, ``M_drive = I_red eps + 1/2 I_red' omega^2 - M_red,other``, with
``I_red`` and ``M_red`` from the loops' transmission functions.
:func:`driving_moment` (``md.driving_moment``) takes the closed form of
:mod:`mechdyn.derive.analytic` for open chains and comes here for mechanisms with loops.

The expression is written in the crank angle, the dependent coordinates and the
transmission functions ``theta_2'``, ``theta_2''`` (their values come from the position
analysis); ``I_red'`` by the chain rule,
``dI/dphi = dI/dphi|_explicit + sum dI/dtheta_j theta_j' + sum dI/dtheta_j' theta_j''``.
Mean, peak and RMS over the motion's window are evaluated numerically along the motion
(:class:`~mechdyn.Linkage`); ``of_time`` has no closed form and is None.

>>> import numpy as np, sympy as sp, mechdyn as md
>>> phi, x = md.coordinates("phi x")
>>> yoke = md.Mechanism("Scotch yoke as a loop", [phi, x])
>>> _ = yoke.link("crank", J=1, angle=phi)
>>> _ = yoke.link("yoke", m=2, x=x)
>>> _ = yoke.constraint("slot", x - sp.cos(phi))
>>> needed = md.driving_moment(yoke, md.uniform_rotation(3), {}, guess={x: 1})
>>> round(needed.rms, 9)            # 2 sin cos 9 = 9 sin(2 phi): rms 9 / sqrt(2)
6.363961031
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import sympy as sp

from mechdyn.declare.parameters import ParameterSet
from mechdyn.declare.parameters import exact_floats as _exact
from mechdyn.derive import inverse
from mechdyn.derive.analytic import AnalyticError
from mechdyn.derive.inverse import DrivingMoment, Motion
from mechdyn.symbols import t
from mechdyn.derive.transmission import ratio_symbol, reduced_inertia_in_ratios

__all__ = ["driving_moment", "LoopDrivingMoment", "loop_driving_moment"]


@dataclass
class LoopDrivingMoment(DrivingMoment):
    """A :class:`~mechdyn.DrivingMoment` of a linkage: ``expression`` in the positions
    and transmission functions; ``at(times)`` evaluates it along the motion."""
    linkage: object = None
    law: object = None
    left_out: tuple = ()

    def at(self, times):
        """The driving moment at ``times`` (s) along the prescribed motion."""
        times = np.atleast_1d(np.asarray(times, dtype=float))
        phi, omega, eps = (sp.lambdify(t, sp.diff(self.law, t, k), "numpy") for k in range(3))
        out = []
        for value in times:
            angle, speed, acceleration = (float(f(value)) for f in (phi, omega, eps))
            sweep = self.linkage.sweep([angle])
            other = self.linkage.reduced_moment(angle, speed, value, exclude=self.left_out)
            out.append(sweep.inertia[0] * acceleration
                       + sweep.inertia_slope[0] / 2 * speed**2 - other)
        return np.array(out)

    def _numeric(self):
        if self.window is None or not sp.sympify(self.window).is_number:
            from mechdyn.errors import ParameterError
            raise ParameterError("driving moment statistics: the motion has no numeric "
                                 "time window (give duration=)")
        return (lambda value: float(self.at(value)[0])), float(self.window)


def driving_moment(mech, motion, params=None, scene=None, drive=None,
                   guess=None) -> DrivingMoment:
    """The driving moment a one-DOF machine needs to follow ``motion`` (inverse
    dynamics): the closed form of :func:`mechdyn.derive.inverse.driving_moment` for open
    chains, :func:`loop_driving_moment` for closed loops (``guess``: the dependent
    coordinates near the start).

    Examples
    --------
    >>> import mechdyn as md
    >>> phi = md.coordinate("phi")
    >>> disc = md.Mechanism("disc", [phi])
    >>> _ = disc.link("disc", J=2, angle=phi)
    >>> _ = disc.load("brake", -3, along=phi)
    >>> md.driving_moment(disc, md.uniform_acceleration(5)).expression   # 2 * 5 + 3
    13
    """
    if mech.constraints:
        return loop_driving_moment(mech, motion, params, scene, drive, guess)
    return inverse.driving_moment(mech, motion, params, scene, drive, guess)


def loop_driving_moment(mech, motion, params=None, scene=None, drive=None, guess=None):
    """The driving moment of a one-DOF linkage for ``motion`` (see module docstring)."""
    from mechdyn.analyse.linkage import Linkage
    if not isinstance(motion, Motion):
        raise AnalyticError(f"driving_moment: motion must be a md.Motion, got {motion!r}")
    values = ParameterSet(params, mechanism=mech, scene=scene)        # before deriving
    eqs = mech.equations(scene)
    if len(eqs.independent) != 1:
        raise AnalyticError(f"driving_moment: {mech.name!r} has {len(eqs.independent)} "
                            "independent coordinates; it needs one")
    left_out = ()
    if drive is not None:
        left_out = tuple(n for n in eqs.generalized_forces
                         if n == drive or drive in mech.elements[n].tags)
        if not left_out:
            raise AnalyticError(f"driving_moment: no load named or tagged {drive!r} in "
                                f"{mech.name!r} (loads: {', '.join(eqs.generalized_forces)})")
    crank = eqs.independent[0]
    u, a = eqs.u[eqs.q.index(crank)], eqs.a[eqs.q.index(crank)]
    inertia = reduced_inertia_in_ratios(eqs)
    slope = sp.diff(inertia, crank)
    for q in eqs.q:
        if q != crank:
            slope += sp.diff(inertia, q) * ratio_symbol(q) \
                + sp.diff(inertia, ratio_symbol(q)) * ratio_symbol(q, 2)
    speeds = {eqs.u[i]: _ratio(eqs, i) * u for i in range(eqs.dof)}
    moment = sp.Add(*[column[i].xreplace(speeds) * _ratio(eqs, i)
                      for name, column in eqs.generalized_forces.items()
                      if name not in left_out for i in range(eqs.dof) if column[i] != 0])
    expression = (inertia * a + slope / 2 * u**2 - moment).xreplace(values.exact())
    linkage = Linkage(mech, values, guess, scene)
    window = None if motion.window is None else _exact(sp.sympify(motion.window))
    return LoopDrivingMoment(expression, None, window, linkage, motion.law, left_out)


def _ratio(eqs, i):
    q = eqs.q[i]
    return sp.S.One if q in eqs.independent else ratio_symbol(q)

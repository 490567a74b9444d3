"""Couplings with the names a machine designer expects, declared on a Mechanism.

Each is a thin wrapper that builds a :class:`~mechdyn.declare.elements.Friction`, a one-way
element (:mod:`mechdyn.declare.unilateral`) or a load with the force law of the MSL component it
is named after:

- ``clutch`` / ``brake``: friction ``geometry * mu(|slip|) * normal_force``, free while
  the normal force is not positive (MSL ``Clutch``, ``Brake``);
- ``bearing_friction``: friction ``moment(|slip|)`` (MSL ``BearingFriction``);
- ``one_way_clutch``, ``freewheel``: a one-way clutch (MSL ``OneWayClutch``);
- ``stop``: a hard stop with impacts; ``backlash``: an elastic backlash (MSL
  ``ElastoBacklash``) or, without a stiffness, an ideal one (two stops);
- ``elasto_gap``: an elastic contact that only pushes (MSL ``ElastoGap``);
- ``lossy_gear``: a gear pair with mesh loss by power-flow direction (MSL ``LossyGear``).

``mu`` and the bearing ``moment`` may be numbers, expressions or functions of the
sliding speed's magnitude (``md.table(...)``), called with ``|d(along)/dt|``.

>>> import mechdyn as md
>>> phi_1, phi_2 = md.coordinates("phi_1 phi_2")
>>> drive = md.Mechanism("two shafts", [phi_1, phi_2])
>>> clutch = drive.clutch("clutch", normal_force=200 * md.t, mu=0.3, along=phi_2 - phi_1,
...                       peak=1.1, geometry=0.1)
>>> clutch.moment, clutch.along
(6.0*t, -phi_1(t) + phi_2(t))
"""
from __future__ import annotations

import sympy as sp

from mechdyn.declare.elements import Friction, Load, as_expression
from mechdyn.errors import DeclarationError
from mechdyn.symbols import t
from mechdyn.declare.unilateral import LossyGear, OneWayClutch, Stop

__all__ = ["Couplings", "elasto_backlash_moment", "elasto_gap_force"]


class Couplings:
    """The coupling declarations of :class:`~mechdyn.declare.mechanism.Mechanism` (a mixin:
    every method adds elements through ``self.add``)."""

    def clutch(self, name, normal_force, mu, along, peak=1, geometry=1, tags=()) -> Friction:
        """A friction clutch between two shafts (``along``: the slip angle
        ``phi_b - phi_a``): sliding moment ``geometry * mu * normal_force`` (``mu`` a
        number or a function of the slip speed's magnitude), ``peak`` times that at
        rest; free (no moment, never stuck) while ``normal_force <= 0``."""
        mu = _of_slip(mu, along, f"clutch {name!r}: mu")
        return self.add(Friction(name, moment=geometry * mu * normal_force, along=along,
                                 peak=peak, tags=tags))

    def brake(self, name, normal_force, mu, along, peak=1, geometry=1, tags=()) -> Friction:
        """A brake on ``along`` (a shaft's angle against the frame): as :meth:`clutch`."""
        mu = _of_slip(mu, along, f"brake {name!r}: mu")
        return self.add(Friction(name, moment=geometry * mu * normal_force, along=along,
                                 peak=peak, tags=tags))

    def bearing_friction(self, name, moment, along, peak=1, tags=()) -> Friction:
        """Bearing friction on ``along``: sliding moment ``moment`` (a number or a
        function of the speed's magnitude, e.g. ``md.table``), ``peak`` times its value
        at rest."""
        moment = _of_slip(moment, along, f"bearing friction {name!r}: moment")
        return self.add(Friction(name, moment=moment, along=along, peak=peak, tags=tags))

    def one_way_clutch(self, name, moment, along, peak=1, release=0, tags=()) -> OneWayClutch:
        """A one-way clutch: ``along`` may only increase; sliding forward it brakes with
        ``moment`` (a number, expression or function of the slip speed), locked it holds
        any backward moment and releases forward above ``max(peak * moment, release)``."""
        moment = _of_slip(moment, along, f"one-way clutch {name!r}: moment")
        return self.add(OneWayClutch(name, moment=moment, along=along, peak=peak,
                                     release=release, tags=tags))

    def freewheel(self, name, along, release=0, tags=()) -> OneWayClutch:
        """A freewheel (overrunning clutch): ``along`` may only increase, overrunning
        costs nothing, locked it holds any backward moment. Locked at rest it releases
        forward once the moment pushing forward exceeds ``release`` (default 0: at once;
        MSL's small threshold of a disengaged clutch):
        :class:`~mechdyn.declare.unilateral.OneWayClutch` with ``moment = 0``."""
        return self.add(OneWayClutch(name, moment=0, along=along, release=release,
                                     tags=tags))

    def stop(self, name, along, lower=None, upper=None, restitution=0, tags=()) -> Stop:
        """A hard stop ``lower <= along <= upper`` with impacts of coefficient
        ``restitution`` (0: plastic, 1: elastic); see :class:`~mechdyn.declare.unilateral.Stop`."""
        return self.add(Stop(name, along=along, lower=lower, upper=upper,
                             restitution=restitution, tags=tags))

    def lossy_gear(self, name, input, output, ratio, eta_forward=1, eta_backward=1,
                   bearing_forward=0, bearing_backward=0, tags=()) -> LossyGear:
        """A gear pair ``input = ratio * output`` with the mesh loss of
        :class:`~mechdyn.declare.unilateral.LossyGear` (``eta_backward <= 0``: self-locking)."""
        return self.add(LossyGear(name, input=input, output=output, ratio=ratio,
                                  eta_forward=eta_forward, eta_backward=eta_backward,
                                  bearing_forward=bearing_forward,
                                  bearing_backward=bearing_backward, tags=tags))

    def backlash(self, name, stretch, c=None, d=0, gap=None, restitution=0, tags=()):
        """A backlash of total play ``gap`` centred on ``stretch = 0``: elastic with
        stiffness ``c`` and damping ``d`` (MSL ``ElastoBacklash``: the damping moment is
        limited so that the contact never pulls; a load), or without ``c`` ideal: rigid
        contacts at ``stretch = -+gap/2`` with impacts of coefficient ``restitution``
        (a stop)."""
        if gap is None:
            raise DeclarationError(f"backlash {name!r}: give gap= (the total play)")
        gap = as_expression(gap, f"backlash {name!r}: gap")
        if c is None:
            return self.stop(name, stretch, lower=-gap / 2, upper=gap / 2,
                             restitution=restitution, tags=tags)
        moment = elasto_backlash_moment(stretch, _rate(stretch), c, d, gap)
        return self.add(Load(name, value=-moment, along=stretch, tags=tags))

    def elasto_gap(self, name, gap_expression, c, d, opening, n=1, tags=()) -> Load:
        """An elastic contact (MSL ``ElastoGap``): in contact while ``gap_expression <
        opening``, pushing along ``gap_expression`` with ``c (opening - gap)^n`` plus
        damping ``d`` times its rate, the damping limited so the contact never pulls."""
        force = elasto_gap_force(gap_expression, _rate(gap_expression), c, d, opening, n)
        return self.add(Load(name, value=force, along=gap_expression, tags=tags))


def elasto_backlash_moment(stretch, rate, c, d, gap):
    """MSL ElastoBacklash's moment ``tau`` (at flange_b; the element pushes ``-tau``
    along ``stretch``): a spring-damper outside the play ``|stretch| > gap/2``, its
    damping limited to the spring moment and never pulling; a plain spring-damper for a
    play of at most 1e-10."""
    if gap.is_number and gap <= sp.Float(1e-10):
        return c * stretch + d * rate
    above, below, damping = c * (stretch - gap / 2), c * (stretch + gap / 2), d * rate
    return sp.Piecewise(
        (sp.Piecewise((0, above + damping <= 0), (above + sp.Min(above, damping), True)),
         stretch > gap / 2),
        (sp.Piecewise((0, below + damping >= 0), (below + sp.Max(below, damping), True)),
         stretch < -gap / 2),
        (0, True))


def elasto_gap_force(gap, rate, c, d, opening, n=1):
    """MSL ElastoGap's push along ``gap`` (``-f`` of the component): ``c (opening -
    gap)^n`` plus the damping ``-d rate`` clamped to ``[-elastic, elastic]``, in contact
    (``gap < opening``), else 0."""
    elastic = c * (opening - gap) ** n
    push = elastic + sp.Max(-elastic, sp.Min(elastic, -d * rate))
    return sp.Piecewise((push, gap < opening), (0, True))


def _rate(expr):
    """``d(expr)/dt`` written with the coordinates' speeds."""
    return sp.diff(as_expression(expr, "rate"), t)


def _of_slip(value, along, what):
    """A characteristic: a number or expression as it is, or a function (a table) of
    the slip speed's magnitude ``|d(along)/dt|``."""
    if callable(value) and not isinstance(value, sp.Basic):
        speed = sp.Abs(_rate(as_expression(along, f"{what}: along")))
        return as_expression(value(speed), what)
    return as_expression(value, what)

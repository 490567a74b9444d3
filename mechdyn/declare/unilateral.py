"""Elements that act one way: a one-way clutch, a hard stop, a lossy gear.

Like :class:`~mechdyn.declare.elements.Friction` they switch between modes at run time
(:mod:`mechdyn.simulate.friction`): a one-way clutch locks or overruns, a stop is open or in
contact (with impacts, :mod:`mechdyn.simulate.contacts`), a lossy gear slides or locks with a loss
that depends on the direction of power flow (:mod:`mechdyn.declare.gear_loss`).

>>> import mechdyn as md
>>> x = md.coordinate("x")
>>> Stop("end stops", along=x, lower=0, upper=1, restitution=0.5).limits
((1, 0), (-1, 1))
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from mechdyn.declare.element_base import Element, Limit, Sliding, Work
from mechdyn.declare.elements import Constraint, Friction
from mechdyn.errors import DeclarationError

__all__ = ["OneWayClutch", "Stop", "LossyGear"]


@dataclass(frozen=True)
class OneWayClutch(Friction):
    """A one-way clutch (freewheel with a friction clutch in parallel): ``along`` may
    only increase. Sliding forward it brakes with ``moment`` (0: a freewheel overruns
    freely); at rest it locks, holds any moment against backward motion, and releases
    forward once the moment pushing forward exceeds ``peak * moment`` (or ``release``,
    whichever is larger: MSL's small threshold of a disengaged clutch).

    Examples
    --------
    >>> import mechdyn as md
    >>> phi = md.coordinate("phi")
    >>> hub = md.Mechanism("hub", [phi])
    >>> _ = hub.link("wheel", J=0.1, angle=phi)
    >>> hub.freewheel("pawl", along=phi)      # moment 0: a freewheel
    OneWayClutch(name='pawl', tags=(), moment=0, along=phi(t), peak=1, release=0)
    """
    release: object = 0

    DEPENDS = {**Friction.DEPENDS, "release": ""}
    RULES = {**Friction.RULES,
             "release": ("nonnegative", "a release moment must not be negative")}
    KIND = "one_way"

    def __post_init__(self):
        super().__post_init__()
        self.convert("release", nonnegative=True)

    def work(self, motion):
        along = motion.position(self.along, self.name)
        law = motion.law(self.moment, along, self.name)
        return Work(forces=((-law * sp.Heaviside(motion.rate(along)), along),),
                    sliding=Sliding(self.KIND, law, along, motion.plain(self.peak),
                                    motion.plain(self.release)))

    def check_units(self, units):
        super().check_units(units)
        units.work("release * d(along)/d{q}", "along", "release")

    def expressions(self):
        out = super().expressions()
        if self.release != 0:
            out["release"] = self.release
        return out


@dataclass(frozen=True)
class Stop(Element):
    """A hard stop on ``along``: ``lower <= along <= upper`` (either limit may be None).
    Reaching a limit is an impact: the speed of ``along`` jumps to ``-restitution``
    times its value (the impulse of least kinetic energy change); resting on a limit
    the stop holds while it pushes, and lets go when the loads pull away.

    Examples
    --------
    >>> import mechdyn as md
    >>> x = md.coordinate("x")
    >>> stamp = md.Mechanism("stamp", [x], units={x: "m"})
    >>> _ = stamp.link("ram", m=2, x=x)
    >>> stop = stamp.stop("anvil", along=x, lower=0, restitution=0.5)
    >>> stop.lower, stop.upper, stop.restitution
    (0, None, 0.500000000000000)
    """
    along: object = None
    lower: object = None
    upper: object = None
    restitution: object = 0

    DEPENDS = {"along": "qt", "lower": "", "upper": "", "restitution": ""}
    MOVING = ("along",)
    RULES = {"restitution": ("fraction", "a coefficient of restitution lies in [0, 1]")}

    def work(self, motion):
        along, restitution = motion.plain(self.along), motion.plain(self.restitution)
        return Work(contacts=tuple(Limit(label, side, along, motion.plain(limit), restitution)
                                   for label, side, limit in limit_sides(self)))

    def check_units(self, units):
        units.same("lower", "along")
        units.same("upper", "along")

    def output(self, eqs):
        return sp.S.Zero              # the contact force: filled in at run time

    def __post_init__(self):
        super().__post_init__()
        what = f"stop {self.name!r}"
        if self.along is None:
            raise DeclarationError(f"{what}: 'along' is required")
        if self.lower is None and self.upper is None:
            raise DeclarationError(f"{what}: give lower=, upper= or both")
        self.convert("along")
        for attribute in ("lower", "upper"):
            if getattr(self, attribute) is not None:
                self.convert(attribute)
        self.convert("restitution")
        e = self.restitution
        if e.is_number and not 0 <= e <= 1:
            raise DeclarationError(f"{what}: restitution = {_text(e)} must lie in [0, 1]")
        if self.lower is not None and self.upper is not None:
            width = self.upper - self.lower
            if width.is_number and not width > 0:
                raise DeclarationError(f"{what}: lower = {self.lower} must lie below "
                                       f"upper = {self.upper}")

    @property
    def limits(self) -> tuple:
        """``(side, limit)`` per limit: side +1 for the lower (the stop pushes along
        +along), -1 for the upper."""
        return tuple((side, limit) for side, limit in ((1, self.lower), (-1, self.upper))
                     if limit is not None)

    def expressions(self):
        out = {"along": self.along, "restitution": self.restitution}
        for attribute in ("lower", "upper"):
            if getattr(self, attribute) is not None:
                out[attribute] = getattr(self, attribute)
        return out


@dataclass(frozen=True)
class LossyGear(Constraint):
    """A gear pair ``input = ratio * output`` whose mesh loses power by the direction
    of power flow (MSL ``LossyGear``): with ``tau`` the moment the input side passes
    into the gear, turning forward the loss moment is ``(1 - eta_forward) tau +
    bearing_forward`` while the input drives and ``(1 - 1/eta_backward) tau +
    bearing_backward`` while the output drives (the larger of the two); mirrored
    backward. ``eta_backward <= 0`` is a self-locking gear (a worm): the output can
    never drive it. At rest it holds while the loss moment needed stays within that
    law. The efficiencies and bearing moments may depend on the speeds.

    Examples
    --------
    A self-locking worm gear (``eta_backward <= 0``):

    >>> import mechdyn as md
    >>> worm, wheel = md.coordinates("worm wheel")
    >>> hoist = md.Mechanism("worm hoist", [worm, wheel])
    >>> _ = hoist.link("worm", J=1e-3, angle=worm)
    >>> _ = hoist.link("wheel", J=0.5, angle=wheel)
    >>> gear = hoist.lossy_gear("gear", input=worm, output=wheel, ratio=40,
    ...                         eta_forward=0.6, eta_backward=-0.2)
    >>> gear.ratio, gear.eta_backward
    (40, -0.200000000000000)
    """
    input: object = None
    output: object = None
    ratio: object = 1
    eta_forward: object = 1
    eta_backward: object = 1
    bearing_forward: object = 0
    bearing_backward: object = 0

    _LAW = ("eta_forward", "eta_backward", "bearing_forward", "bearing_backward")
    DEPENDS = dict.fromkeys(_LAW, "qvt")
    RULES = {"eta_forward": ("efficiency", "an efficiency must lie in (0, 1]"),
             **dict.fromkeys(("bearing_forward", "bearing_backward"),
                             ("nonnegative", "a bearing moment must not be negative"))}

    def __post_init__(self):
        what = f"lossy gear {self.name!r}"
        if self.input is None or self.output is None:
            raise DeclarationError(f"{what}: give input= and output= (its two angles)")
        object.__setattr__(self, "equations", ())
        for attribute in ("input", "output", "ratio") + self._LAW:
            self.convert(attribute)
        if self.ratio.is_number and self.ratio == 0:
            raise DeclarationError(f"{what}: ratio must not be zero")
        eta = self.eta_forward
        if eta.is_number and not 0 < eta <= 1:
            raise DeclarationError(f"{what}: eta_forward = {_text(eta)} must lie in (0, 1]")
        if self.eta_backward.is_number and not self.eta_backward <= 1:
            raise DeclarationError(f"{what}: eta_backward = {_text(self.eta_backward)} must not "
                                   "exceed 1 (0 or below: self-locking)")
        for attribute in ("bearing_forward", "bearing_backward"):
            value = getattr(self, attribute)
            if value.is_negative:
                raise DeclarationError(f"{what}: {attribute} = {value} must not be negative")
        object.__setattr__(self, "equations", (self.input - self.ratio * self.output,))
        super().__post_init__()

    @property
    def law(self) -> tuple:
        """``(eta_forward, eta_backward, bearing_forward, bearing_backward)``."""
        return tuple(getattr(self, attribute) for attribute in self._LAW)

    def work(self, motion):
        """The mesh's loss acts along ``ratio * output`` (the gear's own constraint
        holds the rest)."""
        along = motion.position(self.ratio * self.output, self.name)
        return Work(sliding=Sliding("gear", sp.S.Zero, along,
                                    law=tuple(motion.plain(value) for value in self.law)))

    def output_along(self):
        return self.input

    def expressions(self):
        out = super().expressions()
        out.update({attribute: getattr(self, attribute) for attribute in self._LAW})
        return out


def limit_sides(stop: Stop) -> list:
    """``(label, side, limit)`` of each limit of a stop: ``NAME.lower`` (side +1),
    ``NAME.upper`` (side -1)."""
    return [(f"{stop.name}.{'lower' if side > 0 else 'upper'}", side, limit)
            for side, limit in stop.limits]


def _text(number) -> str:
    """A number as the user would write it (1.5, not 1.50000000000000)."""
    return f"{float(number):g}"

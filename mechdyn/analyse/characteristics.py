"""Motor and load characteristics of a one-DOF machine, its operating points and their
stability.

The drive's moment reduced to the coordinate, ``M_motor(omega)``, is drawn against the
resisting moment of everything else, ``M_load(omega)`` (reduced the same way; averaged
over a cycle of the coordinate where it depends on the position, evaluated at the
scene's start time where it depends on time). They balance at the operating points; a
point is stable when ``dM_motor/domega < dM_load/domega`` there: a little faster, the
load wins and slows the machine back down.

>>> import sympy as sp, mechdyn as md
>>> phi = md.coordinate("phi")
>>> fan = md.Mechanism("fan", [phi])
>>> _ = fan.link("rotor", J=0.5, angle=phi)
>>> _ = fan.load("motor", md.motors.dc_shunt(100, 200)(md.speed(phi)), along=phi)
>>> _ = fan.load("air", -0.005 * md.speed(phi)**2, along=phi)
>>> (point,) = characteristic(fan).points      # 100 (1 - w/200) = 0.005 w^2
>>> round(point.speed, 6), point.stable
(100.0, True)
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import sympy as sp
from scipy.optimize import brentq

from mechdyn.analyse.cycle_mean import cycle_mean
from mechdyn.errors import MechdynError
from mechdyn.declare.parameters import ParameterSet, missing_values
from mechdyn.symbols import t

__all__ = ["characteristic", "Characteristic", "OperatingPoint", "CharacteristicError"]

_GRID = 4001          # speeds scanned for balances


class CharacteristicError(MechdynError, ValueError):
    """A machine or scene whose characteristics cannot be drawn (several DOF, no drive).

    Examples
    --------
    >>> import mechdyn as md
    >>> x, y = md.coordinates("x y")
    >>> table = md.Mechanism("table", [x, y])
    >>> _ = table.link("slide", m=1, x=x, y=y)
    >>> try:
    ...     md.characteristic(table)
    ... except md.CharacteristicError as error:
    ...     print(type(error).__name__)
    CharacteristicError
    """


@dataclass(frozen=True)
class OperatingPoint:
    """Where motor and load balance: ``speed`` (rad/s of the coordinate), ``moment``
    (N m, reduced), the slopes of both curves there and ``stable``."""
    speed: float
    moment: float
    motor_slope: float
    load_slope: float

    @property
    def stable(self) -> bool:
        return self.motor_slope < self.load_slope

    def describe(self, shown=None) -> str:
        """In words, speeds and moments in the display units of ``shown``."""
        from mechdyn.display import Display
        shown = Display(shown)
        (speed,), speed_unit = shown.values("speed", "rad/s", [self.speed])
        (moment,), moment_unit = shown.values("moment", "N*m", [self.moment])
        return (f"{'stable' if self.stable else 'unstable'} at {speed:.6g} {speed_unit}, "
                f"{moment:.6g} {moment_unit} (slopes dM/domega: motor "
                f"{self.motor_slope:.4g}, load {self.load_slope:.4g} N*m*s)")

    def __str__(self):
        return self.describe()

    def __repr__(self):
        return (f"{'stable' if self.stable else 'unstable'} at {self.speed:.6g} rad/s, "
                f"{self.moment:.6g} N*m")


@dataclass
class Characteristic:
    """Motor and load moments over ``speeds`` and the operating ``points``.

    Examples
    --------
    >>> import mechdyn as md
    >>> phi = md.coordinate("phi")
    >>> fan = md.Mechanism("fan", [phi])
    >>> _ = fan.link("rotor", J=0.5, angle=phi)
    >>> _ = fan.load("motor", md.motors.dc_shunt(100, 200)(md.speed(phi)), along=phi)
    >>> _ = fan.load("air", -0.005 * md.speed(phi)**2, along=phi)
    >>> curves = md.characteristic(fan, speeds=(0, 200))
    >>> curves
    <Characteristic 'fan': 1 operating point(s) over 4001 speeds>
    >>> curves.drive, float(curves.motor[0]), float(curves.load[-1])   # at 0 and 200 rad/s
    (('motor',), 100.0, 200.0)
    """
    name: str
    coordinate: str
    drive: tuple
    speeds: np.ndarray
    motor: np.ndarray
    load: np.ndarray
    points: list
    notes: tuple = ()

    def __repr__(self):
        return (f"<Characteristic {self.name!r}: {len(self.points)} operating point(s) over "
                f"{len(self.speeds)} speeds>")

    def summary(self, units=None) -> str:
        """The operating points in words (``units``: e.g. ``{"speed": "rpm"}``)."""
        from mechdyn.display import Display
        shown = Display(units)
        (low, high), unit = shown.values("speed", "rad/s", self.speeds[[0, -1]])
        lines = [f"{self.name}: drive {', '.join(self.drive)} against the rest, reduced to "
                 f"{self.coordinate}, {low:.4g} to {high:.4g} {unit}"]
        lines += [f"  {point.describe(shown)}" for point in self.points] or \
            ["  no operating point in this range"]
        lines += [f"  note: {note}" for note in self.notes]
        return "\n".join(lines)

    def __str__(self):
        return self.summary()

    def plot(self, path=None, units=None):
        """Both curves against the speed, the operating points marked (filled: stable,
        open: unstable); ``units`` as for results (``{"speed": "rpm"}``)."""
        from mechdyn.display import Display
        from mechdyn.plotting import finish, pyplot
        plt = pyplot()
        shown = Display(units)
        speeds, speed_unit = shown.values("speed", "rad/s", self.speeds)
        motor, moment_unit = shown.values("moment", "N*m", self.motor)
        load, _ = shown.values("moment", "N*m", self.load)
        fig, ax = plt.subplots(figsize=(7.5, 4.8))
        ax.plot(speeds, motor, label=f"motor: {', '.join(self.drive)}")
        ax.plot(speeds, load, label="load (reduced)")
        for point in self.points:
            (x,), _ = shown.values("speed", "rad/s", [point.speed])
            (y,), _ = shown.values("moment", "N*m", [point.moment])
            ax.plot([x], [y], "o", ms=8, color="tab:green" if point.stable else "tab:red",
                    mfc="tab:green" if point.stable else "white", mew=2, zorder=3)
            ax.annotate(f"{'stable' if point.stable else 'unstable'}\n{x:.4g} {speed_unit}, "
                        f"{y:.4g} {moment_unit.replace('*', ' ')}", (x, y),
                        xytext=(8, 8), textcoords="offset points", fontsize=8)
        ax.set_xlabel(f"speed of {self.coordinate} [{speed_unit}]")
        ax.set_ylabel(f"moment reduced to {self.coordinate} [{moment_unit.replace('*', ' ')}]")
        ax.set_title(f"{self.name}: characteristics and operating points")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
        return finish(fig, path)


def characteristic(mechanism, scene=None, params=None, drive=None, speeds=None,
                   cycle=2 * np.pi) -> Characteristic:
    """The motor's and the load's moment against the speed, and the operating points.

    Parameters
    ----------
    mechanism : Mechanism
        One DOF under the scene (springs made rigid count).
    scene : Scene, optional
        Selects the effects (all by default); its start time fixes time-dependent loads.
    params : dict, optional
    drive : str, optional
        Name or tag of the driving load(s); default: the load named or tagged "motor",
        else the one load that depends on the speed.
    speeds : (float, float), optional
        Range of the coordinate's speed; default from rest to 1.2 times the motor's
        no-load speed.
    cycle : float
        Period of the coordinate for position-dependent moments (their mean is used).

    Returns
    -------
    Characteristic

    Examples
    --------
    A shunt motor ``100 (1 - omega/200)`` against air drag ``0.005 omega^2`` balances at
    100 rad/s:

    >>> import mechdyn as md
    >>> phi = md.coordinate("phi")
    >>> fan = md.Mechanism("fan", [phi])
    >>> _ = fan.link("rotor", J=0.5, angle=phi)
    >>> _ = fan.load("motor", md.motors.dc_shunt(100, 200)(md.speed(phi)), along=phi)
    >>> _ = fan.load("air", -0.005 * md.speed(phi)**2, along=phi)
    >>> (point,) = md.characteristic(fan).points
    >>> round(point.speed, 6), point.stable
    (100.0, True)
    """
    values = ParameterSet(params, mechanism=mechanism, scene=scene)   # before deriving
    eqs = mechanism.equations(scene)
    if eqs.dof != 1:
        raise CharacteristicError(
            f"characteristic: {mechanism.name!r} has {eqs.dof} coordinates under this scene "
            f"({', '.join(map(str, eqs.q))}); make springs rigid in a scene to reduce it "
            "to one")
    names = _drive(mechanism, eqs, drive)
    q, u = eqs.q[0], eqs.u[0]
    start = scene.t_start if scene is not None else 0.0
    motor = sp.Add(*[eqs.generalized_forces[n][0] for n in names])
    rest = sp.Add(*[column[0] for n, column in eqs.generalized_forces.items()
                    if n not in names])
    notes = []
    if (motor + rest).has(t):
        notes.append(f"moments depend on the time: evaluated at t = {start:g} s")
    if (motor + rest).has(q):
        notes.append(f"moments depend on {q}: mean over a cycle of {cycle:.6g}")
    motor_at = _curve(motor, q, u, values, start, cycle, "the motor's moment")
    load_at = _curve(-rest, q, u, values, start, cycle, "the load's moment")
    motor_slope = _curve(sp.diff(motor, u), q, u, values, start, cycle, "the motor's moment")
    load_slope = _curve(sp.diff(-rest, u), q, u, values, start, cycle, "the load's moment")
    low, high = speeds if speeds is not None else (0.0, _top_speed(motor_at, scene, eqs))
    grid = np.linspace(low, high, _GRID)
    motor_values, load_values = motor_at(grid), load_at(grid)
    points = []
    balance = motor_values - load_values
    for k in np.flatnonzero(np.sign(balance[:-1]) * np.sign(balance[1:]) < 0):
        speed = brentq(lambda w: float(motor_at(np.array([w]))[0] - load_at(np.array([w]))[0]),
                       grid[k], grid[k + 1], xtol=1e-13, rtol=4 * np.finfo(float).eps)
        w = np.array([speed])
        points.append(OperatingPoint(speed, float(motor_at(w)[0]), float(motor_slope(w)[0]),
                                     float(load_slope(w)[0])))
    points += [OperatingPoint(float(grid[k]), float(motor_values[k]),
                              float(motor_slope(grid[k:k + 1])[0]),
                              float(load_slope(grid[k:k + 1])[0]))
               for k in np.flatnonzero(balance == 0)]
    return Characteristic(mechanism.name, str(q), names, grid, motor_values, load_values,
                          sorted(points, key=lambda p: p.speed), tuple(notes))


def _drive(mechanism, eqs, drive):
    loads = list(eqs.generalized_forces)
    if drive is not None:
        names = tuple(n for n in loads if n == drive or drive in mechanism.elements[n].tags)
        if not names:
            raise CharacteristicError(f"characteristic: no load named or tagged {drive!r} in "
                                      f"the scene (loads: {', '.join(loads)})")
        return names
    named = tuple(n for n in loads if n == "motor" or "motor" in mechanism.elements[n].tags)
    if named:
        return named
    speed = eqs.u[0]
    moving = tuple(n for n in loads if eqs.generalized_forces[n][0].has(speed)
                   and not any(f.name == n for f in eqs.frictions))
    if len(moving) == 1:
        return moving
    raise CharacteristicError(f"characteristic: which load is the drive? name it with "
                              f"drive= / --drive (loads: {', '.join(loads)})")


def _curve(expr, q, u, values, start, cycle, what):
    """A vectorized function of the speed: ``expr`` with the parameter ``values`` (a
    :class:`~mechdyn.declare.parameters.ParameterSet`), at the start time, averaged over
    a cycle of ``q`` where it depends on it (:func:`~mechdyn.analyse.cycle_mean.cycle_mean`:
    exact for loads that switch with the position)."""
    expr = values.substitute(expr).subs(t, start)
    missing = expr.free_symbols - {q, u}
    if missing:
        raise missing_values(sorted(map(str, missing)), f"{what} (characteristic)",
                             getattr(values.mechanism, "name", None))
    if not expr.has(q):
        f = sp.lambdify((q, u), expr, "numpy")
        return lambda w: np.broadcast_to(np.asarray(f(0.0, w), dtype=float), np.shape(w)) * 1.0
    return cycle_mean(expr, q, u, cycle)


def _top_speed(motor_at, scene, eqs):
    """1.2 times where the motor's moment first falls to zero (its no-load speed), or
    twice the scene's initial speed, or 100 rad/s."""
    grid = np.geomspace(1e-3, 1e6, 2000)
    values = motor_at(grid)
    crossing = np.flatnonzero((values[:-1] > 0) & (values[1:] <= 0))
    if crossing.size:
        return 1.2 * float(grid[crossing[0] + 1])
    initial = 0.0
    if scene is not None:
        initial = max((abs(float(v)) for k, v in scene.initial.items()
                       if isinstance(k, sp.Derivative) and sp.sympify(v).is_number), default=0)
    return 2.0 * initial if initial > 0 else 100.0

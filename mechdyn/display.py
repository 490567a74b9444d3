"""What results are measured in, and the units people want to read them in.

Every column of a result has an SI unit: coordinates their declared unit (rad by
default), speeds and accelerations per s and s^2, an element's output the moment or
force it exerts along its own coordinate (N*m along an angle, N along a length; from
the parameter units where declared), ``power:NAME`` W, an expression output its
dimension. :class:`Display` picks other units to show: by kind (``speed=rpm``,
``power=kW``) or by column (``rope=kN``).

>>> shown = Display("speed=rpm, power=kW")
>>> shown.unit("phidot", "rad/s"), shown.unit("power:motor", "W"), shown.unit("phi", "rad")
('rpm', 'kW', 'rad')
>>> shown.values("phidot", "rad/s", [157.07963267948966])
(array([1500.]), 'rpm')
"""
from __future__ import annotations

import numpy as np

from mechdyn.errors import MechdynError

__all__ = ["KINDS", "Display", "column_units", "kind_of", "cost_line", "tidy", "ROUNDING"]

ROUNDING = 64 * np.finfo(float).eps   # relative to its scale, a value this small is 0

# kind -> its SI unit (the text columns carry)
KINDS = {"angle": "rad", "speed": "rad/s", "acceleration": "rad/s^2", "length": "m",
         "velocity": "m/s", "linear_acceleration": "m/s^2", "force": "N",
         "moment": "N*m", "power": "W", "time": "s"}


def kind_of(unit: str) -> str:
    """The kind of a column's SI unit (``"N*m"``: ``"moment"``), or ``""``."""
    return next((kind for kind, si in KINDS.items() if si == unit), "")


class Display:
    """Display units by kind or column name: ``"speed=rpm,power=kW"`` or a dict."""

    def __init__(self, choices=None):
        if isinstance(choices, Display):
            choices = choices.choices
        if isinstance(choices, str):
            pairs = [part.partition("=") for part in choices.split(",") if part.strip()]
            if any(not sep or not unit.strip() for _, sep, unit in pairs):
                raise MechdynError(f"units {choices!r}: expected KIND=UNIT pairs separated "
                                   f"by commas, e.g. speed=rpm,power=kW (kinds: "
                                   f"{', '.join(KINDS)}; or a column name)")
            choices = {key.strip(): unit.strip() for key, _, unit in pairs}
        self.choices = dict(choices or {})

    def unit(self, column: str, si: str) -> str:
        """The unit to show ``column`` (measured in ``si``) in."""
        if column in self.choices:
            return self.choices[column]
        kind = kind_of(si)
        return self.choices.get(kind, si) if kind else si

    def values(self, column: str, si: str, values):
        """``(values, unit)``: the values converted to the display unit."""
        unit = self.unit(column, si)
        if unit == si or not si:
            return np.asarray(values, dtype=float), si
        from mechdyn.units import UnitError, convert
        try:
            return convert(values, si, unit), unit
        except UnitError as error:
            raise MechdynError(f"units: {column} ({si}): {error}") from None

    def check(self, columns: dict):
        """Refuse keys that name neither a kind nor one of ``columns`` (name -> SI)."""
        unknown = [key for key in self.choices if key not in KINDS and key not in columns]
        if unknown:
            raise MechdynError(f"units: {', '.join(unknown)} is neither a kind "
                               f"({', '.join(KINDS)}) nor a column "
                               f"({', '.join(columns)})")
        for column, si in columns.items():
            self.values(column, si, [0.0])


def tidy(values, scale=None) -> np.ndarray:
    """``values`` as a summary shows them: within rounding of zero relative to ``scale``
    (the quantity's largest magnitude in the run; default the largest of ``values``)
    they are exactly 0, and no zero is negative (a flywheel at rest, not -7.8e-16 rad/s
    or -0 J).

    >>> tidy([10.2337, -7.77156e-16, -0.0]).tolist()
    [10.2337, 0.0, 0.0]
    >>> tidy([1.0388e-28], scale=18018.0).tolist(), tidy([1e-9], scale=1.0).tolist()
    ([0.0], [1e-09])
    """
    values = np.asarray(values, dtype=float)
    if scale is None:
        scale = np.max(np.abs(values), initial=0.0)
    return np.where(np.abs(values) <= ROUNDING * abs(scale), 0.0, values) + 0.0


def column_units(result) -> dict:
    """The SI unit of every column of ``result.columns()`` (``""`` where unknown)."""
    units = {"t": "s"}
    for c in result.coordinates:
        units[c] = result.units.get(c, "rad")
    n = len(result.coordinates)
    for i, c in enumerate(result.coordinates):
        units[result.state_names[n + i]] = _per(units[c], "s")
    for c, name in zip(result.coordinates, result.acceleration_names):
        units[name] = _per(units[c], "s^2")
    for label in result.output_labels:
        units[label] = result.units.get(label, "W" if label.startswith("power:") else "")
    return units


def _per(unit, time):
    return f"{unit}/{time}" if unit not in ("", "1") else f"1/{time}"


def cost_line(stats) -> str:
    """What a run cost, from its ``stats``: method, steps, RHS calls, Jacobians, time."""
    return (f"{stats['method']}: {stats['steps']} steps, {stats['nfev']} RHS calls, "
            f"{stats.get('njev', 0)} Jacobians, {stats.get('wall_time', 0) * 1e3:.1f} ms")


REPEATED = 3          # an element's event of one kind more often than this is grouped


def event_groups(events, t_start=0.0, t_end=1.0) -> list:
    """Events as ``(text, label, times)`` in the order they first happen (``label``
    the short text a plot writes): one each, but the
    repeated events of one element and kind (more than ``REPEATED``) as one group,
    ``"slip guide: 83 times, t = 0.05 ... 3.98 s"``. Times closer to the start than
    1e-12 of the run are the start (an event located at 5e-17 s happened at 0).

    >>> from types import SimpleNamespace as E
    >>> slips = [E(time=t, kind="slip", name="guide", detail="") for t in (5e-17, 1, 2, 3)]
    >>> [text for text, _, _ in event_groups(slips, 0, 4)]
    ['slip guide: 4 times, t = 0 ... 3 s']
    """
    span = max(t_end - t_start, 1e-300)

    def at(time):
        return t_start if abs(time - t_start) < 1e-12 * span else time
    by_element = {}
    for event in sorted(events, key=lambda e: e.time):
        by_element.setdefault((event.kind, event.name), []).append(event)
    groups = []
    for (kind, name), group in by_element.items():
        times = [at(e.time) for e in group]
        if len(group) > REPEATED:
            text = (f"{kind} {name}: {len(group)} times, t = {times[0]:.4g} ... "
                    f"{times[-1]:.4g} s")
            groups.append((text, text, times))
        else:
            groups += [(f"t = {time:.6g} s: {kind} {name} ({e.detail})",
                        f"{kind} {name} (t = {time:.4g} s)", [time])
                       for e, time in zip(group, times)]
    return sorted(groups, key=lambda group: group[2][0])

"""A linkage in a few lines (:meth:`Linkage.describe <mechdyn.analyse.linkage.Linkage>`):
its class as a designer names it, the crank's range, the singular positions with their
crank angles, each dependent coordinate's extremes (or that it stays constant), the
range of ``I_red`` and of the transmission angle.

Classes: a four-bar by Grashof's criterion and, at Grashof's equality, by its lengths
and branch (parallelogram, anti-parallelogram, deltoid); a slider-crank (one loop of a
crank, a rod, a slider's travel and a fixed offset) by ``r + |e|`` against the rod.
What cannot be determined is said in its line, never a traceback.

>>> import mechdyn as md
>>> phi, th, psi = md.coordinates("phi theta psi")
>>> par = md.Mechanism("parallelogram", [phi, th, psi])
>>> for name, angle in (("crank", phi), ("coupler", th), ("rocker", psi)):
...     _ = par.link(name, J=1, angle=angle)
>>> _ = par.loop("ABCD", (1, phi), (3, th), (-1, psi), (-3, 0))
>>> text = md.Linkage(par, guess={phi: 0.5, th: 0, psi: 0.5}).describe(points=73)
>>> print("\\n".join(text.splitlines()[1:5]))
  class: parallelogram (ground 3, crank 1, coupler 3, rocker 1; shortest: crank)
  the crank turns fully
  change point of loop ABCD at phi = 3.14159265 rad (180.0000 deg)
  change point of loop ABCD at phi = 6.28318531 rad (360.0000 deg)
"""
from __future__ import annotations

import numpy as np
import sympy as sp

from mechdyn.analyse.linkage_limits import (answers, branch_sweep, crank_range, extremes,
                                            grashof, is_constant, singularities,
                                            transmission_angle)
from mechdyn.analyse.linkage_types import LinkageError
from mechdyn.declare.elements import Constraint
from mechdyn.errors import MechdynError

__all__ = ["describe", "linkage_class"]


def linkage_class(self):
    """The class of a four-bar or slider-crank in words (with its lengths), or None
    for another linkage."""
    try:
        return str(grashof(self))
    except LinkageError:
        return _slider_crank(self)


def _slider_crank(self):
    """A loop of the crank, a rod, a slider's travel (a length that is a coordinate
    along a fixed direction) and an optional fixed offset; None otherwise."""
    loops = [e for e in self.mechanism.elements.values() if isinstance(e, Constraint)]
    if len(loops) != 1 or len(loops[0].terms) not in (3, 4):
        return None
    values = {s: sp.Float(v) for s, v in zip(self.functions.params, self.p)}
    crank = self.eqs.q[self.independent[0]]
    coordinates = set(self.eqs.q)
    roles = {}
    for length, angle in loops[0].terms:
        length = sp.sympify(self.eqs.to_plain(length)).xreplace(values)
        angle = sp.sympify(self.eqs.to_plain(angle)).xreplace(values)
        key = ("slider" if length.free_symbols & coordinates and angle.is_number else
               "crank" if angle.free_symbols == {crank} and length.is_number else
               "rod" if length.is_number and angle.free_symbols & coordinates else
               "offset" if length.is_number and angle.is_number else None)
        if key is None or key in roles:
            return None
        roles[key] = (length, angle)
    if set(roles) - {"offset"} != {"slider", "crank", "rod"}:
        return None
    r, l = abs(float(roles["crank"][0])), abs(float(roles["rod"][0]))
    e = 0.0
    if "offset" in roles:
        e = abs(float(roles["offset"][0] * sp.sin(roles["offset"][1] - roles["slider"][1])))
    kind = ("slider-crank" if r + e < l * (1 - 1e-12) else "slider-crank with change "
            "points" if r + e <= l * (1 + 1e-12) else "slider-rocker (r + e > l)")
    return f"{kind} (crank {r:.6g}, rod {l:.6g}, offset {e:.6g})"


@answers("the description")
def describe(self, points=361) -> str:
    """A few lines on the linkage over a crank revolution (or its range on this
    branch): class, range, singular positions, extremes, ``I_red``, transmission
    angle."""
    deg = np.degrees
    crank = self.names[self.independent[0]]
    lines = [f"{self.mechanism.name}: crank {crank}, dependent "
             f"{', '.join(self.names[i] for i in self.dependent)}"]
    kind = linkage_class(self)
    if kind:
        lines.append(f"  class: {kind}")
    start = self._last[self.independent[0]]
    limits = crank_range(self, start, points)
    found = singularities(self, start, points)
    lines.append("  the crank turns fully" if limits is None else
                 f"  crank range {deg(limits[0]):.4f} .. {deg(limits[1]):.4f} deg on this "
                 "branch (toggle positions at both ends; beyond them the loops cannot be "
                 "closed)")
    lines += [f"  {item}" for item in found] or ["  no toggle position or change point"]
    sweep = branch_sweep(self, start, points, limits)
    for i in self.dependent:
        lines += _coordinate_lines(self, sweep, i, start, points, limits, crank)
    inertia = sweep.inertia
    low, high = np.argmin(inertia), np.argmax(inertia)
    mean = np.mean(inertia[:-1] if limits is None else inertia)
    lines.append(f"  I_red constant: {mean:.6g} kg m^2" if np.ptp(inertia) <= 1e-9 * mean else
                 f"  I_red: {inertia[low]:.6g} .. {inertia[high]:.6g} kg m^2 (at {crank} = "
                 f"{deg(sweep.phi[low]):.1f}, {deg(sweep.phi[high]):.1f} deg), mean {mean:.6g}")
    try:
        mu = deg(transmission_angle(self, sweep))
        worst = int(np.argmax(np.abs(mu - 90)))
        lines.append(f"  transmission angle: {mu.min():.2f} .. {mu.max():.2f} deg, farthest "
                     f"from 90 deg at {crank} = {deg(sweep.phi[worst]):.1f} deg")
    except MechdynError:
        pass                                   # not a four-bar
    self.position(start)
    return "\n".join(lines)


def _coordinate_lines(self, sweep, i, start, points, limits, crank):
    """The extremes of dependent coordinate ``i`` (stroke and time ratio where the
    crank turns fully), or that it stays constant."""
    deg = np.degrees
    name = self.names[i]
    unit = self.mechanism.units.get(name, "rad")
    shown = (lambda v: f"{deg(v):.4f} deg") if unit == "rad" else \
        (lambda v: f"{v:.6g} {unit}")
    if is_constant(sweep, i):
        return [f"  {name} constant: {shown(float(np.mean(sweep.q[i])))}"]
    try:
        ends = extremes(self, name, start, points)
    except MechdynError as error:
        return [f"  {name} extremes: not determined ({error})"]
    text = ", ".join(f"{shown(v)} at {crank} = {deg(a):.4f} deg" for a, v in ends)
    none = "none (turns fully)" if limits is None else "none (monotonic over the range)"
    lines = [f"  {name} extremes: {text or none}"]
    if len(ends) == 2 and limits is None:
        forward = (ends[1][0] - ends[0][0]) % (2 * np.pi)
        slow, fast = max(forward, 2 * np.pi - forward), min(forward, 2 * np.pi - forward)
        lines.append(f"    stroke {shown(abs(ends[1][1] - ends[0][1]))}, crank "
                     f"angles {deg(forward):.4f} / {360 - deg(forward):.4f} deg, time "
                     f"ratio {slow / fast:.4f}")
    return lines

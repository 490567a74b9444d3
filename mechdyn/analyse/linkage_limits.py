"""Special positions of a linkage: toggle positions and the crank's range, change points,
the output's extreme (dead-centre) positions, Grashof's classification, the transmission
angle and coupler curves. Methods of :class:`mechdyn.Linkage`.

A *toggle* is where the loop locks the dependent coordinates (``G_d`` loses rank): the
crank cannot pass, and beyond it the loop cannot be closed (a non-Grashof crank's end of
range). A *change point* is where the constraints themselves lose rank (``G``), so the
linkage may leave on another branch. The output's *extreme positions* are where its
transmission function ``dq/dphi`` vanishes: a rocker's swing, a slider's stroke, the
quick-return time ratio.

>>> import sympy as sp, mechdyn as md
>>> phi, th2, th3 = md.coordinates("phi theta_2 theta_3")
>>> rocker = md.Mechanism("triple rocker", [phi, th2, th3])
>>> for name, angle in [("input", phi), ("coupler", th2), ("output", th3)]:
...     _ = rocker.link(name, J=1, angle=angle)
>>> _ = rocker.loop("ABCD", (3, phi), (3.5, th2), (-5, th3), (-2, 0))
>>> linkage = md.Linkage(rocker, guess={phi: np.pi, th2: 1.2, th3: 2.2})
>>> low, high = linkage.crank_range()         # coupler and rocker folded: |AD| = 5 - 3.5
>>> [round(float(np.degrees(x)), 6) for x in (low, high)]   # 13 - 12 cos(phi) = 1.5^2
[26.38433, 333.61567]
>>> str(linkage.singularities()[0])
'toggle of loop ABCD at phi = 0.460493425 rad (26.3843 deg)'

"""
from __future__ import annotations

from dataclasses import replace
from functools import wraps
from itertools import combinations

import numpy as np
import sympy as sp
from scipy.optimize import brentq, minimize_scalar, root

from mechdyn.analyse.linkage_types import CrankSweep, LinkageError, Singularity
from mechdyn.analyse.linkage_types import grashof as classify
from mechdyn.analyse.linkage_walk import CHANGE_POINT, _weakest_row
from mechdyn.errors import MechdynError

__all__ = ["singularities", "crank_range", "extremes", "grashof", "transmission_angle",
           "coupler_curve", "branch_sweep", "is_constant", "answers"]

_SUSPECT = 0.5              # a local minimum of the rank margin below this is refined


def answers(what):
    """Decorate an analysis: a library's error inside it (scipy's, numpy's) becomes a
    :class:`~mechdyn.analyse.linkage.LinkageError` naming ``what`` it could not
    determine; mechdyn's own errors pass.

    >>> @answers("the toggle")
    ... def toggle(self):
    ...     raise ValueError("no sign change")
    >>> class Machine:
    ...     mechanism = type("Mechanism", (), {"name": "press"})
    >>> try:
    ...     toggle(Machine())
    ... except MechdynError as error:
    ...     print(type(error).__name__, error)
    LinkageError 'press': the toggle could not be determined (ValueError: no sign change)
    """
    def wrap(function):
        @wraps(function)
        def analysis(self, *args, **kwargs):
            try:
                return function(self, *args, **kwargs)
            except MechdynError:
                raise
            except (ArithmeticError, ValueError, RuntimeError, np.linalg.LinAlgError) as error:
                raise LinkageError(f"{self.mechanism.name!r}: {what} could not be "
                                   f"determined ({type(error).__name__}: {error})") from None
        return analysis
    return wrap


def _limit(self, q_good, phi_good, phi_bad):
    """The last crank angle the loops close at, between a reachable and an unreachable
    one (the toggle position by Newton's method from the last position reached, else
    after bisection). Returns the angle and the positions there."""
    low, high = sorted((phi_good, phi_bad))
    angle, q = _fold(self, q_good, phi_good)
    if low <= angle <= high and angle != phi_good:
        return angle, q
    while abs(phi_bad - phi_good) > 1e-7 * (1 + abs(phi_good)):
        middle = (phi_good + phi_bad) / 2
        q, _ = self._walk(q_good, np.array([middle]))
        if q is None:
            phi_bad = middle
        else:
            q_good, phi_good = q, middle
    return _fold(self, q_good, phi_good)


def _fold(self, q, phi):
    """The toggle position itself, near ``q``: Newton's method (scipy's hybrid method)
    on the loops and ``det G_d = 0`` over all coordinates, where the bisection ends
    because Newton in the dependent coordinates alone converges only linearly there."""
    _, grads = self.closure(q)
    scale = abs(np.prod(np.linalg.norm(grads[:, self.dependent], axis=1)))

    def equations(values):
        g, grads = self.closure(values)
        return np.append(g, np.linalg.det(grads[:, self.dependent]) / scale)
    solution = root(equations, q, method="hybr", options={"xtol": 1e-15})
    index = self.independent[0]
    if np.max(np.abs(equations(solution.x))) < 1e-12 and \
            np.max(np.abs(solution.x - q)) < 0.5:      # the same branch, near by
        return float(solution.x[index]), solution.x
    return phi, q


def _scan(self, start, span, points):
    """Walk from ``start`` over ``span``: (angles reached, positions, the toggle angle
    and positions if the walk stopped at one, else None)."""
    q = self.position(start)
    grid = start + np.linspace(0.0, span, points)
    reached, positions = [grid[0]], [q]
    for value in grid[1:]:
        next_q, _ = self._walk(q, np.array([value]))
        if next_q is None:
            angle, q_limit = _limit(self, q, reached[-1], value)
            return np.array(reached), np.array(positions).T, (angle, q_limit)
        q = next_q
        reached.append(value)
        positions.append(q)
    return np.array(reached), np.array(positions).T, None


@answers("the crank's range")
def crank_range(self, start=None, points=721):
    """``(low, high)``: the crank angles between which the loops close on this branch,
    or None when the crank turns fully. ``start``: an angle inside the range (default:
    the last position solved)."""
    self._one_dof("crank_range")
    start = self._last[self.independent[0]] if start is None else float(start)
    _, forward_q, forward = _scan(self, start, 2 * np.pi, points)
    if forward is None:
        return None
    _, _, backward = _scan(self, start, -2 * np.pi, points)
    self.position(start)
    return (backward[0] if backward else forward[0] - 2 * np.pi, forward[0])


@answers("the singular positions")
def singularities(self, start=None, points=721) -> list:
    """Toggle positions (ends of the crank's range) and change points over one crank
    revolution from ``start``, each a :class:`~mechdyn.analyse.linkage.Singularity` naming its
    loop and crank angle, in the order met."""
    self._one_dof("singularities")
    name = self.names[self.independent[0]]
    start = self._last[self.independent[0]] if start is None else float(start)
    found = []
    for span in (2 * np.pi, -2 * np.pi):
        angles, positions, stop = _scan(self, start, span, points)
        found += [Singularity("change point", self.loop_of(row), angle, name)
                  for angle, row in _change_points(self, angles, positions)]
        if stop is not None:
            angle, q = stop
            found.append(Singularity("toggle", self.loop_of(_locking_row(self, q)),
                                     angle, name))
        if stop is None:
            break
    self.position(start)
    unique = []
    for item in sorted(found, key=lambda s: s.at):
        if not any(u.kind == item.kind and abs(u.at - item.at) < 1e-6 for u in unique):
            unique.append(item)
    return unique


def _change_points(self, angles, positions):
    """Crank angles where ``G`` (all coordinates) loses rank along a walk: local minima
    of its rank margin, each refined (:func:`_crossing`) and kept where the margin
    vanishes there."""
    ratio = np.array([self.margin(positions[:, j]) for j in range(len(angles))])
    out = []
    for j in range(1, len(angles) - 1):
        if ratio[j] < ratio[j - 1] and ratio[j] <= ratio[j + 1] and ratio[j] < _SUSPECT:
            angle, q = _crossing(self, positions[:, j - 1], angles[j - 1], angles[j + 1])
            if q is not None and self.margin(q) < CHANGE_POINT:
                out.append((angle, _weakest_row(self, q)))
    return out


def _crossing(self, q_before, low, high):
    """The change point between the crank angles ``low`` and ``high`` (walked from
    ``q_before`` at ``low``): where the largest ``m x m`` minor of ``G`` changes sign,
    by bisection and then a secant through points 1e-4 rad either side (positions at
    the change point itself are accurate only to the root of the tolerance); where no
    minor changes sign, the least rank margin."""
    def walked(value):
        return self._walk(q_before, np.array([value]))[0]

    def minors(value):
        q = walked(value)
        if q is None:
            return np.full(1, np.nan)
        grads = self.closure(q)[1]
        return np.array([np.linalg.det(grads[:, list(c)]) for c in
                         combinations(range(self.n), self.m)])
    ends = minors(low), minors(high)
    k = int(np.argmax(np.abs(ends[0]))) if np.all(np.isfinite(ends[0])) else 0
    if len(ends[1]) > k and ends[0][k] * ends[1][k] < 0:
        root = brentq(lambda v: minors(v)[k], low, high, xtol=1e-6)
        h = 1e-4
        left, right = minors(root - h)[k], minors(root + h)[k]
        if np.isfinite(left) and np.isfinite(right) and left != right:
            root = root - h + 2 * h * left / (left - right)
    else:
        def measure(value):
            q = walked(value)
            return 1.0 if q is None else self.margin(q)
        root = minimize_scalar(measure, bounds=tuple(sorted((low, high))), method="bounded",
                               options={"xatol": 1e-12}).x
    return float(root), walked(float(root))


def _locking_row(self, q):
    """The constraint row most nearly dependent on the others at ``q``."""
    _, grads = self.closure(q)
    part = grads[:, self.dependent]
    part = part / np.maximum(np.linalg.norm(part, axis=1, keepdims=True), 1e-300)
    residuals = []
    for k in range(len(part)):
        others = np.delete(part, k, axis=0)
        if not len(others):
            return k
        fit = np.linalg.lstsq(others.T, part[k], rcond=None)[0]
        residuals.append(np.linalg.norm(part[k] - others.T @ fit))
    return int(np.argmin(residuals))


@answers("the sweep over the crank's range")
def branch_sweep(self, start, points=361, limits="find"):
    """A sweep over one crank revolution from ``start``, or for a crank that cannot turn
    fully over its range on this branch, 1e-6 of it short of the toggles: walked from
    ``start`` towards each end (walking away from a toggle could take either branch)."""
    limits = crank_range(self, start, points) if limits == "find" else limits
    here = self.position(start)
    if limits is None:
        sweep = self.sweep(start + np.linspace(0.0, 2 * np.pi, points))
    else:
        margin = 1e-6 * (limits[1] - limits[0])
        grid = np.linspace(limits[0] + margin, limits[1] - margin, points)
        down = self.sweep(np.concatenate([[start], grid[grid < start][::-1]]))
        self._last = here
        up = self.sweep(grid[grid >= start])
        parts = [np.concatenate([x[..., :0:-1], y], axis=-1) for x, y in
                 zip((down.phi, down.q, down.ratio, down.second, down.inertia,
                      down.inertia_slope), (up.phi, up.q, up.ratio, up.second, up.inertia,
                                            up.inertia_slope))]
        sweep = CrankSweep(*parts, self.names)
    self._last = here
    return sweep


def is_constant(sweep, row):
    """Whether a coordinate keeps its value over a sweep (a parallelogram's coupler)."""
    values = sweep.q[row]
    return bool(np.ptp(values) <= 1e-9 * (1 + np.max(np.abs(values))))


@answers("the extreme positions")
def extremes(self, coordinate, start=None, points=721) -> list:
    """The extreme positions of a dependent coordinate (where ``dq/dphi = 0``): a
    rocker's ends of swing, a slider's dead centres. A list of ``(crank angle, value)``
    over one revolution from ``start`` (or over the crank's range on this branch);
    empty for a coordinate that turns fully or stays constant."""
    sweep_start = self._last[self.independent[0]] if start is None else float(start)
    sweep = branch_sweep(self, sweep_start, points)
    row = sweep._row(coordinate)
    if is_constant(sweep, row):
        return []
    ratio = sweep.ratio[row]
    small = 1e-12 * max(float(np.max(np.abs(ratio))), 1e-300)
    ratio = np.where(np.abs(ratio) <= small, 0.0, ratio)
    out = []
    for j in range(len(ratio) - 1):
        if ratio[j] == 0 and (not out or out[-1][0] != sweep.phi[j]) and 0 < j:
            out.append((float(sweep.phi[j]), float(sweep.q[row, j])))
        elif ratio[j] * ratio[j + 1] < 0:
            out.append(_turning_point(self, sweep, row, j, coordinate, LinkageError))
    self.position(sweep_start)
    return out


def _turning_point(self, sweep, row, j, coordinate, error):
    """Where ``dq/dphi`` of ``row`` changes sign between sweep points ``j``, ``j + 1``
    (positions walked from point ``j``, on its branch)."""
    def walked(value):
        q, _ = self._walk(sweep.q[:, j], np.array([value]))
        if q is None:
            raise error(f"extremes of {coordinate}: the loops do not close at "
                        f"{self._independent_text(value)} between two positions of the "
                        "sweep", at=float(value))
        return q
    try:
        angle = brentq(lambda v: self.velocity_matrix(walked(v))[row, 0], sweep.phi[j],
                       sweep.phi[j + 1], xtol=1e-14, rtol=1e-15)
    except (ValueError, np.linalg.LinAlgError) as failure:
        raise error(f"extremes of {coordinate}: the turning point between "
                    f"{self._independent_text(sweep.phi[j])} and "
                    f"{self._independent_text(sweep.phi[j + 1])} could not be located "
                    f"({failure})", at=float(sweep.phi[j])) from None
    return float(angle), float(walked(angle)[row])


def _four_bar(self):
    """The roles of a four-bar loop: (lengths by role, term angles by role, signs,
    index of each role in the loop's order)."""
    from mechdyn.declare.elements import Constraint
    loops = [e for e in self.mechanism.elements.values() if isinstance(e, Constraint)]
    if len(loops) != 1 or len(loops[0].terms) != 4:
        raise LinkageError(f"{self.mechanism.name!r} is not a four-bar (one loop of four "
                           "terms); Grashof's criterion and its transmission angle need one")
    terms = [(self.eqs.to_plain(l), self.eqs.to_plain(a)) for l, a in loops[0].terms]
    values = {s: sp.Float(v) for s, v in zip(self.functions.params, self.p)}
    crank_symbol = self.eqs.q[self.independent[0]]
    ground = [k for k, (_, a) in enumerate(terms) if not (a.free_symbols & set(self.eqs.q))]
    crank = [k for k, (_, a) in enumerate(terms) if a.free_symbols & set(self.eqs.q)
             == {crank_symbol}]
    if len(ground) != 1 or len(crank) != 1:
        raise LinkageError(f"{self.mechanism.name!r}: a four-bar loop needs one ground term "
                           "(a constant angle) and one crank term (the independent angle)")
    g, c = ground[0], crank[0]
    roles = {"ground": g, "crank": c, "coupler": (g + 2) % 4, "rocker": (c + 2) % 4}
    lengths = {}
    for role, k in roles.items():
        length = sp.sympify(terms[k][0]).xreplace(values)
        if not length.is_number:
            raise LinkageError(f"four-bar term {k + 1}: length {terms[k][0]} is not constant")
        lengths[role] = float(length)
    return lengths, {role: terms[k][1] for role, k in roles.items()}, roles


def grashof(self):
    """Grashof's classification of a four-bar loop (terms in order around the loop); a
    parallelogram's branch at the current position names it or its crossed form."""
    lengths, angles, _ = _four_bar(self)
    found = classify(lengths["ground"], lengths["crank"], lengths["coupler"],
                     lengths["rocker"])
    if found.kind.startswith("parallelogram or"):       # the branch decides
        at = dict(zip(self.eqs.q, self._last))
        crank, rocker = (lengths[r] * np.exp(1j * float(sp.sympify(angles[r]).xreplace(at)))
                         for r in ("crank", "rocker"))
        crossed = abs(crank + rocker) > 1e-6 * max(abs(v) for v in lengths.values())
        found = replace(found, kind="anti-parallelogram" if crossed else "parallelogram")
    return found


@answers("the transmission angle")
def transmission_angle(self, sweep, between=None):
    """The transmission angle (rad, 0..pi; 90 deg ideal, 0 or 180 deg at a toggle) at
    each position of a sweep: for a four-bar the interior angle between coupler and
    rocker; with ``between=(angle_a, angle_b)`` the angle between those directions."""
    if between is None:
        lengths, angles, roles = _four_bar(self)
        adjacent = (roles["rocker"] - roles["coupler"]) % 4 == 1
        first, second = ("coupler", "rocker") if adjacent else ("rocker", "coupler")
        sign = -np.sign(lengths[first] * lengths[second])
        exprs = [angles[first] - angles[second]]
    else:
        sign, exprs = 1.0, [self.eqs.to_plain(sp.sympify(between[0] - between[1]))]
    difference = self.evaluate([_as_function(self, e) for e in exprs], sweep)[0]
    return np.arccos(np.clip(sign * np.cos(difference), -1.0, 1.0))


def coupler_curve(self, point, sweep):
    """The path ``(x, y)`` of a point (two expressions of the coordinates) over a
    sweep: a coupler curve."""
    x, y = self.evaluate([point[0], point[1]], sweep)
    return x, y


def _as_function(self, expr):
    """A plain-symbol expression back in the coordinates (functions of t)."""
    back = {sp.Symbol(name): q for name, q in zip(self.names, self.eqs.coordinates)}
    return expr.xreplace(back)

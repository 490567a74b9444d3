"""The constrained equations of a friction mode, and how far each stuck group is from
letting go.

Unknowns: the accelerations ``a``, the closed loops' multipliers ``lambda_L`` (a lossy
gear's mesh is one), the holding force ``lambda_G`` of each stuck group (along its
leader's gradient) and the loss moment ``l`` of each sliding lossy gear:

    M a - G_L' lambda_L - G_G' lambda_G + sum g_i l_i = f
    G_L a = -bias_L,    G_G a = -bias_G
    l_i + c lambda_L[i] = s_i b        (the line (c, b) of the gear's law, tau = -lambda_L)
    lambda_L[i] = -s_i x*              (a self-locking gear at its corner)

The line of each sliding gear is the one its own solution confirms (the loss law is
convex in the mesh moment, and the mesh moment grows with it, so one line fits).

A stuck group holds while a share of its force exists that keeps every member within
its interval: a friction ``[-peak m, peak m]``, a one-way clutch ``[-max(peak m,
release), inf)``, a stop in contact ``[0, inf)``, a lossy gear ``[-L(tau), L(-tau)]``
with ``tau`` its mesh moment, which depends on how the group's force is shared when a
gear holds together with other elements (a bearing friction on its input shaft): then a
small linear programme finds the share with the largest margin.

>>> import numpy as np
>>> interval_margin(3.0, -2.0, 5.0), interval_margin(6.0, -2.0, 5.0)   # (margin, way)
((2.0, 0), (-1.0, -1))
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from itertools import product

import numpy as np

__all__ = ["Solution", "solve", "interval_margin", "group_check", "member_intervals"]


@dataclass
class Solution:
    """Accelerations, group holding forces, loop multipliers, the loss moment of each
    gear (by gear index; NaN for a stuck gear) and the line each sliding gear uses."""
    a: np.ndarray
    holding: np.ndarray
    loops: np.ndarray
    losses: dict
    lines: dict


def solve(view, mode, hint=None) -> Solution:
    """The constrained equations of ``mode`` at the state of ``view`` (a
    :class:`~mechdyn.simulate.friction.StateView`); ``hint``: the lines of the gears to try
    first (by gear index)."""
    n = view.n
    loop_rows, loop_bias = view.terms["constraint_gradient"], view.terms["constraint_bias"]
    leaders = [group[0][0] for group in mode.groups]
    sliding = [i for i, (_, k, _) in enumerate(view.gears) if mode.signs and mode.signs[k]] \
        if view.gears else []
    if not sliding and not len(loop_rows) and not leaders:
        a = view.forcing / view.mass[0, 0] if n == 1 else \
            np.linalg.solve(view.mass, view.forcing)
        return Solution(a, np.zeros(0), np.zeros(0), {}, {})
    group_rows = view.gradients[leaders].reshape(-1, n)
    if not sliding:
        return _linear_solve(view, mode, loop_rows, loop_bias, group_rows, leaders, (), {}, {})
    laws = {i: view.law(i) for i in sliding}
    choice = {i: (hint or {}).get(i, 0) for i in sliding}
    options = [choice] + [dict(zip(sliding, lines)) for lines in
                          product(*[range(len(laws[i].lines()) if not laws[i].self_locking
                                          else 2) for i in sliding])]
    best = None
    for lines in options:
        solution = _linear_solve(view, mode, loop_rows, loop_bias, group_rows, leaders,
                                 sliding, laws, lines)
        misfit = _misfit(view, mode, solution, laws, lines)
        if misfit <= 0:
            return solution
        if best is None or misfit < best[0]:
            best = (misfit, solution)
    return best[1]


def _linear_solve(view, mode, loop_rows, loop_bias, group_rows, leaders, sliding, laws,
                  lines):
    n, m_l, m_g, m_s = view.n, len(loop_rows), len(group_rows), len(sliding)
    size = n + m_l + m_g + m_s
    system, right = np.zeros((size, size)), np.zeros(size)
    system[:n, :n] = view.mass
    right[:n] = view.forcing
    rows = np.concatenate([loop_rows, group_rows]) if m_l else group_rows
    system[:n, n:n + m_l + m_g] = -rows.T
    system[n:n + m_l + m_g, :n] = rows
    right[n:n + m_l] = -loop_bias
    right[n + m_l:n + m_l + m_g] = -view.biases[leaders]
    for j, i in enumerate(sliding):
        name, k, c = view.gears[i]
        row, sign = n + m_l + m_g + j, mode.signs[k]
        system[:n, row] = view.gradients[k]
        law, line = laws[i], lines[i]
        if law.self_locking and line == 1:            # the corner: tau = -lambda = 0
            system[row, n + c] = 1.0
        else:
            slope, offset = law.lines()[line]
            system[row, row], system[row, n + c], right[row] = 1.0, slope, sign * offset
    x = np.linalg.solve(system, right)
    losses = {i: x[n + m_l + m_g + j] for j, i in enumerate(sliding)}
    return Solution(x[:n], x[n + m_l:n + m_l + m_g], x[n:n + m_l], losses,
                    {i: lines[i] for i in sliding})


def _misfit(view, mode, solution, laws, lines) -> float:
    """How far the sliding gears' lines are from the ones their mesh moments select
    (0: every line fits)."""
    worst = 0.0
    for i, line in lines.items():
        _, k, c = view.gears[i]
        sign, law = mode.signs[k], laws[i]
        x = -sign * solution.loops[c]                   # s * tau
        if law.self_locking and line == 1:
            worst = max(worst, law.loss(1e-300) - sign * solution.losses[i])
        elif law.self_locking:
            worst = max(worst, -x)
        else:
            worst = max(worst, law.loss(x) - (lambda s, o: s * x + o)(*law.lines()[line]))
    return worst


# ----------------------------------------------------------------- holding margins
def interval_margin(force, low, high) -> tuple:
    """``(margin, way)``: how far ``force`` lies inside ``[low, high]`` (negative
    outside) and the way the group slides when it is outside (+1 below ``low``: the
    loads push forward harder than it holds; -1 above ``high``; 0 inside)."""
    margin = min(high - force, force - low)
    if margin >= 0:
        return margin, 0
    return margin, 1 if force - low < high - force else -1


def member_intervals(view, members, solution) -> list:
    """The interval of each member's own force (``None`` for a lossy gear in a group of
    several: its interval depends on the share)."""
    out = []
    for k, _ in members:
        kind = view.kind(k)
        if kind == "contact":
            out.append((0.0, math.inf))
        elif kind == "gear":
            i = view.gear_of(k)
            tau = -solution.loops[view.gears[i][2]]
            out.append(view.law(i).holding_interval(tau, view.tau_tolerance(i))
                       if len(members) == 1 else None)
        else:
            capacity = view.peak[k] * max(view.magnitude[k], 0.0)
            if kind == "one_way":
                out.append((-max(capacity, view.release[k]), math.inf))
            else:
                out.append((-capacity, capacity))
    return out


def group_check(view, members, force, solution) -> tuple:
    """``(margin, way)`` of a stuck group (see :func:`interval_margin`)."""
    intervals = member_intervals(view, members, solution)
    if all(interval is not None for interval in intervals):
        low = high = 0.0
        for (k, alpha), (lo, hi) in zip(members, intervals):
            ends = (alpha * lo, alpha * hi)
            low, high = low + min(ends), high + max(ends)
        return interval_margin(force, low, high)
    return _shared_check(view, members, force, solution, intervals)


def shares(view, members, force, solution) -> list:
    """Each member's force: in proportion to the capacities on the side the group's
    force needs (members that hold without limit take it all); with a gear among
    several, the share with the largest margin."""
    intervals = member_intervals(view, members, solution)
    if any(interval is None for interval in intervals):
        return _shared_check(view, members, force, solution, intervals, want_shares=True)
    sides = [hi if force * alpha >= 0 else -lo for (_, alpha), (lo, hi) in
             zip(members, intervals)]
    unlimited = [math.isinf(side) for side in sides]
    if any(unlimited):
        weights = [1.0 if u else 0.0 for u in unlimited]
    else:
        weights = [abs(alpha) * side for (_, alpha), side in zip(members, sides)]
    total = sum(weights)
    if total <= 0:
        weights, total = [1.0] * len(members), float(len(members))
    return [force * w / total / alpha for (_, alpha), w in zip(members, weights)]


def _shared_check(view, members, force, solution, intervals, want_shares=False):
    """A group holding a lossy gear with other members: the largest margin over the
    shares of its force, for each choice of the law's line on each side of each gear
    (exactly in one dimension, two members; a linear programme beyond)."""
    m = len(members)
    p_loops = _loop_pseudo_inverse(view)
    leader_gradient = view.gradients[members[0][0]]
    base_rows = []                      # (coefficients, bound, low side?): row . x + z <= bound
    for j, interval in enumerate(intervals):
        if interval is not None:
            unit = np.eye(m)[j]
            if not math.isinf(interval[0]):
                base_rows.append((-unit, -interval[0], True))
            if not math.isinf(interval[1]):
                base_rows.append((unit, interval[1], False))
    gear_choices = []
    for j, ((k, _), interval) in enumerate(zip(members, intervals)):
        if interval is not None:
            continue
        i = view.gear_of(k)
        c = view.gears[i][2]
        tau0 = -solution.loops[c] - p_loops[c] @ leader_gradient * force
        beta = np.array([p_loops[c] @ view.gradients[kk] for kk, _ in members])
        gear_choices.append([(_gear_row(j, m, tau0, beta, view.law(i), sign, line), low)
                             for low, sign in ((True, 1.0), (False, -1.0))
                             for line in range(2)])
    alphas = np.array([alpha for _, alpha in members])
    combos = []
    for picks in product(*[product(choices[:2], choices[2:]) for choices in gear_choices]):
        combos.append(base_rows + [(row, bound, low) for pair in picks
                                   for (row, bound), low in pair])
    best, point = -math.inf, None
    for rows in combos:
        value, x = _maximin(rows, alphas, force)
        if value > best:
            best, point = value, x
    if want_shares:
        return list(point) if point is not None else list(force / alphas / m)
    if best >= 0:
        return best, 0
    low = max(_maximin([r for r in rows if r[2]], alphas, force)[0] for rows in combos)
    high = max(_maximin([r for r in rows if not r[2]], alphas, force)[0] for rows in combos)
    return best, 1 if low < 0 or low < high else -1


def _gear_row(j, m, tau0, beta, law, sign, line):
    """One side of a gear member's condition with ``tau = tau0 + beta . x`` as a row:
    ``sign * lambda_j >= -L(sign * tau)`` by the line ``line`` of the law (for a
    self-locking gear, line 1 is its corner ``sign * tau <= 0``)."""
    unit = np.eye(m)[j]
    if law.self_locking and line == 1:
        return sign * beta, -sign * tau0
    slope, offset = law.lines()[min(line, len(law.lines()) - 1)]
    return -sign * (unit + slope * beta), offset + sign * slope * tau0


def _maximin(rows, alphas, force):
    """``max z`` over the member forces ``x`` with ``alphas . x = force`` and
    ``row . x + z <= bound`` for every row: ``(z, x)``."""
    m = len(alphas)
    cap = 1e6 * (1.0 + abs(force))
    if not rows:
        return cap, force / alphas / m
    particular = np.zeros(m)
    particular[0] = force / alphas[0]
    if m == 2:                  # x = particular + theta * (-alpha_1, alpha_0)
        direction = np.array([-alphas[1], alphas[0]])
        c = np.array([bound - row @ particular for row, bound, _ in rows] + [cap])
        d = np.array([-(row @ direction) for row, _, _ in rows] + [0.0])
        thetas = [0.0]
        for a in range(len(c)):
            for b in range(a):
                if d[a] != d[b]:
                    thetas.append((c[b] - c[a]) / (d[a] - d[b]))
        if np.all(d >= 0) or np.all(d <= 0):         # the best lies at infinity
            flat = d == 0
            return float(np.min(c[flat])), None
        values = [float(np.min(c + d * theta)) for theta in thetas]
        best = int(np.argmax(values))
        return values[best], particular + thetas[best] * direction
    from scipy.optimize import linprog
    result = linprog(np.r_[np.zeros(m), -1.0], A_ub=[list(r) + [1.0] for r, _, _ in rows],
                     b_ub=[b for _, b, _ in rows], A_eq=[list(alphas) + [0.0]], b_eq=[force],
                     bounds=[(None, None)] * m + [(None, cap)], method="highs")
    if result.status != 0:
        return -math.inf, None
    return -result.fun, result.x[:m]


def _loop_pseudo_inverse(view):
    """``P`` with ``lambda_L = P F`` for a constraint force ``F = G_L' lambda_L``."""
    rows = view.terms["constraint_gradient"]
    return np.linalg.solve(rows @ rows.T, rows)

"""Continuation of a linkage's positions along its independent coordinate, one assembly
branch kept, through change points too.

Each position is solved by Newton's method in the dependent coordinates, warm-started
from the previous one with a second-order predictor (``q + q' h + q'' h^2 / 2``); a
step is halved where Newton fails or the solution jumps. Near a *change point* (the
constraint Jacobian ``G`` of all coordinates loses rank: two branches cross) the
transmission functions are not determined by the position, so the walk predicts along
the tangent it arrived with and accepts a step only if Newton moves the prediction by a
small fraction of the step: the other branch leaves the crossing with another slope, and
is never taken. Rank loss is measured by
:func:`~mechdyn.compile.loop_numeric.rank_margin`.

>>> import numpy as np, mechdyn as md
>>> phi, th, psi = md.coordinates("phi theta psi")
>>> par = md.Mechanism("parallelogram", [phi, th, psi])
>>> for name, angle in (("crank", phi), ("coupler", th), ("rocker", psi)):
...     _ = par.link(name, J=1, angle=angle)
>>> _ = par.loop("ABCD", (1, phi), (3, th), (-1, psi), (-3, 0))
>>> linkage = md.Linkage(par, guess={th: 0, psi: 0.5}, guess_at=0.5)
>>> [round(float(v), 12) + 0.0 for v in linkage.position(4.0)]   # through phi = pi
[4.0, 0.0, 4.0]
"""
from __future__ import annotations

import numpy as np

from mechdyn.analyse.linkage_types import LinkageError
from mechdyn.compile.loop_numeric import rank_margin

__all__ = ["margin", "derivatives", "NEAR_CHANGE", "CHANGE_POINT"]

_NEWTON_STEPS = 30
_TOLERANCE = 1e-14          # |g| relative to the loop size
_JUMP = 0.2                 # largest Newton correction of a continuation step (rad, m)
_BRANCH = 0.05              # ... near a change point: this fraction of the step
_MAX_STEP = 0.25            # largest continuation step of the independent coordinate
_MIN_STEP = 1e-13           # smallest step (relative): the loops close no further
NEAR_CHANGE = 1e-2          # rank margin of G below this: near a change point
CHANGE_POINT = 1e-5         # ... below this: at one (positions there are accurate
                            # only to about the root of Newton's tolerance)
_MEMORY = 16                # tangents remembered at positions walked to


def margin(self, q, columns=None):
    """:func:`rank_margin` of the loops at the positions ``q`` (all coordinates, or the
    ``columns`` given: the dependent ones lose rank at a toggle as well)."""
    return rank_margin(self.closure(q)[1], columns)


def derivatives(self, q):
    """``(dq/dphi, d2q/dphi2)`` at the closed positions ``q`` of a one-DOF linkage: by
    implicit differentiation, or at a change point (where the loops do not determine
    them) as the limits along this branch: the values at ``phi +- h`` and ``+- 2h``
    (h = 1e-3, positions walked from ``q``) averaged and extrapolated to h = 0
    (Richardson: error of order h^4), those positions closed to rounding first. Near
    a change point the error of implicit differentiation grows like the rounding of
    the positions over the square of the rank margin (1e-6 at 1e-5 rad from one)."""
    closeness = self.margin(q)
    if closeness >= CHANGE_POINT:
        q = _polish(self, q) if closeness < NEAR_CHANGE else q
        ratio = self.velocity_matrix(q)[:, 0]
        return ratio, self._second(q, ratio)
    at, h = float(q[self.independent[0]]), 1e-3
    means = []
    for offset in (h, 2 * h):
        pairs = []
        for value in (at - offset, at + offset):
            near, _ = self._walk(q, np.array([value]))
            if near is None:
                _undetermined(self, q)
            near = _polish(self, near)
            ratio = self.velocity_matrix(near)[:, 0]
            pairs.append((ratio, self._second(near, ratio)))
        means.append([(a + b) / 2 for a, b in zip(*pairs)])
    return tuple((4 * fine - coarse) / 3 for fine, coarse in zip(*means))


def _polish(self, q, steps=3):
    """Newton steps past the tolerance while the residual falls: near a change point a
    position's error is the residual over the rank margin."""
    g, grads = self.closure(q)
    for _ in range(steps):
        trial = q.copy()
        trial[self.dependent] -= np.linalg.solve(grads[:, self.dependent], g)
        g_trial, grads_trial = self.closure(trial)
        if not np.max(np.abs(g_trial)) < np.max(np.abs(g)):
            break
        q, g, grads = trial, g_trial, grads_trial
    return q


def _newton(self, q, damped=False):
    """Close the loops from ``q`` moving the dependent coordinates; None if it fails.
    Near a solution (continuation) a step must halve the residual, else the toggle
    is near; ``damped`` (from a user's guess) halves steps until the residual falls."""
    q = np.array(q, dtype=float)
    g, grads = self.closure(q)
    tolerance = _TOLERANCE * max(float(np.abs(grads).max()), 1e-300) * \
        (1 + float(np.abs(q).max()))
    residual = float(np.abs(g).max())
    for _ in range(4 * _NEWTON_STEPS if damped else _NEWTON_STEPS):
        if residual <= tolerance:
            return q
        try:
            step = np.linalg.lstsq(grads[:, self.dependent], g, rcond=None)[0] if damped \
                else np.linalg.solve(grads[:, self.dependent], g)
        except np.linalg.LinAlgError:
            return None
        previous = residual
        for _ in range(30 if damped else 1):
            trial = q.copy()
            trial[self.dependent] -= step
            g, grads = self.closure(trial)
            residual = float(np.abs(g).max())
            if residual < previous or not damped:
                break
            step = step / 2
        q = trial
        if not np.isfinite(residual) or (not damped and not residual < 0.5 * previous
                                           and residual > 1e3 * tolerance):
            return None          # not converging quadratically: near a toggle
    return q if residual <= 1e3 * tolerance else None


def _walk(self, q, target):
    """Continue from ``q`` to the independent values ``target``. Returns the
    positions there (or None) and the last independent values reached. Raises
    :class:`~mechdyn.analyse.linkage.LinkageError` starting at a change point with no
    direction known (the branch to follow is not determined)."""
    start = self._newton(q, damped=True)
    if start is None:
        return None, q[self.independent]
    q = start
    single = len(self.independent) == 1
    tangent = _tangent(self, q) if single else None
    step = np.full(len(self.independent), _MAX_STEP)
    while np.max(np.abs(target - q[self.independent])) > 0:
        step = np.sign(target - q[self.independent]) * np.minimum(
            np.abs(step), np.abs(target - q[self.independent]))
        near = single and self.margin(q) < NEAR_CHANGE
        if near and tangent is None:
            _undetermined(self, q)
        predicted = q + tangent * step[0] if near else self._predict(q, step)
        solved = self._newton(predicted) if predicted is not None else None
        if solved is not None and _accepted(self, solved, predicted, step, near):
            if single:
                tangent = (solved - q) / step[0] if self.margin(solved) < NEAR_CHANGE \
                    else None
            q = solved
            step = np.minimum(2 * np.abs(step), _MAX_STEP)
            continue
        step = step / 2
        if np.max(np.abs(step)) < _MIN_STEP * (1 + np.max(np.abs(target))):
            return None, q[self.independent]
    if single:
        _remember(self, q, tangent)
    return q, q[self.independent]


def _accepted(self, solved, predicted, step, near):
    """A step stays on its branch: a small Newton correction, near a change point a
    small fraction of the step."""
    correction = float(np.max(np.abs(solved - predicted)))
    if correction > _JUMP:
        return False
    if near or (len(self.independent) == 1 and self.margin(solved) < NEAR_CHANGE):
        return correction <= _BRANCH * float(np.max(np.abs(step)))
    return True


def _tangent(self, q):
    """``dq/dphi`` at ``q``: remembered where the walk arrived near a change point,
    else from the velocity matrix (None where it is not determined)."""
    remembered = getattr(self, "_tangents", {}).get(q.tobytes())
    if remembered is not None:
        return remembered
    if self.margin(q) < CHANGE_POINT:
        return None
    return self.velocity_matrix(q)[:, 0]


def _remember(self, q, tangent):
    memory = self.__dict__.setdefault("_tangents", {})
    if tangent is None:
        memory.pop(q.tobytes(), None)
        return
    memory[q.tobytes()] = tangent
    while len(memory) > _MEMORY:
        memory.pop(next(iter(memory)))


def _undetermined(self, q):
    at = float(q[self.independent[0]])
    raise LinkageError(
        f"{self.mechanism.name!r}: {self._independent_text(at)} is a change point of loop "
        f"{self.loop_of(_weakest_row(self, q))}: two assembly branches cross there and "
        "the one to continue on is not determined; assemble at a crank angle off it "
        "(guess_at=...) and walk through it", at=at)


def _weakest_row(self, q):
    """The constraint row most nearly dependent on the others at ``q`` (all
    coordinates, columns scaled to unit length)."""
    _, grads = self.closure(q)
    norms = np.linalg.norm(grads, axis=0)
    part = grads / np.maximum(norms, 1e-12 * max(float(norms.max()), 1e-300))
    _, _, rows = np.linalg.svd(part.T, full_matrices=False)
    return int(np.argmax(np.abs(rows[-1])))


def _predict(self, q, step):
    """Second-order predictor ``q + S step + q'' step^2 / 2`` (first order for
    several independent coordinates)."""
    try:
        matrix = self.velocity_matrix(q)
    except np.linalg.LinAlgError:
        return None
    first = matrix @ step
    predicted = q + first
    if len(self.independent) == 1:
        predicted = predicted + self._second(q, matrix[:, 0]) * step[0] ** 2 / 2
    predicted[self.independent] = q[self.independent] + step
    return predicted

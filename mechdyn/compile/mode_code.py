"""Source of a scene's *mode functions*: the right-hand side and events of segments with
stuck friction elements, stops in contact, open stop limits or closed loops, for the
compiled kernels.

A friction mode is data, not code: which groups of elements are stuck (their leaders'
gradients become rows of the constrained equations), which coordinates they hold, the
members of each group with their kinds and factors ``alpha`` (for the holding margin)
and the offsets of the open limits' gaps. :func:`mode_vector` writes it after the
scene's parameter vector; the generated ``mode_rhs`` and ``mode_events`` read it there,
so one compilation serves every mode of the scene:

- ``mode_rhs``: ``terms`` (mass matrix, forcing, gradients, biases) and the constrained
  equations ``[M -G'; G 0] [a; lambda] = [f; -bias]`` (rows: the closed loops', then one
  per stuck group), solved by LU with partial pivoting (:mod:`mechdyn.kernels.linalg`),
  as :func:`mechdyn.simulate.constrained.solve`; coordinates held by a stuck element
  keep exactly zero speed;
- ``mode_events``: the scene's ``events`` (gaps minus their offsets) followed by one
  holding margin per stuck group (:func:`mechdyn.simulate.constrained.group_check`:
  ``min(high - lambda, lambda - low)`` over the sum of the members' intervals).

Lossy gears (their loss line is chosen per step) have no mode functions.

>>> from mechdyn.simulate.friction import Mode
>>> mode_vector(Mode(signs=(0.0,), groups=(((0, 1.0),),)), kinds=["friction"],
...             frozen=[0], contacts=0)
[1.0, 0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 1.0]
"""
from __future__ import annotations

__all__ = ["mode_source", "mode_vector", "KIND_CODES"]

KIND_CODES = {"friction": 0.0, "one_way": 1.0, "contact": 2.0}

_TEMPLATE = '''
from mechdyn.kernels.linalg import lu_factor, lu_solve
import numpy as _np

_N, _K, _L, _NP, _E, _T = {n}, {k}, {loops}, {n_params}, {n_events}, {n_terms}
_MASS, _FORCE = {mass}, {forcing}
_FG, _FB, _FM, _FP, _FREL = {fg}, {fb}, {fm}, {fp}, {frel}
_CG, _CB = {cg}, {cb}
_LG, _LB = {lg}, {lb}
_GAPS = _np.array({gaps}, dtype=_np.int64)


@njit(inline="always")
def _row(buf, e, j):
    if e < _K:
        return buf[_FG + e * _N + j]
    return buf[_CG + (e - _K) * _N + j]


@njit(inline="always")
def _bias(buf, e):
    if e < _K:
        return buf[_FB + e]
    return buf[_CB + e - _K]


@njit(cache=True, error_model="numpy")
def _constrained(t, y, p, buf, x):
    """The accelerations and multipliers (loops', then the groups') into ``x``;
    False where the constrained equations are singular."""
    terms(t, y, p, buf)
    m = int(p[_NP])
    size = _N + _L + m
    a = _np.zeros((size, size))
    piv = _np.zeros(size, _np.int64)
    for i in range(_N):
        for j in range(i + 1):
            a[i, j] = buf[_MASS + i * (i + 1) // 2 + j]
            a[j, i] = a[i, j]
        x[i] = buf[_FORCE + i]
    for r in range(_L):
        for j in range(_N):
            a[_N + r, j] = buf[_LG + r * _N + j]
            a[j, _N + r] = -buf[_LG + r * _N + j]
        x[_N + r] = -buf[_LB + r]
    for g in range(m):
        e = int(p[_NP + 1 + g])
        for j in range(_N):
            a[_N + _L + g, j] = _row(buf, e, j)
            a[j, _N + _L + g] = -_row(buf, e, j)
        x[_N + _L + g] = -_bias(buf, e)
    if not lu_factor(a, piv):
        return False
    lu_solve(a, piv, x)
    return True


@njit(_RHS, cache=True, error_model="numpy")
def mode_rhs(t, y, p, out):
{plain_call}    buf = _np.empty(_T)
    x = _np.empty(_N + _L + int(p[_NP]))
    ok = _constrained(t, y, p, buf, x)
    for i in range(_N):
        out[i] = y[_N + i]
        out[_N + i] = x[i] if ok else _np.nan
    m = int(p[_NP])
    frozen = _NP + 1 + m
    for f in range(int(p[frozen])):
        i = int(p[frozen + 1 + f])
        out[i] = 0.0
        out[_N + i] = 0.0


@njit(_RHS, cache=True, error_model="numpy")
def mode_events(t, y, p, out):
    plain = _np.empty(max(_E, 1))
    events(t, y, p, plain)
    for i in range(_E):
        out[i] = plain[i]
    m = int(p[_NP])
    at = _NP + 2 + m + int(p[_NP + 1 + m])          # the groups' members
    if m > 0:
        buf = _np.empty(_T)
        x = _np.empty(_N + _L + m)
        ok = _constrained(t, y, p, buf, x)
        for g in range(m):
            count = int(p[at])
            at += 1
            low = 0.0
            high = 0.0
            for _ in range(count):
                e, kind, alpha = int(p[at]), p[at + 1], p[at + 2]
                at += 3
                lo, hi = 0.0, _np.inf
                if kind != 2.0:
                    capacity = buf[_FP + e] * max(buf[_FM + e], 0.0)
                    lo, hi = -capacity, capacity
                    if kind == 1.0:
                        lo, hi = -max(capacity, buf[_FREL + e]), _np.inf
                ends0, ends1 = alpha * lo, alpha * hi
                low += min(ends0, ends1)
                high += max(ends0, ends1)
            force = x[_N + _L + g]
            margin = min(high - force, force - low)
            out[_E + g] = margin if ok else _np.nan
    for j in range(_GAPS.shape[0]):
        out[_GAPS[j]] -= p[at + j]
{loop_events}'''

_PLAIN_CALL = """    if p[_NP] == 0.0:
        rhs(t, y, p, out)
        return
"""
_LOOP_EVENTS = """    at += _GAPS.shape[0]
    minors = _np.empty({minors})
    loop_minors(t, y, p, minors)
    out[_E + m] = minors[int(p[at])]
    drifts = _np.empty(2)
    drift(t, y, p, drifts)
    out[_E + m + 1] = p[at + 1] - drifts[0]
    out[_E + m + 2] = p[at + 2] - drifts[1]
"""


def mode_source(meta, n_params, plain=False, minors=0) -> str:
    """The module text (after the scene's ``terms`` and ``events``; with ``plain`` its
    ``rhs``, which ``mode_rhs`` calls when nothing is stuck; with closed loops its
    ``drift`` and ``loop_minors``, ``minors`` of them) of ``mode_rhs`` and
    ``mode_events`` for a scene with metadata ``meta`` and ``n_params`` entries of
    ``p`` (values, friction signs, branch flags). With closed loops ``mode_events``
    ends with the watched minor of the loops and the room left to the drifts of their
    positions and speeds (:class:`mechdyn.simulate.loop_watch.LoopWatch`)."""
    offsets = {name: offset for name, offset, _ in meta["terms"]}
    n_terms = sum(_size(shape) for _, _, shape in meta["terms"])
    gaps = [i for i, (kind, _) in enumerate(meta["events"]) if kind == "gap"]
    return _TEMPLATE.format(
        n=len(meta["coordinates"]), k=len(meta["frictions"]),
        loops=len(meta.get("constraints", [])), n_params=n_params,
        n_events=len(meta["events"]), n_terms=n_terms, mass=offsets["mass"],
        forcing=offsets["forcing"], fg=offsets["friction_gradient"],
        fb=offsets["friction_bias"], fm=offsets["friction_magnitude"],
        fp=offsets["friction_peak"], frel=offsets["friction_release"],
        cg=offsets["contact_gradient"], cb=offsets["contact_bias"],
        lg=offsets["constraint_gradient"], lb=offsets["constraint_bias"],
        gaps=gaps or "[0][:0]", plain_call=_PLAIN_CALL if plain else "",
        loop_events=_LOOP_EVENTS.format(minors=minors) if meta.get("constraints") else "")


def mode_vector(mode, kinds, frozen, contacts, gap_offsets=None, loops=()) -> list:
    """The numbers of ``mode`` that ``mode_rhs`` and ``mode_events`` read after the
    parameter vector: the number of stuck groups and their leaders, the held
    coordinates, each group's members ``(element, kind code, alpha)``, the offset of
    every stop limit's gap (``gap_offsets``: by limit, 0 where not given), and with
    closed loops ``loops``: the watched minor and the drifts allowed to the loops'
    positions and speeds. ``kinds``: the kind of every element (frictions, then the
    stops' limits); ``frozen``: the coordinate each element holds (-1: none)."""
    held = [frozen[k] for k in mode.stuck if frozen[k] >= 0]
    out = [float(len(mode.groups))] + [float(g[0][0]) for g in mode.groups]
    out += [float(len(held))] + [float(i) for i in held]
    for group in mode.groups:
        out.append(float(len(group)))
        for element, alpha in group:
            out += [float(element), KIND_CODES[kinds[element]], float(alpha)]
    offsets = gap_offsets or {}
    out += [float(offsets.get(j, 0.0)) for j in range(contacts)]
    return out + [float(v) for v in loops]


def _size(shape) -> int:
    out = 1
    for extent in shape:
        out *= extent
    return out

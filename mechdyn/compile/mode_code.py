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
  equations of the mode (closed loops, stuck groups, sliding lossy gears:
  :func:`mechdyn.compile.mode_numerics.constrained`, as
  :func:`mechdyn.simulate.constrained.solve`); coordinates held by a stuck element
  keep exactly zero speed;
- ``mode_events``: the scene's ``events`` (gaps minus their offsets) followed by one
  holding margin per stuck group (:func:`mechdyn.compile.mode_numerics.group_margins`, as
  :func:`mechdyn.simulate.constrained.group_check` for groups without a lossy gear
  among other members).

>>> from mechdyn.simulate.friction import Mode
>>> mode_vector(Mode(signs=(0.0,), groups=(((0, 1.0),),)), kinds=["friction"],
...             frozen=[0], contacts=0)
[1.0, 0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 1.0]
"""
from __future__ import annotations

__all__ = ["mode_source", "mode_vector", "KIND_CODES"]

KIND_CODES = {"friction": 0.0, "one_way": 1.0, "contact": 2.0, "gear": 3.0}

_TEMPLATE = '''
from mechdyn.compile.mode_entry import (constrained, frozen_speeds, group_margins,
                                        least_change_into, rank_margin, require)
import numpy as _np

require("constrained", "frozen_speeds", "group_margins"{loop_entries})

_LAY = _np.array({layout}, dtype=_np.int64)
_N, _NP, _E, _T, _SIZE = {n}, {n_params}, {n_events}, {n_terms}, {size}


@njit(_RHS, cache=True, error_model="numpy")
def mode_rhs(t, y, p, out):
{plain_call}    buf = _np.zeros(_T)        # terms writes its non-zero entries only
    x = _np.empty(_SIZE + int(p[_NP]))
    terms(t, y, p, buf)
    ok = constrained(buf, _LAY, p, x)
    for i in range(_N):
        out[i] = y[_N + i]
        out[_N + i] = x[i] if ok else _np.nan
    frozen_speeds(_LAY, p, out)


@njit(_RHS, cache=True, error_model="numpy")
def mode_events(t, y, p, out):
    plain = _np.empty(max(_E, 1))
    events(t, y, p, plain)
    for i in range(_E):
        out[i] = plain[i]
    m = int(p[_NP])
    buf = _np.zeros(_T)
    x = _np.zeros(_SIZE + m)
    ok = True
    if m > 0:
        terms(t, y, p, buf)
        ok = constrained(buf, _LAY, p, x)
    at = group_margins(buf, _LAY, p, x, ok, out)
{loop_events}'''

_LOOP_PROJECT = '''

@njit(_RHS, cache=True, error_model="numpy")
def loop_project(t, y, p, out):
    parts = _np.empty({m} * ({n} + 3))
    for i in range({n2}):
        out[i] = y[i]
    step = _np.empty({n})
    for _ in range(3):
        closure(t, out, p, parts)
        least_change_into(parts[{m}:{mn}].copy(), parts[:{m}].copy(), step)
        for i in range({n}):
            out[i] -= step[i]
    closure(t, out, p, parts)
    grads = parts[{m}:{mn}].copy()
    rate = grads.reshape(({m}, {n})) @ out[{n}:].copy() + parts[{mn}:{mn} + {m}]
    least_change_into(grads, rate, step)
    for i in range({n}):
        out[{n} + i] -= step[i]
'''

_PLAIN_CALL = """    if p[_NP] == 0.0:
        rhs(t, y, p, out)
        return
"""
_LOOP_EVENTS = """    minors = _np.empty({minors})
    loop_minors(t, y, p, minors)
    out[_E + m] = minors[int(p[at])]
    drifts = _np.empty(2)
    drift(t, y, p, drifts)
    out[_E + m + 1] = p[at + 1] - drifts[0]
    out[_E + m + 2] = p[at + 2] - drifts[1]
    out[_E + m + 3] = 1.0                      # every minor large: far from rank loss
    if _np.abs(minors).max() <= p[at + 3]:
        if m == 0:
            terms(t, y, p, buf)
        out[_E + m + 3] = rank_margin(buf, _LAY) - p[at + 4]
"""


def mode_source(meta, n_params, plain=False, minors=0) -> str:
    """The module text (after the scene's ``terms`` and ``events``; with ``plain`` its
    ``rhs``, which ``mode_rhs`` calls when nothing is stuck and the scene has no lossy
    gear; with closed loops its ``drift`` and ``loop_minors``, ``minors`` of them) of
    ``mode_rhs`` and ``mode_events`` for a scene with metadata ``meta`` and
    ``n_params`` entries of ``p`` (values, friction signs, branch flags, a constant mass
    matrix's factor). With closed
    loops ``mode_events`` ends with the watched minor of the loops, the room left to
    the drifts of their positions and speeds and to the rank margin of their gradients
    (:class:`mechdyn.simulate.loop_watch.LoopWatch`), and the module has
    ``loop_project(t, y, p, out)``: the state put back onto the loops, as
    :func:`mechdyn.simulate.assembly.project` (with the scene's ``closure``)."""
    from mechdyn.compile.mode_numerics import LAYOUT_NAMES
    offsets = {name: offset for name, offset, _ in meta["terms"]}
    gaps = [i for i, (kind, _) in enumerate(meta["events"]) if kind == "gap"]
    gears = meta.get("gears", [])
    n, loops = len(meta["coordinates"]), len(meta.get("constraints", []))
    values = {"n": n, "frictions": len(meta["frictions"]), "loops": loops,
              "params": n_params, "events": len(meta["events"]),
              "terms": sum(_size(shape) for _, _, shape in meta["terms"]),
              "first_sign": len(meta["param_names"]),
              "gaps": len(gaps), "gears": len(gears)}
    layout = [values[name] if name in values else offsets[name] for name in LAYOUT_NAMES]
    layout += gaps + [index for _, k, c in gears for index in (k, c)]
    return _TEMPLATE.format(
        layout=layout, n=n, n_params=n_params, n_events=values["events"],
        n_terms=values["terms"], size=n + loops + len(gears),
        plain_call=_PLAIN_CALL if plain and not gears else "",
        loop_entries=', "rank_margin", "least_change"' if loops else "",
        loop_events=_LOOP_EVENTS.format(minors=minors) if loops else "") + (
        _LOOP_PROJECT.format(m=loops, n=n, n2=2 * n, mn=loops + loops * n) if loops else "")


def mode_vector(mode, kinds, frozen, contacts, gap_offsets=None, loops=()) -> list:
    """The numbers of ``mode`` that ``mode_rhs`` and ``mode_events`` read after the
    parameter vector: the number of stuck groups and their leaders, the held
    coordinates, each group's members ``(element, kind code, alpha)``, the offset of
    every stop limit's gap (``gap_offsets``: by limit, 0 where not given), and with
    closed loops ``loops``: the watched minor, the drifts allowed to the loops'
    positions and speeds, the size of the largest minor under which the rank margin is
    computed, and the margin's floor. ``kinds``: the kind of every element (frictions, then the
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

"""Building a segment's integration: which events it watches, and the runner that steps
it on scipy (:class:`~mechdyn.simulate.stepping.ScipySegment`) or on the compiled kernels
(:class:`~mechdyn.simulate.compiled_stepping.CompiledSegment`).

The watched events are described once, for both backends, as :class:`Watched` entries:
stop conditions and switching functions, the friction elements' sliding speeds (a
sliding element sticks where its speed crosses zero) and magnitudes (a free element
engages) and the gaps of open stop limits (a limit reached is an impact,
:mod:`mechdyn.simulate.contacts`), all entries of the scene's generated ``events`` function; the
release margin
of a stuck group (it needs the constrained equations, so segments with stuck elements
run on scipy); the largest minor of closed loops' constraints. Each entry carries the
side its function counts as being on while exactly zero (:mod:`mechdyn.simulate.events`).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mechdyn.simulate.events import EventWatch
from mechdyn.simulate.stepping import WITH_JACOBIAN, ScipySegment

__all__ = ["Watched", "watched_events", "scipy_runner", "compiled_runner", "fast_rhs",
           "tolerant"]


@dataclass(frozen=True)
class Watched:
    """One watched event: ``kind`` ("stop", "switch", "stick", "engage", "gap",
    "release", "minor", "domain", "mass"), ``index`` (the entry of the generated ``events``; the
    group for a release; the minor), ``element`` (the stop condition, friction element or
    stop limit, else -1), ``direction`` (+1, -1, 0), ``side`` (+1/-1: the side a zero
    counts as; 0: a zero takes the side the function moves to) and ``offset`` (the value
    that counts as zero: a gap negative by rounding at the segment's start); ``timed``: a
    function of t alone, whose crossings the driver knows in advance
    (:mod:`mechdyn.simulate.time_events`): not looked for on the steps."""
    kind: str
    index: int
    element: int
    direction: int
    side: int
    offset: float = 0.0
    timed: bool = False

    @property
    def compiled(self) -> bool:
        """Whether it is an entry of the generated ``events`` function."""
        return self.kind in ("stop", "switch", "stick", "engage", "gap", "domain", "mass")


def watched_events(modes, scene, mode, muted, t0, y0, minor=None) -> list:
    """The events of a segment with friction ``mode`` starting at ``(t0, y0)``: stop
    conditions, switching functions (muted ones, which chattered, are unlocked and not
    watched) from the side their flag locks, the friction and stop-limit events of
    ``modes`` (:class:`~mechdyn.simulate.friction.FrictionModes`), and the closed loops' ``minor``
    (``(index, direction)`` or None)."""
    compiled = modes.c
    index = _event_index(modes)
    timed = index["timed"]
    out = [Watched("stop", i, j, int(c.direction), 0, timed=i in timed)
           for j, (i, c) in enumerate(zip(index["stop"], scene.until))]
    for j, i in enumerate(index["switch"]):
        if i not in muted:
            out.append(Watched("switch", i, -1, 0, int(mode.flags[j]), timed=i in timed))
    rates = index["rate"]
    for k, sign in enumerate(mode.signs):           # zero counts as the sliding side
        if sign != 0:
            out.append(Watched("stick", rates[k], k, int(-sign), int(sign)))
    out += [Watched("release", g, -1, -1, 1) for g in range(len(mode.groups))]
    out += [Watched("domain", i, j, -1, 1) for j, i in enumerate(index["domain"])]
    out += [Watched("mass", i, -1, -1, 1) for i in index["mass"]]
    out += [Watched("engage", index["magnitude"][k], k, 1, -1) for k in sorted(mode.free)]
    if index["gap"]:
        gaps = index["gap"]
        out += [Watched("gap", gaps[j], j, -1, 1, offset)
                for kind, j, _, offset in modes.watched(mode, t0, y0) if kind == "gap"]
    if minor is not None:
        out.append(Watched("minor", minor[0], -1, int(minor[1]), 0))
    return out


def _event_index(modes) -> dict:
    """The entries of the scene's ``events`` by kind, and the timed ones (a set),
    found once per run (kept on ``modes``)."""
    index = getattr(modes, "event_index", None)
    if index is None:
        index = {kind: [] for kind in ("stop", "switch", "rate", "magnitude", "domain",
                                       "gap", "mass")}
        for i, (kind, _) in enumerate(modes.c.event_kinds):
            index.setdefault(kind, []).append(i)
        index["timed"] = set(modes.c.meta.get("timed", ()))
        modes.event_index = index
    return index


def scipy_runner(context, mode, method, t0, y0, t_end, h, watched, rtol, atol, monitor,
                 segment, min_step, drift):
    """A :class:`ScipySegment` for ``mode``: the generated ``rhs`` (or the constrained
    one of stuck elements and lossy gears), the analytic Jacobian for implicit methods, the watched
    events evaluated in Python."""
    c, modes = context.c, context.modes
    p = modes.p(mode)
    size = 2 * c.dof
    constrained = modes.rhs(mode)             # stuck elements or a lossy gear
    fun = tolerant(constrained or fast_rhs(c.raw["rhs"], p, size), (size,))
    jac = None
    if method in WITH_JACOBIAN and constrained is None:
        sparse = "jac_sparsity" in c.meta and method in ("Radau", "BDF")   # a sparse LU
        jac = tolerant(lambda t, y: (c.sparse_jac if sparse else c.jac)(t, y, p), (size, size))
    watch = _event_watch(c, modes, mode, p, watched)
    max_step = context.max_step if mode.groups else context.period_step
    return ScipySegment(method, fun, jac, t0, y0, t_end, rtol, atol, segment, watch,
                        monitor, first_step=h, max_step=max_step, min_step=min_step,
                        drift=drift, revolving=c.meta.get("revolving", ()))


def compiled_runner(context, functions, mode, method, t0, y0, t_end, h, watched, rtol,
                    atol, segment, switch):
    """A :class:`CompiledSegment`. On the plain functions every watched event is an
    entry of ``events``; on the mode functions (:mod:`mechdyn.compile.mode_code`:
    stuck elements, stop limits, closed loops) the mode's numbers follow the parameters,
    the gaps are watched from their offsets, each stuck group's holding margin follows
    the entries of ``events``, then the loops' watched minor and the room left to their
    drifts and to the rank margin of their gradients (the last three watched entries:
    they end the segment with status "drift", for the rank check and a projection).
    As on scipy, a segment with loops and nothing stuck samples its events at the step
    ends only: the drift is the steps', not the interpolant's. Events of t alone are
    ignored: the driver ends the segment at them. A switching function is watched from
    the side its flag locks whatever its value at the start (a projection onto the
    loops may have nudged it back across zero), as on scipy."""
    from mechdyn.compile.mode_code import mode_vector
    from mechdyn.kernels.layout import IGNORED
    from mechdyn.simulate.compiled_stepping import CompiledSegment
    from mechdyn.simulate.methods import has_modes
    c, modes = context.c, context.modes
    p, size = modes.p(mode), len(c.event_kinds)
    max_step, extra, minor = context.period_step, [], None
    if has_modes(c):
        offsets = {w.element: w.offset for w in watched if w.kind == "gap"}
        loops = ()
        if c.constraints:                  # the watched minor, the drifts allowed
            minor = next(w.index for w in watched if w.kind == "minor")
            loops = (minor, *context.loops.limits(y0, p), *context.loops.margin_limits())
            extra = [(size + len(mode.groups) + 1 + k, -1, 1) for k in range(3)]
        p = p + mode_vector(mode, modes.kinds, modes.frozen, modes.contacts, offsets, loops)
        max_step = context.max_step if mode.groups else max_step
    groups = size + len(mode.groups)

    def entry(w):
        return size + w.index if w.kind == "release" else groups if w.kind == "minor" \
            else w.index
    spec = [(entry(w), IGNORED if w.timed else w.direction,
             2 * w.side if w.kind == "switch" else w.side) for w in watched]
    return CompiledSegment(method, functions, p, t0, y0, t_end, rtol, atol, segment,
                           spec + extra, groups + (4 if minor is not None else 0),
                           first_step=h, max_step=max_step, drift=len(extra),
                           midpoint=bool(mode.groups) or not c.constraints,
                           switch=switch and not mode.groups,
                           autonomous=c.meta.get("autonomous", False),
                           scratch=context.scratch)


def _event_watch(c, modes, mode, p, watched):
    """An :class:`EventWatch` over the watched events, numbered as ``watched``."""
    if not watched:
        return None
    size = len(c.event_kinds)
    releases = [("release", w.index, w.direction, 0.0) for w in watched
                if w.kind == "release"]
    raw_events = c.raw["events"]

    def values(t, y):
        out = [0.0] * size
        raw_events(t, _floats(y), p, out)
        margins = iter(modes.event_values(t, y, mode, releases))
        minors = c.loop_minors(t, y, p) if c.constraints else ()
        return np.array([out[w.index] - w.offset if w.compiled else
                         next(margins) if w.kind == "release" else minors[w.index]
                         for w in watched])
    watch = EventWatch(values, [w.direction for w in watched],
                       [w.side != 0 and w.kind != "switch" for w in watched],
                       interior=2 if mode.groups else 1)   # the middle: as the kernels
    watch.start_sides = {k: w.side for k, w in enumerate(watched) if w.kind == "switch"}
    watch.muted[[w.timed for w in watched]] = True     # the driver ends the segment there
    return watch


def _floats(y):
    return y.tolist() if type(y) is np.ndarray else y


def fast_rhs(raw, p, size):
    """solve_ivp's ``fun(t, y)`` over a generated ``rhs(t, y, p, out)``."""
    def fun(t, y):
        out = [0.0] * size
        raw(t, y.tolist(), p, out)
        return out
    return fun


def tolerant(function, shape):
    """``function`` as the solver should see it: NaN where the equations cannot be
    evaluated (an overflowing trial stage, a singular mass matrix there), so the step is
    rejected and shrunk as for any NaN. Real failures surface as a collapsing step."""
    from mechdyn.errors import SimulationError
    failed = np.full(shape, np.nan)
    errors = (ArithmeticError, ValueError, SimulationError, np.linalg.LinAlgError)

    def guarded(t, y):
        try:
            return function(t, y)
        except errors:
            return failed
    return guarded

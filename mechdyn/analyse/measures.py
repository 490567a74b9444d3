"""Named measures of an outcome: what a sweep, the command line and a design study ask
of a run or of a steady cycle.

A measure is written ``NAME`` or ``NAME:ARGUMENT`` (an output label, an element or a
state), read by splitting the text, never evaluated; or it is a user's function of an
outcome (:class:`Measure`). The outcome decides the span: a :class:`~mechdyn.Result`
(``simulate``) is measured over the run, a :class:`~mechdyn.SteadyRunning` (or a
``Flywheel``'s) over its cycle, a :class:`~mechdyn.PeriodicSolution` over its period.

=================  ====================================  ==============================
measure            of a run                              of a steady cycle (period)
=================  ====================================  ==============================
``mean_speed``     --                                    ``cycle / cycle_time`` (rad/s)
``fluctuation``    --                                    ``delta`` (1)
``cycle_time``     --                                    the cycle's time (s)
``peak:OUTPUT``    value of largest magnitude            over the cycle
``rms:OUTPUT``     ``sqrt(integral f^2 dt / duration)``  over the cycle
``energy:NAME``    work of element NAME (J)              per cycle
``t_end``          when it ended (s)                     --
``stop_angle``     coordinate travelled, to a stop       --
``final:KEY``      last value of a state or output       --
=================  ====================================  ==============================

``energy:NAME`` integrates the scene's output ``power:NAME`` (record it:
``outputs=[..., "power:motor"]``); integrals use 4-point Gauss-Legendre on the
integrator's dense output, on its steps cut into 1/512 of the span or less and
coordinate changes of 0.05 (rad or m) or less (a steady cycle's steps in the crank
angle, with ``dt = dphi / omega``).

>>> import sympy as sp, mechdyn as md
>>> phi = md.coordinate("phi")
>>> disc = md.Mechanism("driven disc", [phi])
>>> _ = disc.link("disc", J=2, angle=phi)
>>> _ = disc.load("drive", 3, along=phi)
>>> run = md.Scene("run", initial={phi: 0, md.speed(phi): 1}, t_end=2,
...                outputs=["drive", "power:drive"])
>>> res = disc.simulate(run, {})
>>> work = md.measure("energy:drive")
>>> work.name, work.unit, round(work(res), 9)      # M * angle = 3 * (2 + 0.75 * 4)
('energy:drive', 'J', 15.0)
>>> md.measure("fluctuaton")
Traceback (most recent call last):
...
mechdyn.analyse.measures.MeasureError: unknown measure 'fluctuaton' (did you mean fluctuation?); measures: mean_speed, fluctuation, cycle_time, peak:OUTPUT, rms:OUTPUT, energy:ELEMENT, t_end, stop_angle, final:STATE
"""
from __future__ import annotations

import hashlib
import marshal
import weakref
from functools import partial

import numpy as np

from mechdyn.errors import MechdynError, did_you_mean

__all__ = ["measure", "Measure", "MeasureError", "MEASURES", "STEADY_MEASURES"]


class MeasureError(MechdynError, ValueError):
    """A measure that is unknown, or cannot be taken of the outcome it is given.

    Examples
    --------
    >>> import mechdyn as md
    >>> try:
    ...     md.measure("fluctuaton")
    ... except md.MeasureError as error:
    ...     print(error)
    unknown measure 'fluctuaton' (did you mean fluctuation?); ...
    """


# name -> (argument: "none", "needed" or "optional", what it is of, fixed unit or None)
_KINDS = {
    "mean_speed": ("none", "steady", "rad/s"),
    "fluctuation": ("none", "steady", ""),
    "cycle_time": ("none", "steady", "s"),
    "peak": ("needed", "any", None),
    "rms": ("needed", "any", None),
    "energy": ("needed", "any", "J"),
    "t_end": ("none", "run", "s"),
    "stop_angle": ("optional", "run", None),
    "final": ("needed", "run", None),
}
_PIECES, _TRAVEL = 512, 0.05   # quadrature: pieces of a span, at least; coordinate change
_WHAT = {"peak": "OUTPUT", "rms": "OUTPUT", "energy": "ELEMENT", "final": "STATE"}
MEASURES = tuple(f"{k}:{_WHAT[k]}" if k in _WHAT else k for k in _KINDS)
STEADY_MEASURES = tuple(k for k, (_, of, _) in _KINDS.items() if of == "steady")


class Measure:
    """A named measure: ``Measure(outcome) -> float``.

    Parameters
    ----------
    function : callable
        Of one outcome (a ``Result``, or a ``SteadyRunning`` in a steady sweep),
        returning a number.
    name : str, optional
        The measure's name (a sweep's column); default the function's ``__name__``.
    unit : str
        The value's SI unit, or "".

    Attributes: ``name``, ``unit``, ``of`` ('run', 'steady' or 'any': the outcomes it
    can be taken of), ``kind`` and ``argument`` (of a named measure, else None).

    Examples
    --------
    >>> import mechdyn as md
    >>> def turns(result):
    ...     return result.final("phi") / (2 * 3.141592653589793)
    >>> md.Measure(turns, unit="1")
    <Measure turns [1]>
    """

    def __init__(self, function, name=None, unit="", *, of="any", kind=None, argument=None):
        if not callable(function):
            raise MeasureError(f"a measure must be callable (a function of a result), "
                               f"got {function!r}")
        name = name if name is not None else getattr(function, "__name__", "")
        if not isinstance(name, str) or not name.strip() or name == "<lambda>":
            raise MeasureError(f"give the measure {function!r} a name: "
                               "md.Measure(function, name='...')")
        self.function, self.name, self.unit = function, name.strip(), str(unit or "")
        self.of, self.kind, self.argument = of, kind, argument

    def __call__(self, outcome) -> float:
        value = self.function(outcome)
        try:
            return float(value)
        except (TypeError, ValueError):
            raise MeasureError(f"measure {self.name!r} gave {value!r}, not a number") from None

    @property
    def key(self) -> str:
        """What determines its values: the name of a named measure; a function's name,
        module, qualified name and a hash of its code (the values it reads from
        elsewhere are not covered)."""
        if self.kind is not None:
            return self.name
        code = getattr(self.function, "__code__", None)
        digest = hashlib.sha256(marshal.dumps(code)).hexdigest()[:16] if code else "?"
        where = f"{getattr(self.function, '__module__', '?')}." \
                f"{getattr(self.function, '__qualname__', type(self.function).__name__)}"
        return f"{self.name} = {where} (code {digest})"

    def __repr__(self):
        return f"<Measure {self.name}" + (f" [{self.unit}]>" if self.unit else ">")


def measure(spec, units=None) -> Measure:
    """The measure ``spec`` names.

    Parameters
    ----------
    spec : str, callable or Measure
        ``"fluctuation"``, ``"peak:motor"``, ... (see the module), a function of an
        outcome (named by its ``__name__``), or a :class:`Measure` (returned as it is).
    units : dict, optional
        SI unit by state or output name (``Result.units``), for ``Measure.unit`` of
        the measures of an output or state.

    Returns
    -------
    Measure

    Examples
    --------
    >>> import mechdyn as md
    >>> md.measure("peak:motor", units={"motor": "N*m"})
    <Measure peak:motor [N*m]>
    >>> md.measure("peak")
    Traceback (most recent call last):
    ...
    mechdyn.analyse.measures.MeasureError: measure 'peak' needs an argument: peak:OUTPUT
    """
    if isinstance(spec, Measure):
        return spec
    if callable(spec):
        return Measure(spec)
    if not isinstance(spec, str):
        raise MeasureError(f"a measure is a name such as 'fluctuation' or 'peak:OUTPUT', or "
                           f"a function of a result; got {spec!r}")
    kind, colon, argument = (part.strip() for part in spec.partition(":"))
    if kind not in _KINDS:
        raise MeasureError(f"unknown measure {spec!r}{did_you_mean(kind, _KINDS)}; "
                           f"measures: {', '.join(MEASURES)}")
    takes, of, unit = _KINDS[kind]
    if takes == "needed" and not argument:
        raise MeasureError(f"measure {spec!r} needs an argument: {kind}:{_WHAT[kind]}")
    if takes == "none" and colon:
        raise MeasureError(f"measure {kind} takes no argument (got {spec!r})")
    units = units or {}
    if unit is None:
        unit = units.get(argument, "") if kind != "stop_angle" else \
            units.get(argument, "rad") if argument else "rad"
    name = f"{kind}:{argument}" if argument else kind
    return Measure(partial(_MEASURED[kind], argument, name), name, unit, of=of, kind=kind,
                   argument=argument or None)


# ------------------------------------------------------------------ outcomes
def _outcome(outcome, name):
    """``("steady", SteadyRunning)``, ``("period", Result)`` or ``("run", Result)``."""
    from mechdyn.analyse.fluctuation import Flywheel, SteadyRunning
    from mechdyn.analyse.periodic import PeriodicSolution
    if isinstance(outcome, Flywheel):
        outcome = outcome.running
    if isinstance(outcome, SteadyRunning):
        if outcome.dense is None:
            raise MeasureError(f"measure {name}: this SteadyRunning holds no dense output "
                               "(make it with md.steady_running)")
        return "steady", outcome
    if isinstance(outcome, PeriodicSolution):
        return "period", outcome.result
    if all(hasattr(outcome, a) for a in ("t", "compiled", "outputs_at", "final")):
        return "run", outcome
    raise MeasureError(f"measure {name}: {type(outcome).__name__} is not an outcome to "
                       "measure (a Result, SteadyRunning, Flywheel or PeriodicSolution)")


def _steady_only(name, outcome):
    kind, running = _outcome(outcome, name)
    if kind != "steady":
        raise MeasureError(f"{name} is a measure of steady running (md.steady_running, or "
                           "md.sweep(..., steady=True)), not of a run or a period")
    return running


def _run_only(name, outcome):
    kind, result = _outcome(outcome, name)
    if kind != "run":
        raise MeasureError(f"{name} is a measure of a run (simulate); steady running "
                           "repeats without end")
    return result


def _mean_speed(_, name, outcome):
    return _steady_only(name, outcome).omega_mean


def _fluctuation(_, name, outcome):
    return _steady_only(name, outcome).delta


def _cycle_time(_, name, outcome):
    return _steady_only(name, outcome).cycle_time


def _t_end(_, name, outcome):
    return _run_only(name, outcome).t_end


def _final(key, name, outcome):
    result = _run_only(name, outcome)
    try:
        return result.final(key)
    except KeyError:
        known = list(result.state_names) + list(result.output_labels)
        raise MeasureError(f"{name}: no state or output {key!r}{did_you_mean(key, known)} "
                           f"(states and outputs: {', '.join(known)})") from None


def _stop_angle(coordinate, name, outcome):
    result = _run_only(name, outcome)
    coordinates = list(result.coordinates)
    if not coordinate:
        if len(coordinates) != 1:
            raise MeasureError(f"{name}: the run has {len(coordinates)} coordinates; name "
                               f"one: stop_angle:{coordinates[0]}")
        coordinate = coordinates[0]
    if coordinate not in coordinates:
        raise MeasureError(f"{name}: no coordinate {coordinate!r}"
                           f"{did_you_mean(coordinate, coordinates)} ({', '.join(coordinates)})")
    if result.reason.startswith(("t_end", "failed")):
        raise MeasureError(f"{name}: the run did not stop at a stop condition (it ended: "
                           f"{result.reason}); a stop angle needs until=")
    values = result[coordinate]
    return float(values[-1] - values[0])


def _peak(label, name, outcome):
    """The value of largest magnitude on the grid (a run: its steps and 1001 even times;
    a cycle: its 4001 angles), refined between the best point's neighbours."""
    kind, source = _outcome(outcome, name)
    label = _label(source.compiled, label, name)
    grid, every = _sampled(kind, source)
    if not len(grid):
        return float("nan")
    sampled = np.abs(every[label])
    best = int(np.argmax(np.where(np.isfinite(sampled), sampled, -1.0)))
    low, high = grid[max(best - 1, 0)], grid[min(best + 1, len(grid) - 1)]
    if not high > low:
        return float(every[label][best])
    from scipy.optimize import minimize_scalar
    found = minimize_scalar(lambda x: -abs(float(source.outputs_at(x)[label][0])),
                            bounds=(low, high), method="bounded",
                            options={"xatol": 1e-12 * max(1.0, abs(high))})
    if -found.fun > sampled[best]:
        return float(source.outputs_at(found.x)[label][0])
    return float(every[label][best])


_last = (None, None, None)      # (weak reference to an outcome, its grid, its outputs there)


def _sampled(kind, source) -> tuple:
    """The peak's grid of ``source`` and every output on it; kept for the last outcome
    (a sweep's peaks of one point share it)."""
    global _last
    ref, grid, every = _last
    if ref is not None and ref() is source:
        return grid, every
    if kind == "steady":
        grid = source.phi
    else:
        grid = source.t if len(source.t) < 2 else np.union1d(
            np.linspace(source.t[0], source.t[-1], 1001), source.t)
    every = source.outputs_at(grid)
    _last = (weakref.ref(source), grid, every)       # one assignment: thread-safe
    return grid, every


def _rms(label, name, outcome):
    integral, span = _integral(label, name, outcome, square=True)
    return float(np.sqrt(integral / span))


def _energy(element, name, outcome):
    return _integral(_power_label(outcome, element, name), name, outcome)[0]


_MEASURED = {"mean_speed": _mean_speed, "fluctuation": _fluctuation,
             "cycle_time": _cycle_time, "peak": _peak, "rms": _rms, "energy": _energy,
             "t_end": _t_end, "stop_angle": _stop_angle, "final": _final}


# ------------------------------------------------------------------ numerics
def _label(compiled, label, name) -> str:
    """``label`` if the outcome records that output, else a MeasureError naming them."""
    labels = list(compiled.output_labels)
    if label not in labels:
        raise MeasureError(f"{name}: the scene records no output {label!r}"
                           f"{did_you_mean(label, labels)} (outputs: "
                           f"{', '.join(labels) or 'none'}; add it to the scene's outputs=)")
    return label


def _power_label(outcome, element, name) -> str:
    """The label of the output ``power:ELEMENT`` in the outcome's scene."""
    kind, source = _outcome(outcome, name)
    compiled = source.compiled
    items = compiled.meta.get("output_items", compiled.output_labels)
    for label, item in zip(compiled.output_labels, items):
        if item == f"power:{element}":
            return label
    raise MeasureError(f"{name}: the scene records no power of {element!r}; add "
                       f"'power:{element}' to its outputs (outputs=[..., "
                       f"'power:{element}'])")


def _integral(label, name, outcome, square=False) -> tuple:
    """``(integral of the output over the span in time, the span's duration)``: 4-point
    Gauss-Legendre on every step of the dense output, cut into ``_PIECES`` of the span
    or less and coordinate changes of at most ``_TRAVEL`` (a steady cycle in the
    angle, ``dt = dphi / omega``)."""
    kind, source = _outcome(outcome, name)
    label = _label(source.compiled, label, name)
    if kind == "steady":
        steps, travel = source.steps, np.abs(np.diff(source.steps))
        span = source.cycle_time
    else:
        steps, span = source.t, float(source.t[-1] - source.t[0])
        n = source.compiled.dof
        travel = np.max(np.abs(np.diff(source.y[:n], axis=1)), axis=0, initial=0.0)
    if not span > 0:
        raise MeasureError(f"{name}: the outcome spans no time")
    h = np.diff(steps)
    pieces = np.maximum(np.ceil(np.maximum(np.abs(h) * _PIECES / abs(steps[-1] - steps[0]),
                                           travel / _TRAVEL)), 1).astype(int)
    starts = np.concatenate([a + (b - a) * np.arange(k) / k
                             for a, b, k in zip(steps[:-1], steps[1:], pieces)])
    widths = np.repeat(h / pieces, pieces)
    x, w = np.polynomial.legendre.leggauss(4)
    nodes = (starts[:, None] + (x[None, :] + 1) / 2 * widths[:, None]).ravel()
    values = source.outputs_at(nodes)[label] if len(nodes) else np.zeros(0)
    if square:
        values = values ** 2
    if kind == "steady":
        values = values / source.dense(nodes)[0]
    return float(np.sum(values.reshape(-1, 4) @ w * widths / 2)), span

"""Scenes: what to simulate — which effects, which springs rigid, the initial state,
when to stop, what to record, and how to integrate.

>>> import sympy as sp, mechdyn as md
>>> phi = md.coordinate("phi")
>>> braking = md.Scene("braking", effects=["shoe"], initial={phi: 0, md.speed(phi): 100},
...                    until=md.stopped(phi))
>>> braking.until
(stopped(phi),)
"""
from __future__ import annotations

import math
import numbers
import sys
from dataclasses import dataclass, field

import sympy as sp

from mechdyn.declare.elements import Link, as_expression, is_structural
from mechdyn.errors import MechdynError, SceneError
from mechdyn.symbols import is_coordinate, t, written

__all__ = ["Scene", "StopCondition", "stopped", "reaches", "selection", "DEFAULT_RTOL",
           "DEFAULT_ATOL", "MIN_RTOL"]

DEFAULT_RTOL, DEFAULT_ATOL = 1e-10, 1e-12
DEFAULT_MAX_STEPS = 1_000_000
MIN_RTOL = 100 * sys.float_info.epsilon      # scipy's solve_ivp floor (2.2e-14)


@dataclass(frozen=True)
class StopCondition:
    """Stop when ``expression`` reaches ``value`` (crossing in ``direction``: +1 rising,
    -1 falling, 0 either way). ``given``: the value as typed with a unit (``"20 mm"``;
    ``value`` holds it in SI), checked against the expression's unit when the mechanism
    is known (:mod:`mechdyn.declare.scene_units`)."""
    expression: sp.Expr
    value: sp.Expr = sp.S.Zero
    direction: int = 0
    label: str = ""
    given: str = ""

    def __repr__(self):
        return self.label


def stopped(q) -> StopCondition:
    """Stop when the coordinate ``q`` comes to rest (its speed reaches zero).

    Examples
    --------
    >>> import mechdyn as md
    >>> phi = md.coordinate("phi")
    >>> md.stopped(phi)
    stopped(phi)
    >>> scene = md.Scene("braking", initial={phi: 0, md.speed(phi): 100},
    ...                  until=md.stopped(phi))
    >>> scene.until
    (stopped(phi),)
    """
    if not is_coordinate(q):
        raise SceneError(f"stopped(): {q!r} is not a coordinate")
    return StopCondition(sp.Derivative(q, t), sp.S.Zero, 0, f"stopped({q.func.__name__})")


def reaches(expression, value, direction=0, label=None) -> StopCondition:
    """Stop when ``expression`` (of coordinates, speeds, t, parameters) reaches ``value``;
    ``label`` names the condition in results (default: the condition written out).

    ``value`` may be a text with a unit, ``"20 mm"``, ``"1425 rpm"``: it is converted
    to SI here and its dimension checked against the expression's when the scene runs.

    Examples
    --------
    >>> import mechdyn as md
    >>> h = md.coordinate("h")
    >>> condition = md.reaches(h, "20 mm")
    >>> float(condition.value), condition.label
    (0.02, 'reaches(h, 20 mm)')
    """
    expression = as_expression(expression, "reaches(): expression")
    given = ""
    if isinstance(value, str):
        given = " ".join(value.split())
        value = sp.Float(_si(value, f"reaches({written(expression)}, ...)", None))
    value = as_expression(value, "reaches(): value")
    return StopCondition(expression, value, int(direction),
                         label or f"reaches({written(expression)}, "
                         f"{given or written(value)})", given)


def _si(text, what, unit):
    """The SI value of ``text`` (a number with an optional unit), or a SceneError naming
    ``what``."""
    from mechdyn.units import to_si
    try:
        return to_si(text, unit)
    except MechdynError as error:
        message = str(error)
        if not message.startswith(repr(text)):
            message = f"{text!r}: {message}"
        raise SceneError(f"{what}: {message}") from None


@dataclass(frozen=True)
class Scene:
    """A simulation scenario on a mechanism.

    Parameters
    ----------
    name : str
    effects : list of str, optional
        Names or tags of the loads, springs, dampers, gravity and friction to include;
        ``None`` includes every element. Links are always included.
    initial : dict
        Initial values of coordinates and speeds (``md.speed(q)``); missing ones are an
        error, values may be numbers (SI), expressions of parameters, or texts with a
        unit (``"1500 rpm"``, ``"20 mm"``): converted to SI here, their dimension
        checked against the coordinate's unit (its speed's: unit/s) when the scene runs.
    until : StopCondition or list of them, optional
        Stop at the first one met (``md.stopped``, ``md.reaches``).
    t_end : float or str, optional
        End time; required without ``until`` (defaults to 1000 s with it). Times
        (``t_end``, ``t_start``, ``max_wall_time``) are seconds, or texts with a unit
        of time converted here (``"2 min"``).
    outputs : list or dict, optional
        Element names (their generalized force along their own coordinate, e.g. a
        spring's moment), ``"power:NAME"``, or expressions to record; a dict names
        them: ``{"rod force": expr, "shaft": "shaft"}`` (labels of results, CSV, plots).
    rigid : list or dict, optional
        Springs made rigid: ``stretch = 0`` eliminates a coordinate (a dict maps a
        spring name to the coordinate to eliminate).
    method : str
        ``"auto"``, a ``solve_ivp`` method name, or ``"Rodas5P"`` (compiled kernels).
    backend : str
        ``"auto"`` (the compiled kernels wherever numba is installed and the scene has
        a compiled form, else scipy), ``"scipy"`` or ``"compiled"`` (numba).
    rtol, atol : float
        Tolerances (``atol`` may be a dict per state, with an optional ``"default"``):
        finite, ``atol > 0``, ``MIN_RTOL <= rtol < 1`` (``MIN_RTOL = 100 eps``, about
        2.2e-14, scipy's own floor).
        The defaults, 1e-10 and 1e-12, cost DOP853 about 1.7x the steps of 1e-8 and
        gain four orders of accuracy (docs/hard-cases.md).
    t_start : float
        Start time. Times and tolerances must be finite numbers (a SceneError names
        the field otherwise).
    max_steps, max_wall_time : int, float or None
        The run's budget: accepted steps (default one million) and seconds of wall time
        (default none); a run that exceeds it stops with a SimulationError carrying
        the result so far.

    Raises
    ------
    SceneError
        A field that is not valid (a time or tolerance that is not a finite number, an
        unknown method); effects, initial values and outputs are checked against the
        mechanism when the scene runs.

    Examples
    --------
    >>> import mechdyn as md
    >>> phi = md.coordinate("phi")
    >>> startup = md.Scene("startup", initial={phi: 0, md.speed(phi): "150 rpm"},
    ...                    t_end="2 min", outputs={"motor moment": "motor"})
    >>> startup.t_end, round(startup.initial[md.speed(phi)], 6)
    (120.0, 15.707963)
    >>> try:
    ...     md.Scene("startup", initial={phi: 0, md.speed(phi): 0}, t_end=-1)
    ... except md.SceneError as error:
    ...     print(type(error).__name__)
    SceneError
    """
    name: str
    effects: tuple | None = None
    initial: dict = field(default_factory=dict)
    until: tuple = ()
    t_end: float | None = None
    outputs: tuple = ()
    rigid: tuple = ()
    method: str = "auto"
    rtol: float = DEFAULT_RTOL
    atol: float = DEFAULT_ATOL
    t_start: float = 0.0
    max_steps: int | None = DEFAULT_MAX_STEPS
    max_wall_time: float | None = None
    backend: str = "auto"
    given: dict = field(default_factory=dict, repr=False, compare=False)

    def __post_init__(self):
        self._convert_initial_texts()
        if self.effects is not None:
            effects = (self.effects,) if isinstance(self.effects, str) else tuple(self.effects)
            object.__setattr__(self, "effects", effects)
        until = self.until
        if isinstance(until, StopCondition):
            until = (until,)
        until = tuple(until or ())
        for condition in until:
            if not isinstance(condition, StopCondition):
                raise SceneError(f"scene {self.name!r}: until must hold md.stopped(...) or "
                                 f"md.reaches(...), got {condition!r}")
        object.__setattr__(self, "until", until)
        if isinstance(self.rigid, dict):
            rigid = tuple((str(k), _coordinate_name(v)) for k, v in self.rigid.items())
        else:
            rigid = tuple((r, None) if isinstance(r, str) else (r[0], _coordinate_name(r[1]))
                          for r in ((self.rigid,) if isinstance(self.rigid, str) else self.rigid))
        object.__setattr__(self, "rigid", rigid)
        if isinstance(self.outputs, dict):
            outputs = tuple((str(label), item) for label, item in self.outputs.items())
        else:
            outputs = (self.outputs,) if isinstance(self.outputs, str) else tuple(self.outputs)
        object.__setattr__(self, "outputs", outputs)
        labels = [label for label, _ in self.labelled_outputs()]
        for label in labels:
            if labels.count(label) > 1:
                raise SceneError(f"scene {self.name!r}: two outputs are labelled {label!r}")
        object.__setattr__(self, "t_start", self._time("t_start", self.t_start))
        if self.t_end is None and not until:
            raise SceneError(f"scene {self.name!r}: give t_end or a stop condition (until=)")
        if self.t_end is not None:
            object.__setattr__(self, "t_end", self._time("t_end", self.t_end))
            if not self.t_end > self.t_start:
                raise SceneError(f"scene {self.name!r}: t_end = {self.t_end} must be later "
                                 f"than the start {self.t_start}")
        rtol = self._number("rtol", self.rtol)
        if not MIN_RTOL <= rtol < 1:
            raise SceneError(f"scene {self.name!r}: rtol = {rtol!r} must lie in "
                             f"[{MIN_RTOL:.3g}, 1): a relative error of 1 or more checks "
                             "nothing, and scipy's solvers raise any rtol below 100 machine "
                             "epsilons to that floor")
        object.__setattr__(self, "rtol", rtol)
        if isinstance(self.atol, dict):
            atol = {key: self._number(f"atol[{key}]", value, positive=True)
                    for key, value in self.atol.items()}
        else:
            atol = self._number("atol", self.atol, positive=True)
        object.__setattr__(self, "atol", atol)
        if self.backend not in ("auto", "scipy", "compiled"):
            raise SceneError(f"scene {self.name!r}: backend {self.backend!r}: use 'auto', "
                             "'scipy' or 'compiled'")
        if self.max_steps is not None:
            object.__setattr__(self, "max_steps",
                               int(self._number("max_steps", self.max_steps, positive=True)))
        if self.max_wall_time is not None:
            object.__setattr__(self, "max_wall_time",
                               self._time("max_wall_time", self.max_wall_time, positive=True))

    def _convert_initial_texts(self):
        """Initial values typed with a unit become SI floats; the texts are kept in
        ``given`` (state -> text) for the dimension check against the mechanism."""
        if not isinstance(self.initial, dict):
            raise SceneError(f"scene {self.name!r}: initial must be a dict {{q: value, "
                             f"md.speed(q): value}}, got {type(self.initial).__name__}")
        initial = dict(self.initial)
        given = {key: text for key, text in self.given.items()    # kept through replace()
                 if isinstance(initial.get(key), float)}
        for key, value in self.initial.items():
            if isinstance(value, str):
                given[key] = " ".join(value.split())
                shown = written(key) if isinstance(key, sp.Basic) else repr(key)
                initial[key] = _si(value, f"scene {self.name!r}: initial value of {shown}",
                                   None)
        object.__setattr__(self, "initial", initial)
        object.__setattr__(self, "given", given)

    def _time(self, field_name, value, positive=False) -> float:
        """A time: a number of seconds or a text with a unit of time."""
        if isinstance(value, str):
            value = _si(value, f"scene {self.name!r}: {field_name}", "s")
        return self._number(field_name, value, positive)

    def labelled_outputs(self) -> list:
        """``(label, item)`` for each output: the dict's names, else the element name,
        ``"power:NAME"`` or the expression written in plain symbols."""
        pairs = []
        for output in self.outputs:
            if isinstance(output, tuple) and len(output) == 2 and isinstance(output[0], str):
                pairs.append(output)
            elif isinstance(output, sp.Basic):
                pairs.append((written(output), output))
            else:
                pairs.append((str(output), output))
        return pairs

    def _number(self, field_name, value, positive=False) -> float:
        """A finite real number (positive if asked), or a SceneError naming the field."""
        if isinstance(value, (bool, str)) or not isinstance(value, (numbers.Real, sp.Number)):
            raise SceneError(f"scene {self.name!r}: {field_name} must be a number, got "
                             f"{value!r}")
        number = float(value)
        if not math.isfinite(number):
            raise SceneError(f"scene {self.name!r}: {field_name} = {value!r} is not finite")
        if positive and not number > 0:
            raise SceneError(f"scene {self.name!r}: {field_name} must be a positive number, "
                             f"got {value!r}")
        return number

    @property
    def time_limit(self) -> float:
        return self.t_end if self.t_end is not None else self.t_start + 1000.0


def _coordinate_name(q):
    if q is None or isinstance(q, str):
        return q
    if is_coordinate(q):
        return q.func.__name__
    raise SceneError(f"rigid: {q!r} is not a coordinate")


def selection(mechanism, scene) -> tuple:
    """The element names a scene includes and its rigid springs, checked.

    Returns ``(names, rigid)``, the key under which equations are derived and cached.
    """
    from mechdyn.declare.elements import Spring
    loads = [n for n, e in mechanism.elements.items() if not is_structural(e)]
    if scene is None:
        return tuple(loads), ()
    if not isinstance(scene, Scene):
        raise SceneError(f"expected a md.Scene, got {scene!r}")
    if scene.effects is None:
        chosen = set(loads)
    else:
        chosen = set()
        for effect in scene.effects:
            hits = {n for n in loads
                    if n == effect or effect in mechanism.elements[n].tags}
            if not hits:
                links = [n for n, e in mechanism.elements.items() if isinstance(e, Link)]
                hint = (f" ({effect!r} is a link; links are always included)"
                        if effect in links else "")
                raise SceneError(
                    f"scene {scene.name!r}: unknown effect {effect!r}{hint}; the loads of "
                    f"{mechanism.name!r} are {sorted(loads)} with tags "
                    f"{sorted({tag for n in loads for tag in mechanism.elements[n].tags})}")
            chosen |= hits
    _check_coordinates(mechanism, scene)
    for name, _ in scene.rigid:
        element = mechanism.elements.get(name)
        if not isinstance(element, Spring):
            raise SceneError(f"scene {scene.name!r}: rigid {name!r} is not a spring of "
                             f"{mechanism.name!r}")
    names = tuple(n for n in loads if n in chosen)
    return names, tuple(scene.rigid)


def _check_coordinates(mechanism, scene):
    """Stop conditions and output expressions may use only the mechanism's coordinates."""
    from sympy.core.function import AppliedUndef
    uses = [(f"stop condition {c!r}", e) for c in scene.until for e in (c.expression, c.value)]
    uses += [(f"output {o}", o) for o in scene.outputs if isinstance(o, sp.Basic)]
    declared = set(mechanism.coordinates)
    for what, expr in uses:
        for f in expr.atoms(AppliedUndef):
            if f not in declared:
                names = ", ".join(q.func.__name__ for q in mechanism.coordinates)
                raise SceneError(f"scene {scene.name!r}: {what} uses {f.func.__name__}, which "
                                 f"is not a coordinate of {mechanism.name!r} (coordinates: "
                                 f"{names})")

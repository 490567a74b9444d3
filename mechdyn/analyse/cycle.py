"""Duty cycles: scenes run one after another, each phase starting where the one before
ended, with its own effects (start-up, steady running under load, braking).

Rules (:func:`duty_cycle`):

- **Time runs on.** Phase 1 starts at its scene's ``t_start``; every later phase at the
  time the one before ended. A phase's scene keeps its own clock: its
  ``t_end - t_start`` is the phase's longest duration (its stop conditions may end it
  sooner), and loads that depend on ``md.t`` see the time since the phase began plus
  the scene's ``t_start``, as when the scene runs alone. Results show cycle time.
- **The state runs on.** A later phase starts from the previous end state: positions
  and speeds are continuous. Its scene's initial values may restate the end state (to
  1e-6 relative, 1e-9 absolute) or reset the position of a coordinate its equations do not contain (a free
  shaft's angle: resetting it changes nothing in the motion); anything else, a
  different speed for instance, is a :class:`DutyCycleError`. A first phase needs its
  initial values as any scene does; a phase scene written for a cycle gives none.
- **The coordinates stay.** Every phase must have the same coordinates: phases with
  different rigid springs (different coordinates) are refused.
- Friction modes are decided afresh at each phase start (a brake that ends a phase at
  rest holds in the next if it can), and the method is chosen per phase.

Each phase also records the power of every load, friction and damper, so the result
gives the energy per phase: kinetic and potential energy at its start and end and the
work of each element (:class:`~mechdyn.analyse.cycle_result.PhaseEnergy`).

>>> import mechdyn as md
>>> model = md.load_model("models/motor_startup.py")
>>> phi = model.mechanism.coordinates[0]
>>> coast = md.Scene("coast", effects=["load"], t_end=2)      # no initial values
>>> cycle = md.duty_cycle(model, ["startup", coast])
>>> [(p.name, round(p.start, 3), round(p.end, 3)) for p in cycle.phases]
[('startup', 0.0, 14.178), ('coast', 14.178, 16.178)]
>>> coasting = cycle.phase("coast").result             # on the scene's own clock
>>> round(coasting.final(md.speed(phi)) - float(coasting.y[1][0]), 9)  # -M_L t / J
-24.0
"""
from __future__ import annotations

import numpy as np

from mechdyn.errors import ParameterError, SceneError, SimulationError
from mechdyn.declare.scene import Scene

__all__ = ["duty_cycle", "DutyCycleError", "phase_scenes"]

_SAME, _SAME_ABSOLUTE = 1e-6, 1e-9   # agreement of a restated initial value (SI)


class DutyCycleError(SceneError):
    """A duty cycle that cannot run: no phases, an unknown scene, phases with different
    coordinates, or a later phase whose initial values break the state's continuity.

    Examples
    --------
    A second braking phase would start at 100 rad/s where the first ended at rest:

    >>> import mechdyn as md
    >>> model = md.load_model("shoe_brake")
    >>> try:
    ...     md.duty_cycle(model, "braking+braking")
    ... except md.DutyCycleError as error:
    ...     print(type(error).__name__)
    DutyCycleError
    """


def phase_scenes(phases, scenes=None) -> list:
    """The scenes of ``phases``: a text ``"startup+steady+braking"`` or a list of scene
    names and :class:`~mechdyn.declare.scene.Scene` objects (names looked up in ``scenes``)."""
    if isinstance(phases, (str, Scene)):
        phases = phases.split("+") if isinstance(phases, str) else [phases]
    chosen = []
    for item in phases:
        if isinstance(item, Scene):
            chosen.append(item)
            continue
        name = item.strip() if isinstance(item, str) else item
        if not isinstance(name, str) or not name:
            raise DutyCycleError(f"duty cycle: a phase must be a md.Scene or a scene's "
                                 f"name, got {item!r}")
        if not scenes or name not in scenes:
            where = (f"scenes: {', '.join(scenes)}" if scenes else "give Scene objects, "
                     "or a model (md.load_model) whose scenes the names pick")
            raise DutyCycleError(f"duty cycle: no scene {name!r} ({where})")
        chosen.append(scenes[name])
    if not chosen:
        raise DutyCycleError("duty cycle: no phases given")
    return chosen


def duty_cycle(model, phases, params=None, *, progress=None, max_wall_time=None):
    """Run ``phases`` one after another (see the module for the rules).

    Parameters
    ----------
    model : Model or Mechanism
        A model file's :class:`~mechdyn.declare.model_file.Model` (its scenes can be named and
        its ``params`` are the defaults) or a :class:`~mechdyn.declare.mechanism.Mechanism`.
    phases : str or list
        ``"startup+steady+braking"``, or scene names and ``md.Scene`` objects.
    params : dict, optional
        Parameter values for every phase (over the model's defaults).
    progress : callable, optional
        ``progress(t, t_end)`` in cycle time, ``t_end`` the current phase's bound,
        about every quarter second; an object with a ``phase(name, number, count,
        t_start)`` method also hears of each phase start
        (:class:`mechdyn.progress.ProgressLine`).
    max_wall_time : float, optional
        Seconds of wall time each phase may take (else the scene's budget).

    Returns a :class:`~mechdyn.analyse.cycle_result.CycleResult`. A phase that fails raises
    :class:`SimulationError` naming the phase, with ``error.partial`` the cycle so far.

    Examples
    --------
    The disc of the shoe brake coasts for a second, then brakes (the angle is free, so
    the braking scene's ``phi = 0`` may restart it; its speed must and does match):

    >>> import mechdyn as md
    >>> model = md.load_model("shoe_brake")
    >>> phi = model.mechanism.coordinates[0]
    >>> coast = md.Scene("coast", effects=[], initial={phi: 0, md.speed(phi): 100}, t_end=1)
    >>> cycle = md.duty_cycle(model, [coast, "braking"])
    >>> [(p.name, round(p.start, 9), round(p.end, 9)) for p in cycle.phases]
    [('coast', 0.0, 1.0), ('braking', 1.0, 51.0)]
    """
    from mechdyn.compile.compiler import compile_scene
    from mechdyn.analyse.cycle_result import CycleResult, Phase
    mechanism, scenes, defaults = _source(model)
    chosen = phase_scenes(phases, scenes)
    values = _parameter_sets(mechanism, chosen, defaults, params)
    runs = [_with_powers(mechanism, scene) for scene in chosen]
    compiled = [compile_scene(mechanism, run) for run, _ in runs]
    _check_coordinates(chosen, compiled)
    names = _labels(chosen)
    done, end_state, clock = [], None, None
    for k, (scene, (run, powers)) in enumerate(zip(chosen, runs)):
        start = None if k == 0 else _start(mechanism, scene, compiled[k], values[k],
                                           end_state, done[-1])
        offset = 0.0 if k == 0 else clock - scene.t_start
        if hasattr(progress, "phase"):
            progress.phase(names[k], k + 1, len(chosen), offset + scene.t_start,
                           " or ".join(map(repr, scene.until)))
        shifted = None if progress is None else \
            (lambda t, t_end, offset=offset: progress(t + offset, t_end + offset))
        try:
            result = mechanism.simulate(run, values[k], progress=shifted, start=start,
                                        max_wall_time=max_wall_time)
        except SimulationError as error:
            if error.partial is not None:
                done.append(Phase(k + 1, names[k], scene, error.partial, offset, powers))
            error.partial = CycleResult(mechanism.name, done) if done else None
            error.args = (f"duty cycle phase {k + 1} {names[k]!r} (from t = "
                          f"{offset + scene.t_start:.6g} s): {error}",)
            raise
        done.append(Phase(k + 1, names[k], scene, result, offset, powers))
        end_state = result.y[:, -1].copy()
        clock = offset + result.t_end
    return CycleResult(mechanism.name, done)


# ---------------------------------------------------------------------- inputs
def _source(model):
    from mechdyn.declare.mechanism import Mechanism
    from mechdyn.declare.model_file import Model
    if isinstance(model, Model):
        return model.mechanism, model.scenes, model.params
    if isinstance(model, Mechanism):
        return model, {}, {}
    raise DutyCycleError(f"duty_cycle() needs a model (md.load_model) or a md.Mechanism, "
                         f"got {type(model).__name__}")


def _parameter_sets(mechanism, scenes, defaults, params) -> list:
    """A :class:`ParameterSet` per phase; a given name no phase knows is refused."""
    from mechdyn.declare.parameter_rules import facts_of, scene_symbols
    from mechdyn.declare.parameters import ParameterSet, _key_name
    if isinstance(params, ParameterSet):
        return [ParameterSet(None, defaults=params, mechanism=mechanism, scene=scene)
                for scene in scenes]
    if params is not None and not isinstance(params, dict):
        raise ParameterError(f"parameter values must be a dict {{symbol or name: value}}, "
                             f"got {type(params).__name__}")
    given = dict(params or {})
    known = set(facts_of(mechanism).symbols)
    per_scene = [known | {s.name for s in scene_symbols(scene)} for scene in scenes]
    unknown = {k: v for k, v in given.items()
               if not any(_key_name(k) in names for names in per_scene)}
    if unknown:
        ParameterSet(unknown, mechanism=mechanism, scene=scenes[0])   # names them
    return [ParameterSet({k: v for k, v in given.items() if _key_name(k) in names},
                         defaults=defaults, mechanism=mechanism, scene=scene)
            for scene, names in zip(scenes, per_scene)]


def _with_powers(mechanism, scene):
    """The scene run for a phase: its outputs plus ``power:NAME`` of every element
    whose work is not stored as potential energy (loads, friction, dampers: the work per
    phase); returns ``(scene, {name: label})``."""
    from dataclasses import replace

    eqs = mechanism.equations(scene)
    labelled = scene.labelled_outputs()
    labels = {label for label, _ in labelled}
    by_item = {item: label for label, item in labelled if isinstance(item, str)}
    powers, extra = {}, []
    for name in eqs.elements:
        work = eqs.works[name]
        if not work.forces or work.potential != 0:     # no work, or stored (springs)
            continue
        item = f"power:{name}"
        label = by_item.get(item)
        if label is None:
            label = item if item not in labels else f"{item} (cycle)"
            extra.append((label, item))
        powers[name] = label
    if not extra:
        return scene, powers
    return replace(scene, outputs=tuple(labelled) + tuple(extra)), powers


def _check_coordinates(scenes, compiled):
    first = compiled[0].coordinates
    for scene, c in zip(scenes[1:], compiled[1:]):
        if c.coordinates != first:
            def rigid(s):
                return f" (rigid: {', '.join(n for n, _ in s.rigid)})" if s.rigid else ""
            raise DutyCycleError(
                f"duty cycle: phase {scene.name!r} has the coordinates "
                f"{', '.join(c.coordinates)}{rigid(scene)} but phase {scenes[0].name!r} "
                f"has {', '.join(first)}{rigid(scenes[0])}: the phases of a duty cycle "
                "keep their coordinates (make the same springs rigid in every phase)")


def _labels(scenes) -> list:
    """The phases' names: the scene names, numbered where one repeats."""
    names = [s.name for s in scenes]
    return [n if names.count(n) == 1 else f"{n}#{names[:k + 1].count(n)}"
            for k, n in enumerate(names)]


# ------------------------------------------------------------------ continuity
def _start(mechanism, scene, compiled, values, end_state, previous):
    """The start of a later phase: the previous end state, with the scene's initial
    values checked (restated, or a reset of a position its equations do not hold)."""
    from mechdyn.declare.scene_units import state_unit
    from mechdyn.simulate.simulation import given_initial
    from mechdyn.symbols import speed
    start = np.array(end_state, dtype=float)
    free = None
    for index, value in given_initial(compiled, mechanism, scene, values.numbers).items():
        end = start[index]
        if abs(value - end) <= _SAME * max(abs(value), abs(end)) + _SAME_ABSOLUTE:
            continue
        if free is None:
            free = _free_positions(mechanism, scene)
        name = compiled.state_names[index]
        if index < compiled.dof and compiled.coordinates[index] in free:
            start[index] = value
            continue
        key = mechanism.coordinates[[q.func.__name__ for q in mechanism.coordinates]
                                    .index(compiled.coordinates[index % compiled.dof])]
        unit = state_unit(mechanism, key if index < compiled.dof else speed(key))
        why = ("its speed is continuous" if index >= compiled.dof else
               "its equations contain this coordinate, so only a coordinate they do not "
               "contain may have its position reset")
        raise DutyCycleError(
            f"duty cycle: phase {scene.name!r} gives {name} = {value:.6g} {unit}, but it "
            f"starts where phase {previous.name!r} ended, at {name} = {end:.6g} {unit} "
            f"(state continuity: {why}); leave {name} out of the scene's initial values")
    return start


def _free_positions(mechanism, scene) -> set:
    """Names of the coordinates the scene's equations do not contain: the mass matrix,
    the forcing (loads, springs, friction, switches) and the loops."""
    eqs = mechanism.equations(scene)
    if eqs.constraints:
        return set()
    used = set(eqs.mass_matrix.free_symbols) | set(eqs.forcing.free_symbols)
    return {str(q) for q in eqs.q if q not in used}

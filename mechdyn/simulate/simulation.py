"""Simulation: integrate a scene of a mechanism.

The inputs are checked here (parameters, initial state, tolerances); the run itself is
:class:`mechdyn.simulate.driver.Driver`: segments with friction modes (:mod:`mechdyn.simulate.friction`),
methods chosen and changed by measuring the problem (:mod:`mechdyn.simulate.methods`), events
located on every step (:mod:`mechdyn.simulate.events`), budgets and progress.

Closed loops (``Equations.constraints``, see :mod:`mechdyn.compile.loop_code`): the initial
state is assembled (:func:`mechdyn.simulate.assembly.assemble`: Newton on the dependent positions
from the scene's guesses, ``G u = -dg/dt`` for the dependent speeds); the generated
``rhs`` solves ``M a = f + G' lambda``, ``G a = -bias`` with the loops always active (and
``_kkt`` stacks them with stuck frictions); after a step where the drift ``|g|`` or
``|G u + dg/dt|`` exceeds rtol times the loop's size the segment ends there and the state
is projected back (:func:`mechdyn.simulate.assembly.project`); the largest minor of ``G`` is
watched as an event, and where it changes sign with every minor small the run stops
with :class:`~mechdyn.compile.loop_code.LoopSingularError`; a loop's name as an output records
its multipliers (:meth:`_Run.loop_multipliers`).

>>> import mechdyn as md
>>> model = md.load_model("models/shoe_brake.py")
>>> res = model.mechanism.simulate(model.scenes["braking"], model.params)
>>> round(res.t_end, 9), round(res.final(model.mechanism.coordinates[0]), 6)
(50.0, 2500.0)
"""
from __future__ import annotations

import numpy as np
import sympy as sp

from mechdyn.compile.compiler import compile_scene
from mechdyn.simulate.driver import Budget, Driver
from mechdyn.declare.output_units import output_units
from mechdyn.errors import SceneError, SimulationError, did_you_mean
from mechdyn.simulate.methods import KERNEL_ONLY, choose_method
from mechdyn.declare.parameters import ParameterSet
from mechdyn.simulate.result import Result
from mechdyn.declare.scene import DEFAULT_ATOL, Scene
from mechdyn.simulate.stepping import METHODS
from mechdyn.units import finite

__all__ = ["simulate", "initial_state", "given_initial", "atol_vector", "check_method",
           "choose_method", "METHODS"]


def simulate(mechanism, scene: Scene, params: dict, *, progress=None, max_steps=None,
             max_wall_time=None, backend=None, start=None) -> Result:
    """Integrate ``scene`` on ``mechanism`` with parameter values ``params``.

    ``progress(t, t_end)`` is called about every quarter second of a run;
    ``max_steps``, ``max_wall_time`` and ``backend`` override the scene's; ``start``, a
    state ``[q..., u...]`` in the compiled order, replaces the scene's initial values (a
    later phase of a duty cycle, :mod:`mechdyn.analyse.cycle`). Raises
    :class:`SimulationError` (with ``.partial``, the result up to the failure) when the
    integration fails on every method it may use, or exceeds its budget.
    """
    if not isinstance(scene, Scene):
        raise SceneError(f"simulate() needs a md.Scene, got {scene!r}")
    values, kept = checked_values(mechanism, scene, params)      # before any compiling
    compiled = compile_scene(mechanism, scene)
    if kept.get("compiled") is not compiled:
        kept.clear()
        kept.update(compiled=compiled, base=values.vector(compiled.param_names))
    base = list(kept["base"])
    if start is None:
        initial = tuple(scene.initial.items())          # a dict: it may change in place
        if kept.get("initial") != initial:
            kept.update(initial=initial,
                        y0=initial_state(compiled, mechanism, scene, values.numbers))
        y0 = kept["y0"].copy()
    else:
        from mechdyn.declare.scene_units import check_given
        check_given(mechanism, scene)                 # its stop values' units
        y0 = np.array(start, dtype=float)
        if y0.shape != (2 * compiled.dof,) or not np.all(np.isfinite(y0)):
            raise SceneError(f"scene {scene.name!r}: start must hold {2 * compiled.dof} "
                             f"finite values ({', '.join(compiled.state_names)}), got "
                             f"{list(start)!r}")
    atol = atol_vector(compiled, mechanism, scene)
    check_method(scene)
    budget = Budget(scene.max_steps if max_steps is None else max_steps,
                    scene.max_wall_time if max_wall_time is None else max_wall_time)
    driver = Driver(compiled, base, scene, atol, mechanism, budget, progress, backend)
    try:
        result = driver.run(y0)
    except SimulationError as error:
        if error.partial is not None:
            label_units(error.partial, mechanism, scene)
        raise
    return label_units(result, mechanism, scene)


def checked_values(mechanism, scene, params) -> tuple:
    """The :class:`ParameterSet` of a run and a dict for what follows from it (the
    parameter vector, the assembled initial state), remembered per scene and parameter
    values: a session's next run with the same values skips the checks and the loops'
    assembly (the mechanism's memo is cleared by any change to the mechanism)."""
    try:
        key = tuple((k, type(v), repr(v) if type(v) is float else v) for k, v in params.items())
        hash(key)
    except (AttributeError, TypeError):                   # unhashable values: not kept
        return ParameterSet(params, mechanism=mechanism, scene=scene), {}
    hit = mechanism._memo.get(("values", id(scene)))
    if hit is not None and hit[0] is scene and hit[1] == key:
        return hit[2], hit[3]
    values = ParameterSet(params, mechanism=mechanism, scene=scene)
    mechanism._memo[("values", id(scene))] = (scene, key, values, {})
    return values, mechanism._memo[("values", id(scene))][3]


def label_units(result, mechanism, scene):
    """The SI unit of each coordinate (rad where none is declared) and output in
    ``result.units`` (remembered per scene)."""
    hit = mechanism._memo.get(("units", id(scene)))
    if hit is None or hit[0] is not scene:
        declared = {q.func.__name__: mechanism.units.get(q.func.__name__, "rad")
                    for q in mechanism.coordinates}
        hit = (scene, {**declared, **output_units(mechanism, scene)})
        mechanism._memo[("units", id(scene))] = hit
    result.units.update({label: unit for label, unit in hit[1].items()
                         if label not in result.units})
    return result


# --------------------------------------------------------------------- inputs
def given_initial(compiled, mechanism, scene, params) -> dict:
    """The initial values ``scene`` gives, evaluated: state index (in ``[q..., u...]``
    of ``compiled``) -> float; values of coordinates made rigid are left out."""
    from mechdyn.declare.scene_units import check_given
    check_given(mechanism, scene)
    n = compiled.dof
    declared = {q.func.__name__ for q in mechanism.coordinates}
    slots = {}
    for i, name in enumerate(compiled.coordinates):
        slots[("q", name)] = i
        slots[("u", name)] = n + i
    values = {str(k): v for k, v in params.items()}
    given, known = {}, _known_slots(mechanism, scene)
    for key, value in scene.initial.items():
        slot = known.get(key) or known.setdefault(key, _initial_slot(key, declared, scene))
        if slot[1] not in compiled.coordinates:
            continue                                  # a coordinate made rigid
        expr = value if isinstance(value, sp.Basic) else None
        if expr is not None:
            expr = expr.subs({s: values[s.name] for s in expr.free_symbols if s.name in values})
            if not expr.is_number:
                raise SceneError(f"scene {scene.name!r}: initial value of {key} = {value} has "
                                 f"no number (unknown: {sorted(map(str, expr.free_symbols))})")
            value = expr
        what = f"scene {scene.name!r}: initial value of {key}"
        given[slots[slot]] = finite(value, SceneError, f"{what} = {value!r} is not a number",
                                    f"{what} is not finite")
    return given


def initial_state(compiled, mechanism, scene, params) -> np.ndarray:
    """The scene's initial state vector ``[q..., u...]``, checked and evaluated."""
    n = compiled.dof
    y0 = np.full(2 * n, np.nan)
    for index, value in given_initial(compiled, mechanism, scene, params).items():
        y0[index] = value
    # Closed loops: dependent speeds are solved, dependent positions are guesses.
    solved = [n + i for i in range(n) if compiled.constraints and i not in compiled.independent]
    missing = [compiled.state_names[i] for i in range(2 * n)
               if np.isnan(y0[i]) and i not in solved]
    if missing:
        guesses = (" and a guess for each dependent coordinate, which picks the assembly "
                   "branch" if solved else "")
        phase = ("; a scene without initial values runs as a later phase of a duty "
                 "cycle, e.g. --scene startup+" + scene.name) if not scene.initial else ""
        raise SceneError(f"scene {scene.name!r}: missing initial values for "
                         f"{', '.join(missing)} (give them in initial={{q: ..., "
                         f"md.speed(q): ...}}{guesses}){phase}")
    if compiled.constraints:
        from mechdyn.simulate.assembly import assemble
        return assemble(compiled, y0, compiled.parameter_vector(params), scene.t_start,
                        scene.name, [i for i in solved if not np.isnan(y0[i])])
    return y0


def _known_slots(mechanism, scene) -> dict:
    """The slots of the scene's initial-value keys found so far (remembered per scene:
    a large model's run otherwise spends a good part of its time classifying keys)."""
    hit = mechanism._memo.get(("slots", id(scene)))
    if hit is None or hit[0] is not scene:
        hit = (scene, {})
        mechanism._memo[("slots", id(scene))] = hit
    return hit[1]


def _initial_slot(key, declared, scene, what="initial value"):
    from mechdyn.symbols import is_coordinate, t
    if is_coordinate(key) and key.func.__name__ in declared:
        return ("q", key.func.__name__)
    if isinstance(key, sp.Derivative) and is_coordinate(key.expr) and \
            key.variable_count == ((t, 1),) and key.expr.func.__name__ in declared:
        return ("u", key.expr.func.__name__)
    raise SceneError(f"scene {scene.name!r}: {what} given for {key}, which is not a "
                     f"declared coordinate or its speed (coordinates: {sorted(declared)})")


def check_method(scene):
    """Refuse a scene whose method is not ``"auto"`` or one of the known ones."""
    if scene.method != "auto" and scene.method not in (*METHODS, *KERNEL_ONLY):
        raise SceneError(f"scene {scene.name!r}: unknown method {scene.method!r}"
                         f"{did_you_mean(scene.method, (*METHODS, *KERNEL_ONLY))}; "
                         f"use 'auto' or one of {', '.join((*METHODS, *KERNEL_ONLY))}")


def atol_vector(compiled, mechanism, scene):
    """A scalar atol, or the vector of a per-state dict (``"default"`` for the rest)."""
    if not isinstance(scene.atol, dict):
        return float(scene.atol)
    declared = {q.func.__name__ for q in mechanism.coordinates}
    vector = np.full(2 * compiled.dof, float(scene.atol.get("default", DEFAULT_ATOL)))
    for key, value in scene.atol.items():
        if key == "default":
            continue
        kind, name = _initial_slot(key, declared, scene, "atol")
        if name in compiled.coordinates:
            offset = compiled.dof if kind == "u" else 0
            vector[offset + compiled.coordinates.index(name)] = float(value)
    return vector



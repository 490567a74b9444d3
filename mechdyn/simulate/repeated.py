"""One scene run at many parameter vectors that differ in a few values (a sweep's points).

:func:`~mechdyn.simulate.simulation.simulate` checks the parameter values, compiles (a
cache lookup), evaluates the initial state and the tolerances on every call: about a
fifth of a compiled shoe-brake run. :class:`RepeatedRuns` does all that once for the
fixed values and then runs a point by writing its values into a copy of the parameter
vector; the initial state is evaluated again only where it depends on the varied
values (or on all of them: closed loops assemble it). Parameters given as expressions
of a varied one (``Q: 3*P``) are evaluated again at every point, and the whole vector
rebuilt from them (``docs/caching.md``). A point's values must already
have been checked (:meth:`~mechdyn.declare.parameters.ParameterSet.refused_points`);
its result and its errors are those of ``simulate`` with the same values.

>>> import mechdyn as md
>>> brake = md.load_model("models/shoe_brake.py")
>>> runs = RepeatedRuns(brake.mechanism, brake.scenes["braking"], brake.params, ["P"])
>>> [round(runs.run((force,)).t_end, 9) for force in (10.0, 40.0)]   # 1000 / P
[100.0, 25.0]
"""
from __future__ import annotations

import sympy as sp

from mechdyn.compile.compiler import compile_scene
from mechdyn.declare.parameters import ParameterSet
from mechdyn.simulate.driver import Budget, Driver
from mechdyn.simulate.simulation import atol_vector, check_method, initial_state

__all__ = ["RepeatedRuns"]


class RepeatedRuns:
    """``run(point)`` is ``simulate(mechanism, scene, {**params, **dict(zip(varied,
    point))})`` (without the units of the result), the work common to all points done
    once here; raises what ``simulate`` raises for ``params`` when that work fails."""

    def __init__(self, mechanism, scene, params, varied):
        values = ParameterSet(params, mechanism=mechanism, scene=scene)
        self.mechanism, self.scene, self.numbers = mechanism, scene, values.numbers
        self.compiled = compile_scene(mechanism, scene)
        self.template = values.vector(self.compiled.param_names)
        self.varied = list(varied)
        self.slots = [self.compiled.param_names.index(name) for name in self.varied]
        self.derived = values.depending_on(self.varied)    # rebuilt at every point
        self.atol = atol_vector(self.compiled, mechanism, scene)
        check_method(scene)
        self.y0 = None
        changed = set(self.varied) | self.derived.keys()
        if not (self.compiled.constraints or _initial_names(scene) & changed):
            self.y0 = initial_state(self.compiled, mechanism, scene, self.numbers)

    def run(self, point):
        numbers = {**self.numbers, **dict(zip(self.varied, point))}
        if self.derived:          # values given as expressions of the varied ones
            numbers = ParameterSet({**numbers, **self.derived}, mechanism=self.mechanism,
                                   scene=self.scene).numbers
            p = [numbers[name] for name in self.compiled.param_names]
        else:
            p = list(self.template)
            for slot, value in zip(self.slots, point):
                p[slot] = value
        y0 = self.y0
        if y0 is None:
            y0 = initial_state(self.compiled, self.mechanism, self.scene, numbers)
        budget = Budget(self.scene.max_steps, self.scene.max_wall_time)
        return Driver(self.compiled, p, self.scene, self.atol, self.mechanism,
                      budget).run(y0)


def _initial_names(scene) -> set:
    """The names of the parameters the scene's initial values use."""
    return {symbol.name for value in scene.initial.values() if isinstance(value, sp.Basic)
            for symbol in value.free_symbols}

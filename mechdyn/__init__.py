"""mechdyn: dynamics of machines and mechanisms.

Declare a mechanism (links and loads as sympy expressions of generalized coordinates),
derive Lagrange's equations and the reduced quantities, print them as LaTeX, compile and
simulate scenes.

Every public name loads on first use (the declaring API with sympy, the later stages
when asked for), so a run that needs no sympy (the command line's warm start) never
imports it.
"""
from mechdyn.version import __version__

from importlib import import_module

from mechdyn.errors import (DeclarationError, DependencyError, DerivationError, MechdynError,
                     MechdynWarning, OutputError, ParameterError, SceneError, SimulationError)

# Public names loaded on first use: name -> module.
_LAZY = {
    **dict.fromkeys(["Damper", "Friction", "Gravity", "Link", "Load", "Spring"], "declare.elements"),
    **dict.fromkeys(["OneWayClutch", "Stop", "LossyGear"], "declare.unilateral"),
    **dict.fromkeys(["Element", "Work"], "declare.element_base"),
    "table": "declare.tables", "Table": "declare.tables",
    "Mechanism": "machine", "Model": "declare.model_file", "load_model": "declare.model_file",
    "Scene": "declare.scene", "reaches": "declare.scene", "stopped": "declare.scene",
    **dict.fromkeys(["acceleration", "coordinate", "coordinates", "plain", "speed", "t",
                     "same", "difference"], "symbols"),
    "classify": "derive.analytic", "Classification": "derive.analytic",
    "AnalyticError": "derive.analytic",
    "closed_form": "derive.closed_form", "Solution": "derive.closed_form",
    "StopPoint": "derive.closed_form",
    "uniform_rotation": "derive.inverse", "uniform_acceleration": "derive.inverse",
    "Motion": "derive.inverse", "DrivingMoment": "derive.inverse",
    "driving_moment": "analyse.linkage_drive",
    "natural_frequencies": "derive.modal", "Modes": "derive.modal",
    "linearize": "derive.linear", "StateSpace": "derive.linear",
    "Result": "simulate.result", "Event": "simulate.events",
    "sweep": "analyse.sweeps", "Sweep": "analyse.sweeps",
    **dict.fromkeys(["measure", "Measure", "MeasureError"], "analyse.measures"),
    **dict.fromkeys(["periodic_steady_state", "floquet", "PeriodicSolution"],
                    "analyse.periodic"),
    **dict.fromkeys(["forcing_period", "Floquet", "PeriodicError", "NoPeriodicSolutionError"],
                    "analyse.shooting"),
    **dict.fromkeys(["steady_running", "flywheel", "SteadyRunning", "Flywheel"],
                    "analyse.fluctuation"),
    **dict.fromkeys(["sensitivities", "SensitivityError"], "analyse.sensitivities"),
    "Sensitivities": "analyse.sensitivity_result",
    **dict.fromkeys(["optimize", "Optimum"], "analyse.optimize"),
    **dict.fromkeys(["OptimizeError", "GoalError"], "analyse.design_goals"),
    "work_precision": "analyse.precision", "WorkPrecision": "analyse.precision",
    "characteristic": "analyse.characteristics", "Characteristic": "analyse.characteristics",
    "to_si": "units", "UnitError": "units", "ValueTextError": "parse",
    "LoopSingularError": "compile.loop_numeric", "SingularMassError": "compile.generated",
    "AssemblyError": "simulate.assembly", "ModelFileError": "declare.model_file",
    "ReductionError": "derive.reduction", "CharacteristicError": "analyse.characteristics",
    **dict.fromkeys(["SweepError", "SweepFileError"], "analyse.sweep_file"),
    **dict.fromkeys(["FmuError", "FmuCompilerError"], "report.fmu.build"),
    "duty_cycle": "analyse.cycle", "DutyCycleError": "analyse.cycle", "CycleResult": "analyse.cycle_result",
    "animate": "report.animation", "Film": "report.animation",
    **dict.fromkeys(["Linkage", "LinkageError", "CrankSweep", "Singularity", "Grashof",
                     "grashof"], "analyse.linkage"),
    **dict.fromkeys(["kinetostatics", "shaking", "Kinetostatics", "Reaction",
                     "KinetostaticsError"], "analyse.joint_reactions"),
    **dict.fromkeys(["balance", "Balance", "Counterweight"], "analyse.balancing"),
}
# The time md.t (a sympy symbol) loads on first use too; the annotation binds nothing
# and carries its documentation where Sphinx reads it (tests/test_docstrings.py runs it).
t: "sympy.Symbol"
"""The time: a real sympy symbol, the argument of every coordinate; loads, springs and
imposed motions may depend on it, as may stop conditions.

Examples
--------
>>> import sympy as sp, mechdyn as md
>>> x = md.coordinate("x")
>>> x.args == (md.t,), md.t.is_real
(True, True)
>>> shaker = md.Mechanism("shaker", [x])
>>> _ = shaker.link("mass", m=1, x=x)
>>> shaker.load("force", sp.sin(3 * md.t), along=x).value
sin(3*t)
"""

_LAZY_MODULES = {"reduction": "derive.reduction", "units": "units", "motors": "declare.motors"}

# The public names, once each, grouped as docs/api.rst groups them
# (tests/test_docstrings.py holds the two together).
__all__ = [
    # declaring a mechanism
    "Mechanism", "coordinate", "coordinates", "speed", "acceleration", "plain", "t",
    "same", "difference", "table", "Table", "motors", "Model", "load_model",
    # elements
    "Link", "Load", "Spring", "Damper", "Gravity", "Friction", "OneWayClutch", "Stop",
    "LossyGear", "Element", "Work",
    # scenes and simulation
    "Scene", "stopped", "reaches", "Result", "Event", "duty_cycle", "CycleResult",
    # analyses
    "sweep", "Sweep", "measure", "Measure",
    "periodic_steady_state", "floquet", "forcing_period", "PeriodicSolution", "Floquet",
    "steady_running", "flywheel", "SteadyRunning", "Flywheel",
    "sensitivities", "Sensitivities", "optimize", "Optimum",
    "work_precision", "WorkPrecision",
    "linearize", "StateSpace", "natural_frequencies", "Modes",
    "classify", "Classification", "closed_form", "Solution", "StopPoint",
    "uniform_rotation", "uniform_acceleration", "Motion", "driving_moment", "DrivingMoment",
    "characteristic", "Characteristic",
    "Linkage", "CrankSweep", "Singularity", "grashof", "Grashof",
    "kinetostatics", "shaking", "Kinetostatics", "Reaction",
    "balance", "Balance", "Counterweight",
    # reports
    "animate", "Film",
    # units and reduction by hand
    "to_si", "units", "reduction",
    # errors and warnings
    "MechdynError", "MechdynWarning", "DeclarationError", "DerivationError", "SceneError",
    "ParameterError", "SimulationError", "OutputError", "DependencyError",
    "AnalyticError", "UnitError", "ValueTextError", "ModelFileError", "ReductionError",
    "AssemblyError", "LoopSingularError", "SingularMassError", "DutyCycleError",
    "SweepError", "SweepFileError", "MeasureError", "PeriodicError",
    "NoPeriodicSolutionError", "SensitivityError", "OptimizeError", "GoalError",
    "CharacteristicError", "LinkageError", "KinetostaticsError", "FmuError",
    "FmuCompilerError",
]


def __getattr__(name):
    if name in _LAZY:
        value = getattr(import_module(f".{_LAZY[name]}", __name__), name)
    elif name in _LAZY_MODULES:
        value = import_module(f".{_LAZY_MODULES[name]}", __name__)
    else:
        raise AttributeError(f"module 'mechdyn' has no attribute {name!r}")
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(__all__))

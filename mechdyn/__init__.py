"""mechdyn: dynamics of machines and mechanisms.

Declare a mechanism (links and loads as sympy expressions of generalized coordinates),
derive Lagrange's equations and the reduced quantities, print them as LaTeX, compile and
simulate scenes.

Every public name loads on first use (the declaring API with sympy, the later stages
when asked for), so a run that needs no sympy (the command line's warm start) never
imports it.
"""
__version__ = "0.1.0"

from importlib import import_module

from .errors import (DeclarationError, DerivationError, MechdynError, MechdynWarning,
                     ParameterError, SceneError, SimulationError)

# Public names loaded on first use: name -> module.
_LAZY = {
    **dict.fromkeys(["Damper", "Friction", "Gravity", "Link", "Load", "Spring"], "elements"),
    **dict.fromkeys(["OneWayClutch", "Stop", "LossyGear"], "unilateral"),
    "table": "tables", "Table": "tables",
    "Mechanism": "mechanism", "Model": "model_file", "load_model": "model_file",
    "Scene": "scene", "reaches": "scene", "stopped": "scene",
    **dict.fromkeys(["acceleration", "coordinate", "coordinates", "plain", "speed", "t"],
                    "symbols"),
    "classify": "analytic", "closed_form": "analytic", "driving_moment": "analytic",
    "uniform_rotation": "analytic", "uniform_acceleration": "analytic",
    "Classification": "analytic", "Solution": "analytic", "StopPoint": "analytic",
    "Motion": "analytic", "DrivingMoment": "analytic", "AnalyticError": "analytic",
    "natural_frequencies": "modal", "Modes": "modal",
    "linearize": "linear", "StateSpace": "linear",
    "Result": "result", "Event": "events",
    "sweep": "sweeps", "Sweep": "sweeps",
    **dict.fromkeys(["periodic_steady_state", "floquet", "forcing_period", "Floquet",
                     "PeriodicSolution", "PeriodicError", "NoPeriodicSolutionError"],
                    "periodic"),
    **dict.fromkeys(["steady_running", "flywheel", "SteadyRunning", "Flywheel"],
                    "fluctuation"),
    "work_precision": "precision", "WorkPrecision": "precision",
    "characteristic": "characteristics", "Characteristic": "characteristics",
    "to_si": "units", "UnitError": "units",
    "duty_cycle": "cycle", "DutyCycleError": "cycle", "CycleResult": "cycle_result",
    "animate": "animation", "Film": "animation",
    **dict.fromkeys(["Linkage", "LinkageError", "CrankSweep", "Singularity", "Grashof",
                     "grashof"], "linkage"),
    **dict.fromkeys(["kinetostatics", "shaking", "Kinetostatics", "Reaction",
                     "KinetostaticsError"], "joint_reactions"),
    **dict.fromkeys(["balance", "Balance", "Counterweight"], "balancing"),
}
_LAZY_MODULES = {"reduction", "units", "motors"}

__all__ = [
    "motors", "Mechanism", "Link", "Load", "Spring", "Damper", "Gravity", "Friction",
    "OneWayClutch", "Stop", "LossyGear", "table", "Table",
    "Scene", "stopped", "reaches", "Model", "load_model",
    "t", "coordinate", "coordinates", "speed", "acceleration", "plain",
    "MechdynError", "MechdynWarning", "DeclarationError", "DerivationError", "SceneError",
    "ParameterError", "SimulationError",
    *_LAZY, *_LAZY_MODULES,
]


def __getattr__(name):
    if name in _LAZY:
        value = getattr(import_module(f".{_LAZY[name]}", __name__), name)
    elif name in _LAZY_MODULES:
        value = import_module(f".{name}", __name__)
    else:
        raise AttributeError(f"module 'mechdyn' has no attribute {name!r}")
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(__all__))

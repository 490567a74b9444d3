"""mechdyn: dynamics of machines and mechanisms.

Declare a mechanism (links and loads as sympy expressions of generalized coordinates),
derive Lagrange's equations and the reduced quantities, print them as LaTeX, compile and
simulate scenes.
"""
from .analytic import (AnalyticError, Classification, DrivingMoment, Motion, Solution,
                       StopPoint, classify, closed_form, driving_moment,
                       uniform_acceleration, uniform_rotation)
from .elements import Damper, Friction, Gravity, Link, Load, Spring
from .errors import (DeclarationError, DerivationError, MechdynError, ParameterError,
                     SceneError, SimulationError)
from .mechanism import Mechanism
from .model_file import Model, load_model
from .scene import Scene, reaches, stopped
from .symbols import acceleration, coordinate, coordinates, plain, speed, t

__version__ = "0.1.0"

__all__ = [
    "Mechanism", "Link", "Load", "Spring", "Damper", "Gravity", "Friction",
    "Scene", "stopped", "reaches", "Model", "load_model",
    "t", "coordinate", "coordinates", "speed", "acceleration", "plain",
    "MechdynError", "DeclarationError", "DerivationError", "SceneError",
    "ParameterError", "SimulationError",
    "classify", "closed_form", "driving_moment", "uniform_rotation",
    "uniform_acceleration", "Classification", "Solution", "StopPoint", "Motion",
    "DrivingMoment", "AnalyticError",
]

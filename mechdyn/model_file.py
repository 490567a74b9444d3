"""Loading model files: Python files that define ``mechanism``, ``params`` and ``scenes``
(and, for linkages, optionally ``points``: name -> ``(x, y)``, points whose paths
``mechdyn linkage`` draws, such as a coupler point).

A model file is the user's own code and runs like any script. Values typed on the command
line are parsed by :mod:`mechdyn.parse`, never evaluated.

>>> model = load_model("models/shoe_brake.py")   # doctest: +SKIP
>>> sorted(model.scenes)                          # doctest: +SKIP
['braking']
"""
from __future__ import annotations

import runpy
from dataclasses import dataclass, field
from pathlib import Path

from .errors import MechdynError
from .mechanism import Mechanism
from .scene import Scene

__all__ = ["Model", "load_model"]


class ModelFileError(MechdynError, ValueError):
    """A model file that cannot be used (missing, or without a mechanism)."""


@dataclass
class Model:
    """What a model file defines."""
    path: Path
    mechanism: Mechanism
    params: dict = field(default_factory=dict)
    scenes: dict = field(default_factory=dict)
    doc: str = ""
    points: dict = field(default_factory=dict)     # name -> (x, y): coupler points

    def scene(self, name: str) -> Scene:
        """The scene called ``name``, with a clear error listing the others."""
        if name not in self.scenes:
            raise ModelFileError(f"{self.path}: no scene {name!r}; scenes: "
                                 f"{', '.join(self.scenes) or 'none'}")
        return self.scenes[name]

    def param_symbol(self, name: str):
        """The parameter symbol called ``name`` (as typed on the command line)."""
        for symbol in self.params:
            if str(symbol) == name:
                return symbol
        for symbol in self.mechanism.equations().parameters:
            if str(symbol) == name:
                return symbol
        raise ModelFileError(f"{self.path}: no parameter {name!r}; parameters: "
                             f"{', '.join(sorted(str(s) for s in self.params))}")


def load_model(path) -> Model:
    """Run a model file and collect its ``mechanism``, ``params`` and ``scenes``."""
    path = Path(path)
    if not path.is_file():
        raise ModelFileError(f"model file {path} not found")
    try:
        namespace = runpy.run_path(str(path), run_name="mechdyn_model")
    except MechdynError as error:
        raise ModelFileError(f"{path}: {error}") from error
    except Exception as error:
        line = _line_in(error, path)
        raise ModelFileError(f"{path}{line}: {type(error).__name__}: {error}") from error
    mechanism = namespace.get("mechanism")
    if not isinstance(mechanism, Mechanism):
        raise ModelFileError(f"{path} defines no `mechanism` (a md.Mechanism); a model file "
                             "defines `mechanism`, `params` (defaults) and `scenes`")
    scenes = dict(namespace.get("scenes") or {})
    for name, scene in scenes.items():
        if not isinstance(scene, Scene):
            raise ModelFileError(f"{path}: scenes[{name!r}] is not a md.Scene")
    return Model(path, mechanism, dict(namespace.get("params") or {}), scenes,
                 (namespace.get("__doc__") or "").strip(), dict(namespace.get("points") or {}))


def _line_in(error, path) -> str:
    """``", line N"`` of the deepest traceback frame inside the model file."""
    line, tb = "", error.__traceback__
    while tb is not None:
        if Path(tb.tb_frame.f_code.co_filename).resolve() == path.resolve():
            line = f", line {tb.tb_lineno}"
        tb = tb.tb_next
    return line

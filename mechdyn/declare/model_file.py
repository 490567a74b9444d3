"""Loading model files: Python files that define ``mechanism``, ``params`` and ``scenes``
(and, for linkages, optionally ``points``: name -> ``(x, y)``, points whose paths
``mechdyn linkage`` draws, such as a coupler point).

A model file is the user's own code and runs like any script. Whatever goes wrong in it
(an exception, ``sys.exit(n)``, a ``KeyboardInterrupt`` it raises itself, ``scenes`` or
``params`` of the wrong type, parameter values its mechanism refuses) is a
:class:`ModelFileError` naming the file (and the line), so ``mechdyn models`` lists the
other files and the command exits with status 2. A real Ctrl-C still interrupts. Values
typed on the command line are parsed by :mod:`mechdyn.parse`, never evaluated.

The bundled models ship with the package: ``load_model("shoe_brake")`` finds one by
name from any folder, and so does ``models/shoe_brake.py`` where no ``models`` folder is
at hand (the README's and the user guide's examples run in an empty folder).

>>> model = load_model("shoe_brake")
>>> sorted(model.scenes)
['braking']
"""
from __future__ import annotations

import importlib.util
import runpy
import signal
import threading
from collections.abc import Mapping
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path

import sympy as sp

from mechdyn.errors import MechdynError, did_you_mean
from mechdyn.declare.mechanism import Mechanism
from mechdyn.declare.scene import Scene

__all__ = ["Model", "load_model", "bundled_folder", "locate"]


class ModelFileError(MechdynError, ValueError):
    """A model file that cannot be used (missing, or without a mechanism).

    Examples
    --------
    >>> import mechdyn as md
    >>> try:
    ...     md.load_model("models/shoe_brake.py").scene("breaking")
    ... except md.ModelFileError as error:
    ...     print(error)
    models/shoe_brake.py: no scene 'breaking' (did you mean braking?); scenes: braking
    """


@dataclass
class Model:
    """What a model file defines.

    ``path``, ``mechanism``, ``params`` (default values), ``scenes`` (name -> Scene),
    ``doc`` (the file's docstring), ``points`` (name -> ``(x, y)``: coupler points);
    ``scene(name)`` and ``param_symbol(name)`` look one up by name.

    Examples
    --------
    >>> import mechdyn as md
    >>> model = md.load_model("shoe_brake")
    >>> model.mechanism.name, list(model.scenes), model.doc.splitlines()[0]
    ('Shoe brake', ['braking'], 'Shoe brake (worked example 1): a disc braked by a lever-pressed shoe.')
    >>> model.param_symbol("P"), model.params[model.param_symbol("P")]
    (P, 20)
    """
    path: Path
    mechanism: Mechanism
    params: dict = field(default_factory=dict)
    scenes: dict = field(default_factory=dict)
    doc: str = ""
    points: dict = field(default_factory=dict)     # name -> (x, y): coupler points

    def scene(self, name: str) -> Scene:
        """The scene called ``name``, with a clear error listing the others."""
        if name not in self.scenes:
            cycle = "+" in name and all(part in self.scenes for part in name.split("+"))
            hint = (" (a duty cycle A+B runs with `mechdyn simulate` or md.duty_cycle)"
                    if cycle else "")
            hint = hint or did_you_mean(name, self.scenes)
            raise ModelFileError(f"{self.path}: no scene {name!r}{hint}; scenes: "
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
        known = sorted({str(s) for s in self.params}
                       | {str(s) for s in self.mechanism.equations().parameters})
        raise ModelFileError(f"{self.path}: no parameter {name!r}{did_you_mean(name, known)}"
                             f"; parameters: {', '.join(known)}")


def load_model(path) -> Model:
    """Run a model file and collect its ``mechanism``, ``params`` and ``scenes``;
    ``path`` a file or the name of a bundled model (see :func:`locate`).

    Raises
    ------
    ModelFileError
        A file that is missing or defines no ``mechanism``, or bad ``params`` or
        ``scenes``.

    Examples
    --------
    >>> import mechdyn as md
    >>> model = md.load_model("models/shoe_brake.py")     # or the bundled name "shoe_brake"
    >>> model.scenes["braking"].until
    (stopped(phi),)
    """
    path = locate(path)
    namespace = _run(path)
    mechanism = namespace.get("mechanism")
    if not isinstance(mechanism, Mechanism):
        raise ModelFileError(f"{path} defines no `mechanism` (a md.Mechanism); a model file "
                             "defines `mechanism`, `params` (defaults) and `scenes`")
    scenes = _scenes(path, namespace.get("scenes"))
    params = _params(path, namespace.get("params"), mechanism)
    doc = namespace.get("__doc__")
    points = namespace.get("points") or {}
    if not isinstance(points, Mapping):
        raise ModelFileError(f"{path}: `points` must be a dict {{name: (x, y)}}, got "
                             f"{type(points).__name__}")
    return Model(path, mechanism, params, scenes, doc.strip() if isinstance(doc, str) else "",
                 dict(points))


def bundled_folder() -> Path:
    """The folder of the models that ship with mechdyn (package data
    ``mechdyn/models``, or ``models/`` beside the package in a source checkout)."""
    spec = importlib.util.find_spec("mechdyn.models")
    for location in (spec.submodule_search_locations or []) if spec else []:
        if Path(location).is_dir():
            return Path(location)
    return Path(__file__).resolve().parents[2] / "models"


def bundled_names() -> list:
    """The names of the bundled models (``load_model(name)``)."""
    return sorted(p.stem for p in bundled_folder().glob("*.py") if not p.name.startswith("_"))


def locate(path) -> Path:
    """The model file ``path`` names: the file itself; a bundled model by name
    (``"slider_crank"``); ``models/NAME.py`` of the bundled models where there is no
    ``models`` folder here. Otherwise a :class:`ModelFileError` that suggests the
    closest file names."""
    path = Path(path)
    if path.is_file():
        return path
    bundled = bundled_folder() / (path.stem + ".py")
    bare = path.parent == Path(".") and path.suffix in ("", ".py")
    elsewhere = path.parent == Path("models") and not Path("models").is_dir()
    if (bare or elsewhere) and bundled.is_file():
        return bundled
    local = {p.stem: str(p) for p in sorted(path.parent.glob("*.py"))} \
        if path.parent.is_dir() else {}
    hint = did_you_mean(path.stem, [*local, *bundled_names()])
    for stem, shown in local.items():                        # a file here: its path
        hint = hint.replace(f" {stem}?", f" {shown}?")
    raise ModelFileError(f"model file {path} not found{hint}; the bundled models, by "
                         f"name: {', '.join(bundled_names())}")


def _run(path) -> dict:
    """The namespace a model file leaves; anything it raises, including ``SystemExit``
    and a ``KeyboardInterrupt`` of its own, becomes a :class:`ModelFileError`."""
    with _interrupts_noted() as interrupted:
        try:
            return runpy.run_path(str(path), run_name="mechdyn_model")
        except MechdynError as error:
            raise ModelFileError(f"{path}{_line_in(error, path)}: {error}") from error
        except SystemExit as error:
            raise ModelFileError(f"{path}{_line_in(error, path)}: the model file called "
                                 f"sys.exit({error.code!r}); a model file defines "
                                 "`mechanism`, `params` and `scenes` and must not exit") \
                from None
        except KeyboardInterrupt as error:
            if interrupted:
                raise                                   # a real Ctrl-C
            raise ModelFileError(f"{path}{_line_in(error, path)}: the model file raised "
                                 "KeyboardInterrupt") from None
        except BaseException as error:
            if isinstance(error, ValueError) and "null bytes" in str(error):
                error = SyntaxError(str(error))   # Python 3.10's compile() (3.11+: this)
            text = f": {error}" if str(error) else ""
            raise ModelFileError(f"{path}{_line_in(error, path)}: "
                                 f"{type(error).__name__}{text}") from error


@contextmanager
def _interrupts_noted():
    """Note real SIGINTs (Ctrl-C) while a model file runs, so a ``KeyboardInterrupt``
    the file raises itself can be told from one the user gave."""
    noted = []
    previous = signal.getsignal(signal.SIGINT) \
        if threading.current_thread() is threading.main_thread() else None
    if not callable(previous):           # not the main thread, or SIGINT ignored or fatal
        yield noted
        return

    def note(signum, frame):
        noted.append(signum)
        previous(signum, frame)
    signal.signal(signal.SIGINT, note)
    try:
        yield noted
    finally:
        signal.signal(signal.SIGINT, previous)


def _scenes(path, scenes) -> dict:
    if scenes is None:
        return {}
    if not isinstance(scenes, Mapping):
        raise ModelFileError(f"{path}: `scenes` must be a dict {{name: md.Scene}}, got "
                             f"{type(scenes).__name__}")
    for name, scene in scenes.items():
        if not isinstance(name, str):
            raise ModelFileError(f"{path}: scene names must be strings, got {name!r}")
        if not isinstance(scene, Scene):
            raise ModelFileError(f"{path}: scenes[{name!r}] is not a md.Scene "
                                 f"(got {type(scene).__name__})")
    return dict(scenes)


def _params(path, params, mechanism) -> dict:
    """The default parameter values, checked as every run will check them."""
    from mechdyn.declare.parameters import ParameterSet
    if params is None:
        return {}
    if not isinstance(params, Mapping):
        raise ModelFileError(f"{path}: `params` must be a dict {{symbol or name: value}}, "
                             f"got {type(params).__name__}")
    for key in params:
        if not isinstance(key, (sp.Symbol, str)):
            raise ModelFileError(f"{path}: params: the key {key!r} is not a parameter "
                                 "symbol or name")
    try:
        ParameterSet(defaults=params, mechanism=mechanism)
    except MechdynError as error:
        raise ModelFileError(f"{path}: params: {error}") from None
    return dict(params)


def _line_in(error, path) -> str:
    """``", line N"`` of the deepest traceback frame inside the model file."""
    line, tb = "", error.__traceback__
    while tb is not None:
        if Path(tb.tb_frame.f_code.co_filename).resolve() == path.resolve():
            line = f", line {tb.tb_lineno}"
        tb = tb.tb_next
    return line

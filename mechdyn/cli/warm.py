"""The command line's warm start: a repeated ``mechdyn simulate`` skips the model file and
sympy.

After a run, what it needed is stored in the trusted cache (:mod:`mechdyn.cache`) under a
key made of the model file's bytes, mechdyn's own sources, the scene's name and the
``--param`` texts: the compiled scene's key, the parameter values, the initial state,
the tolerances and budget, the stop conditions and outputs, the mechanism's name and
units, and everything the model file read while it ran (:mod:`mechdyn.cli.reads`: the
files it opened and the modules it imported, from anywhere, with their hashes, the
folders it listed, the environment variables it read, the working directory and the
import path). The same command again finds the entry, checks that all of that is
unchanged, and integrates at once with the compiled scene from the cache, without
running the model file (whose declarations import sympy). The rule: a warm start gives
the answer a cold run would give, or it does not happen. A model file that read what
cannot be checked (ran a program, opened a socket or a device) is never skipped; an
entry whose compiled scene is gone is simply not used.

>>> scene = FrozenScene.from_record({"name": "braking", "t_start": 0.0,
...     "time_limit": 1000.0, "rtol": 1e-10, "method": "auto", "backend": "auto",
...     "max_steps": 1000000, "max_wall_time": None, "until": [["stopped(phi)", 0]],
...     "outputs": []})
>>> scene.until[0].direction, repr(scene.until[0])
(0, 'stopped(phi)')
"""
from __future__ import annotations

import hashlib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from mechdyn import cache
from mechdyn.keys import source_digest

__all__ = ["entry_name", "FrozenScene", "remember", "recall"]


@dataclass(frozen=True)
class FrozenStop:
    label: str
    direction: int

    def __repr__(self):
        return self.label


@dataclass(frozen=True)
class FrozenScene:
    """What a run reads of its scene, as stored data."""
    name: str
    t_start: float
    time_limit: float
    rtol: float
    method: str
    backend: str
    max_steps: int | None
    max_wall_time: float | None
    until: tuple = ()
    outputs: tuple = field(default=())

    @classmethod
    def from_record(cls, record):
        until = tuple(FrozenStop(label, int(direction)) for label, direction in
                      record["until"])
        return cls(record["name"], record["t_start"], record["time_limit"], record["rtol"],
                   record["method"], record["backend"], record["max_steps"],
                   record["max_wall_time"], until, tuple(record["outputs"]))

    def labelled_outputs(self):
        return [(label, label) for label in self.outputs]


@dataclass(frozen=True)
class _FrozenMechanism:
    name: str
    units: dict


def entry_name(model_path, scene_name, assignments) -> str | None:
    """The cache entry name of a command, or None when the model file cannot be read."""
    try:
        model = Path(model_path).read_bytes()
    except OSError:
        return None
    digest = hashlib.sha256(model)
    digest.update(source_digest().encode())
    digest.update(repr((str(scene_name), sorted(assignments or ()))).encode())
    return f"warm-{digest.hexdigest()[:32]}.json"


def remember(name, model, scene, result, atol, reads):
    """Store what the run of ``scene`` of ``model`` that gave ``result`` needed, under the
    entry ``name`` (``reads``: what loading the model file read,
    :meth:`mechdyn.cli.reads.Reads.record`; None: it cannot be verified, nothing is
    stored)."""
    if reads is None:
        return
    compiled = result.compiled
    record = {
        "scene_key": compiled.key, "base": [float(v) for v in result._base],
        "y0": [float(v) for v in result.y[:, 0]], "units": dict(result.units),
        "atol": atol.tolist() if isinstance(atol, np.ndarray) else float(atol),
        "scene": {"name": scene.name, "t_start": float(scene.t_start),
                  "time_limit": float(scene.time_limit), "rtol": float(scene.rtol),
                  "method": scene.method, "backend": scene.backend,
                  "max_steps": scene.max_steps, "max_wall_time": scene.max_wall_time,
                  "until": [[repr(c), int(c.direction)] for c in scene.until],
                  "outputs": list(compiled.output_labels)},
        "mechanism": {"name": model.mechanism.name, "units": dict(model.mechanism.units)},
        "reads": reads,
    }
    cache.store(name, record)


def recall(name, progress=None):
    """The result of the stored run ``name`` integrated again, or None when there is no
    usable entry (none, not authentic, its compiled scene gone, or anything the model
    file read changed)."""
    record = cache.load(name) if name else None
    if record is None:
        return None
    try:
        from mechdyn.cli.reads import verify
        if not verify(record["reads"]):
            return None
        stored = cache.load(f"scene-{record['scene_key']}.json")
        if stored is None:
            return None
        from mechdyn.compile.generated import CompiledScene
        compiled = CompiledScene(stored["meta"], stored["source"], record["scene_key"])
        scene = FrozenScene.from_record(record["scene"])
        mechanism = _FrozenMechanism(record["mechanism"]["name"],
                                     dict(record["mechanism"]["units"]))
        atol = record["atol"]
        atol = np.array(atol) if isinstance(atol, list) else float(atol)
    except (KeyError, TypeError, ValueError, SyntaxError):
        return None                    # an entry of another shape: the cold path rebuilds it
    from mechdyn.simulate.driver import Driver
    from mechdyn.simulate.run_checks import Budget
    if progress is not None and hasattr(progress, "t_start"):
        progress.t_start = scene.t_start
    driver = Driver(compiled, record["base"], scene, atol, mechanism,
                    Budget(scene.max_steps, scene.max_wall_time), progress)
    result = driver.run(np.array(record["y0"]))
    result.units.update(record["units"])
    return result

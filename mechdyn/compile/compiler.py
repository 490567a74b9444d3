"""Compilation: a scene's equations -> fast scalar Python functions, cached.

The state vector is ``y = [q_1..q_n, u_1..u_n]`` (coordinates, then speeds); the parameter
vector ``p`` holds the scene's parameters sorted by name, then one sign per friction
element (+1, -1 sliding that way, 0 stuck). The generated functions
(:mod:`mechdyn.compile.generate`) write into an output vector, ``f(t, y, p, out)``, and carry a
docstring stating these orders; :class:`CompiledScene` calls them from Python.
``M(q) a = f`` is solved numerically (unrolled Cholesky in the generated code), never
symbolically.

A compiled scene is cached in memory and on disk (:mod:`mechdyn.cache`: a private
directory of authenticated entries, ``$MECHDYN_CACHE``, default ``~/.cache/mechdyn``;
``MECHDYN_CACHE=off`` disables the disk), keyed by everything the code depends on
(:mod:`mechdyn.compile.scene_key`; ``docs/caching.md``): a second run of the same model
skips derivation and compilation.

>>> import mechdyn as md
>>> phi = md.coordinate("phi")
>>> disc = md.Mechanism("disc", [phi])
>>> _ = disc.link("disc", J=2, angle=phi)
>>> _ = disc.load("drive", 6, along=phi)
>>> scene = md.Scene("spin", initial={phi: 0, md.speed(phi): 0}, t_end=1)
>>> compiled = compile_scene(disc, scene)
>>> compiled.rhs(0.0, [0.0, 1.0], compiled.parameter_vector({}))
[1.0, 3.0]
"""
from __future__ import annotations

from mechdyn import cache
from mechdyn.progress import COMPILE_DELAY, announce
from mechdyn.compile.generate import generate
from mechdyn.compile.generated import CompiledScene, SingularMassError
from mechdyn.compile.scene_key import declaration_key
from mechdyn.derive.equations import equations
from mechdyn.derive.selection import select

__all__ = ["CompiledScene", "compile_scene", "SingularMassError"]

_memory_cache: dict = {}


def compile_scene(mechanism, scene) -> CompiledScene:
    """The compiled functions of ``scene`` on ``mechanism``, from cache when possible."""
    key = declaration_key(mechanism, scene)
    if key in _memory_cache:
        return _memory_cache[key]
    stored = cache.load(f"scene-{key}.json")      # authenticated, else None
    compiled = None
    if stored is not None:
        try:
            compiled = CompiledScene(stored["meta"], stored["source"], key)
        except Exception:            # authentic but malformed: rebuilt and overwritten
            compiled = None
    if compiled is None:
        with announce(f"deriving and generating the code of scene {_shown(scene)}",
                      delay=COMPILE_DELAY, cached=cache.cache_dir() is not None):
            meta, source = generate(equations(mechanism, scene), select(mechanism, scene))
        compiled = CompiledScene(meta, source, key)
        cache.store(f"scene-{key}.json", {"meta": meta, "source": source})
    _memory_cache[key] = compiled
    return compiled


def _shown(scene) -> str:
    """A scene as the announcement names it."""
    return "(all elements)" if scene is None else repr(scene.name)



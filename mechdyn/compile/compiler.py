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
``MECHDYN_CACHE=off`` disables the disk), keyed by a hash of the mechanism's declaration
and the scene's effects, rigid springs, stop conditions and outputs: a second run of the
same model skips derivation and compilation.

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

import hashlib
from pathlib import Path

import sympy as sp

from mechdyn.version import __version__

from mechdyn import cache
from mechdyn.compile.generate import generate
from mechdyn.compile.generated import CompiledScene, SingularMassError
from mechdyn.declare.element_base import behaviour_key
from mechdyn.derive.equations import equations
from mechdyn.derive.selection import select

__all__ = ["CompiledScene", "compile_scene", "SingularMassError"]

_memory_cache: dict = {}


# ------------------------------------------------------------------------- caching
def _generator_hash() -> str:
    """A hash of the modules that shape generated code, so editing them voids the cache."""
    package = Path(__file__).parents[1]
    digest = hashlib.sha256()
    for module in ("derive/lagrange.py", "derive/terms.py", "compile/codegen.py",
                   "compile/generate.py", "compile/mass_solve.py", "compile/band_linalg.py",
                   "compile/reroll.py", "compile/numba_model.py",
                   "compile/generated.py", "compile/compiler.py", "declare/elements.py",
                   "symbols.py", "compile/loop_code.py", "compile/output_code.py",
                   "declare/unilateral.py", "derive/selection.py", "declare/element_base.py"):
        digest.update((package / module).read_bytes())
    return digest.hexdigest()[:16]


_GENERATOR = _generator_hash()


def declaration_key(mechanism, scene) -> str:
    """A hash of everything the compiled code depends on (remembered for a scene until
    the mechanism changes)."""
    memo = getattr(mechanism, "_memo", {})
    hit = memo.get(("key", id(scene)))
    if hit is not None and hit[0] is scene:
        return hit[1]
    key = _declaration_key(mechanism, scene)
    memo[("key", id(scene))] = (scene, key)
    return key


def _declaration_key(mechanism, scene) -> str:
    names, rigid = select(mechanism, scene).key
    parts = [__version__, _GENERATOR, [q.func.__name__ for q in mechanism.coordinates],
             sorted(mechanism.parameter_units.items())]   # units: checked when derived
    for element in mechanism.elements.values():
        parts.append([behaviour_key(type(element)), element.name, list(element.tags),
                      sorted((k, sp.srepr(v)) for k, v in element.expressions().items())])
    parts += [list(names), [list(r) for r in rigid]]
    if mechanism.constraints:
        parts.append([q.func.__name__ for q in mechanism.independent])
    if scene is not None:
        parts.append([[label, sp.srepr(o) if isinstance(o, sp.Basic) else str(o)]
                      for label, o in scene.labelled_outputs()])
        parts.append([[sp.srepr(c.expression), sp.srepr(c.value), c.direction, repr(c)]
                      for c in scene.until])
    return hashlib.sha256(repr(parts).encode()).hexdigest()[:32]


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
        meta, source = generate(equations(mechanism, scene), select(mechanism, scene))
        compiled = CompiledScene(meta, source, key)
        cache.store(f"scene-{key}.json", {"meta": meta, "source": source})
    _memory_cache[key] = compiled
    return compiled



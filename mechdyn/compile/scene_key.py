"""The key of a scene's compiled code, derived from everything that determines it.

The compiled code of a scene is a function of mechdyn's own sources (all of them: the
version of the generator), the scene's selection, outputs and stop conditions, and each
element: its class and its whole content (every attribute, not only its
``expressions()``). For mechdyn's own elements that is complete: their behaviour is in
mechdyn's sources. A class defined elsewhere may read what no key can see (a module
constant, a closure's cell, a mutable class attribute), so its part of the key is what
it *produced*: the :class:`~mechdyn.declare.element_base.Work` its ``work()`` returns,
evaluated again on every call (``docs/caching.md``).

>>> import mechdyn as md
>>> phi = md.coordinate("phi")
>>> disc = md.Mechanism("disc", [phi])
>>> _ = disc.link("disc", J=2, angle=phi)
>>> _ = disc.load("drive", 6, along=phi)
>>> scene = md.Scene("spin", initial={phi: 0, md.speed(phi): 0}, t_end=1)
>>> key = declaration_key(disc, scene)
>>> len(key), key == declaration_key(disc, scene)
(32, True)
>>> _ = disc.load("brake", -1, along=phi)
>>> key == declaration_key(disc, scene)
False
"""
from __future__ import annotations

import hashlib
import types

from mechdyn.derive.equations import foreign_works
from mechdyn.derive.selection import select
from mechdyn.keys import attributes, content, foreign, source_digest

__all__ = ["declaration_key"]


def declaration_key(mechanism, scene) -> str:
    """A hash of everything the compiled code of ``scene`` on ``mechanism`` depends on
    (module doc). The part from the declarations is remembered per scene until the
    mechanism changes (elements and scenes are frozen); what foreign elements produce
    is evaluated on every call."""
    memo = getattr(mechanism, "_memo", {})
    hit = memo.get(("key", id(scene)))
    if hit is None or hit[0] is not scene:
        hit = memo[("key", id(scene))] = (scene, _declared(mechanism, scene), any(
            foreign(type(element)) for element in mechanism.elements.values()))
    produced = foreign_works(mechanism, scene) if hit[2] else {}
    if not produced:
        return hit[1]
    parts = [hit[1], sorted((name, content(work)) for name, work in produced.items())]
    return hashlib.sha256(repr(parts).encode()).hexdigest()[:32]


def _declared(mechanism, scene) -> str:
    """The hash of the declarations' part of the key."""
    chosen = select(mechanism, scene)
    parts = [source_digest(), [q.func.__name__ for q in mechanism.coordinates],
             sorted(mechanism.parameter_units.items()), sorted(mechanism.units.items())]
    for element in mechanism.elements.values():
        parts.append([_class_key(type(element)), attributes(element)])
    parts += [list(chosen.names), [list(r) for r in chosen.rigid]]
    if mechanism.constraints:
        parts.append([q.func.__name__ for q in mechanism.independent])
    if scene is not None:
        parts.append([[label, content(o)] for label, o in scene.labelled_outputs()])
        parts.append([[content(c.expression), content(c.value), c.direction, repr(c)]
                      for c in scene.until])
    return hashlib.sha256(repr(parts).encode()).hexdigest()[:32]


def _class_key(element_type) -> str:
    """An element class: its module and name, and for a class defined outside mechdyn a
    hash of its methods' code and class data (what ``output`` or ``check_units`` read)."""
    name = f"{element_type.__module__}.{element_type.__qualname__}"
    if not foreign(element_type):
        return name
    digest = hashlib.sha256()
    for base in element_type.__mro__:
        if base is object or base.__module__.split(".")[0] == "mechdyn":
            continue
        for attribute, value in sorted(vars(base).items()):
            value = getattr(value, "__func__", getattr(value, "fget", value))
            if isinstance(getattr(value, "__code__", None), types.CodeType):
                digest.update(attribute.encode())
                _digest_code(value.__code__, digest)
            elif not attribute.startswith("__") and not callable(value):
                digest.update(f"{attribute}={content(value)}".encode())
    return f"{name}:{digest.hexdigest()[:16]}"


def _digest_code(code, digest):
    digest.update(code.co_code + repr(code.co_names).encode())
    for constant in code.co_consts:
        if isinstance(constant, types.CodeType):
            _digest_code(constant, digest)
        elif isinstance(constant, frozenset):       # its order varies with the hash seed
            digest.update(repr(sorted(map(repr, constant))).encode())
        else:
            digest.update(repr(constant).encode())

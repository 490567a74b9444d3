"""Keys of kept things, derived from their content: a value as text that is the same in
every process for the same content (:func:`content`), the version of mechdyn's own code
(:func:`source_digest`), and whether a class's behaviour lies outside it
(:func:`foreign`). The rule they serve is in ``docs/caching.md``.

>>> import sympy as sp
>>> content([1, 1.0, sp.Symbol("k", positive=True)])
"list[int:1,float:1.0,Symbol('k', positive=True)]"
>>> foreign(int), len(source_digest())
(False, 16)
"""
from __future__ import annotations

import dataclasses
import hashlib
from pathlib import Path

import numpy as np

__all__ = ["content", "attributes", "source_digest", "foreign"]


def source_digest() -> str:
    """A hash of every module of mechdyn (the generator's version): editing any of them
    voids the compiled code; computed once per process (BLAKE2b: some 1 MB of source
    in about 2 ms)."""
    global _SOURCES
    if _SOURCES is None:
        digest = hashlib.blake2b(digest_size=8)
        package = Path(__file__).parent
        for path in sorted(package.rglob("*.py")):
            digest.update(str(path.relative_to(package)).encode() + b"\0")
            digest.update(path.read_bytes())
        _SOURCES = digest.hexdigest()[:16]
    return _SOURCES


_SOURCES = None


def content(value) -> str:
    """A value as key text, the same in every process for the same content: sympy by
    ``srepr``, arrays by their bytes, containers and dataclasses item by item; any other
    object by its type and ``repr`` (an address in it keeps the key to one process)."""
    import sympy as sp      # here: the command line's warm start hashes sources without sympy
    if isinstance(value, sp.Basic):
        return sp.srepr(value)
    if isinstance(value, (str, bool, type(None))):
        return repr(value)
    if isinstance(value, (int, float, complex)):
        return f"{type(value).__name__}:{value!r}"
    if isinstance(value, np.ndarray):
        if value.dtype.hasobject:
            return f"object array{value.shape}{content(value.ravel().tolist())}"
        data = hashlib.sha256(np.ascontiguousarray(value).tobytes()).hexdigest()
        return f"array({value.dtype.str},{value.shape},{data})"
    if isinstance(value, (list, tuple)):
        return f"{type(value).__name__}[{','.join(map(content, value))}]"
    if isinstance(value, (set, frozenset)):
        return f"{type(value).__name__}{{{','.join(sorted(map(content, value)))}}}"
    if isinstance(value, dict):
        items = sorted((content(k), content(v)) for k, v in value.items())
        return "{" + ",".join(f"{k}:{v}" for k, v in items) + "}"
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return attributes(value)
    return f"{type(value).__module__}.{type(value).__qualname__}:{value!r}"


def attributes(value) -> str:
    """A dataclass or element by its class and every attribute it holds."""
    held = getattr(value, "__dict__", None)
    if held is None:
        held = {f.name: getattr(value, f.name) for f in dataclasses.fields(value)}
    return f"{type(value).__qualname__}({content(held)})"


def foreign(cls) -> bool:
    """Whether a class (or one of its bases) is defined outside mechdyn: its behaviour
    is not in :func:`source_digest`."""
    return any(base.__module__.split(".")[0] not in ("mechdyn", "builtins")
               for base in cls.__mro__)

"""Where numba keeps mechdyn's own compiled functions (the kernels, the banded solves, the
mode numerics): in mechdyn's cache folder (:func:`mechdyn.cache.cache_dir`), under
``kernels/``, never beside the installed package, where ``pip uninstall`` would leave a
``__pycache__`` behind (and a later editable install's ``import mechdyn`` would find an
empty namespace package there).

Importing this module registers a numba cache locator for the source files of the
mechdyn package only (a program's own numba functions keep numba's usual places, and
``NUMBA_CACHE_DIR`` is neither read nor set for them). Their files go to a folder named
after the source folder's path, as numba names the folders of ``NUMBA_CACHE_DIR``, so two
installed copies never overwrite each other's. Without a disk cache (``MECHDYN_CACHE=off``,
or a folder that cannot be trusted or written) ``CACHED`` is False: the functions are
decorated with ``cache=CACHED`` and compiled in memory, once per process; where a
write is refused (a full disk) the function is kept for the process, with the cache's
one warning.

>>> from pathlib import Path
>>> place = folder_for(Path(__file__).with_name("kernels") / "loop.py")
>>> place is None or (place.parent.name == "kernels" and place.name.startswith("kernels_"))
True
"""
from __future__ import annotations

from contextlib import suppress
from pathlib import Path

from numba.core import caching

from mechdyn import cache

__all__ = ["CACHED", "folder_for"]

PACKAGE = Path(__file__).resolve().parent


_IMPL = getattr(caching, "CacheImpl", None) or getattr(caching, "_CacheImpl", None)
_MIXIN = getattr(caching, "_SourceFileBackedLocatorMixin", None)
_LOCATOR = getattr(caching, "_CacheLocator", None)
_FILE = getattr(caching, "IndexDataCacheFile", None)


def _root():
    """``<cache folder>/kernels``, made private; None without a usable disk cache or
    without the numba internals this module needs (numba 0.61 to 0.68 have them)."""
    directory = cache.cache_dir()
    if directory is None or None in (_IMPL, _MIXIN, _LOCATOR, _FILE):
        return None
    try:
        (directory / "kernels").mkdir(mode=0o700, exist_ok=True)
    except OSError as error:         # read-only or full: compiled in memory, said once
        cache.write_failed(directory, error)
        return None
    return directory / "kernels"


_ROOT = _root()
CACHED = _ROOT is not None          # njit(cache=CACHED) in mechdyn's own modules


def folder_for(source: Path):
    """The folder of numba's files for a source file of the mechdyn package (under
    ``kernels/``) or of a scene's compiled module (its ``__pycache__``, in the cache
    folder's ``numba/``: read there also where the folder is read-only); None for a file
    elsewhere, or without a disk cache."""
    source = Path(source).resolve()
    if _ROOT is None:
        return None
    if PACKAGE in source.parents:
        return _ROOT / _LOCATOR.get_suitable_cache_subpath(str(source))
    if _ROOT.parent.resolve() / "numba" in source.parents:
        return source.parent / "__pycache__"
    return None


if CACHED:
    class _MechdynLocator(_MIXIN, _LOCATOR):
        """numba's cache locator for mechdyn's own source files (:func:`folder_for`)."""

        def __init__(self, py_func, py_file):
            self._py_file = py_file
            self._lineno = py_func.__code__.co_firstlineno
            self._cache_path = str(folder_for(py_file))

        def get_cache_path(self):
            return self._cache_path

        @classmethod
        def from_function(cls, py_func, py_file):
            if folder_for(py_file) is None:
                return None
            locator = cls(py_func, py_file)
            with suppress(OSError):      # read-only or full: saving fails, and says so, later
                super(_MechdynLocator, locator).ensure_cache_path()
            return locator

        def ensure_cache_path(self):
            """numba's, before it saves: a folder the cache may not create or write to
            (read-only, full) leaves the function compiled for this process only, with
            the cache's one warning."""
            try:
                super().ensure_cache_path()
            except OSError as error:
                cache.write_failed(_ROOT.parent, error)

    def _save_or_not(self, key, data, _save=_FILE.save):
        """numba's save, except that a write mechdyn's cache folder refuses (a full
        disk, a file size limit) leaves the function compiled for this process only,
        with the cache's one warning (numba removes its partial file)."""
        ours = Path(self._cache_path).resolve().is_relative_to(_ROOT.parent.resolve())
        if ours and cache.refused(_ROOT.parent):
            return
        try:
            _save(self, key, data)
        except OSError as error:
            if not ours:
                raise
            cache.write_failed(_ROOT.parent, error)

    if not any(c.__name__ == "_MechdynLocator" for c in _IMPL._locator_classes):
        _IMPL._locator_classes.insert(0, _MechdynLocator)
        _FILE.save = _save_or_not

"""What a model file read while it ran: the warm start's proof that a repeated command
would get the same declaration.

:func:`watching` records, for the code run inside it, every file opened (data files,
helper modules imported from anywhere: their sources), every folder listed, every
environment variable read, the working directory (when a relative path was opened) and
the import path. :func:`verify` tells whether all of that is still as it was. Code that
reads what cannot be checked later (runs a program, opens a socket, reads a device or
a FIFO) makes the record unverifiable: the command then always runs cold.

>>> import os, tempfile
>>> folder = tempfile.mkdtemp()
>>> data = os.path.join(folder, "brake.json")
>>> _ = open(data, "w").write('{"P": 20}')
>>> with watching() as reads:
...     text = open(data).read()
...     home = os.environ.get("MECHDYN_EXAMPLE_VARIABLE")
>>> record = reads.record()
>>> verify(record)
True
>>> _ = open(data, "w").write('{"P": 10}')
>>> verify(record)
False
"""
from __future__ import annotations

import hashlib
import importlib.util
import os
import stat
import sys
from collections.abc import MutableMapping
from contextlib import contextmanager
from pathlib import Path

__all__ = ["Reads", "watching", "verify"]

_MECHDYN = Path(__file__).resolve().parents[1]
_LISTINGS = {"os.listdir", "os.scandir", "glob.glob"}
_UNVERIFIABLE = {"subprocess.Popen": "runs a program", "os.system": "runs a program",
                 "os.exec": "runs a program", "os.posix_spawn": "runs a program",
                 "os.spawn": "runs a program", "os.fork": "forks",
                 "socket.connect": "opens a network connection",
                 "socket.getaddrinfo": "looks up a network address",
                 "urllib.Request": "opens a URL"}
_active: list = []                 # the Reads being recorded (innermost last)
_hooked = False


class Reads:
    """What the code run inside :func:`watching` read (see the module docstring)."""

    def __init__(self):
        self.files, self.folders, self.environment = set(), set(), {}
        self.relative = False
        self.everything = False       # the whole environment was read
        self.unverifiable = ""        # why the record cannot be checked, if so
        self._written = set()         # variables it set itself (not read from outside)
        self._modules = []            # modules imported while watched

    def note(self, event, args):
        if event == "open":
            path = args[0]
            if isinstance(path, (str, bytes, os.PathLike)):
                path = os.fsdecode(path)
                self.relative |= not os.path.isabs(path)
                self.files.add(os.path.abspath(path))
        elif event in _LISTINGS:
            path = args[0] if args and args[0] is not None else "."
            if isinstance(path, (str, bytes, os.PathLike)):
                path = os.fsdecode(path)
                self.relative |= not os.path.isabs(path)
                folder = os.path.dirname(path) if event == "glob.glob" else path
                self.folders.add(os.path.abspath(folder or "."))
        elif event in _UNVERIFIABLE and not self.unverifiable:
            self.unverifiable = f"the model file {_UNVERIFIABLE[event]}"

    def record(self) -> dict | None:
        """The record to store (JSON), or None when it cannot be verified later."""
        if self.unverifiable:
            return None
        files = {}
        for path in sorted({_source(p) for p in self.files | _module_files(self._modules)}):
            if _ignored(path):
                continue
            digest = _file_digest(path)
            if digest == "unverifiable":
                return None
            files[path] = digest
        return {"files": files,
                "folders": {folder: _listing(folder) for folder in sorted(self.folders)
                            if not _ignored(folder)},
                "environment": dict(sorted(self.environment.items())),
                "everything": _environment_digest() if self.everything else None,
                "cwd": os.getcwd() if self.relative else None,
                "path": list(sys.path)}


@contextmanager
def watching():
    """Record what the code run inside reads (audit hooks for files, folders and
    programs; ``os.environ`` watched for the variables)."""
    global _hooked
    if not _hooked:
        sys.addaudithook(_hook)
        _hooked = True
    reads = Reads()
    before = set(sys.modules)
    real = os.environ
    os.environ = _WatchedEnvironment(real, reads)
    _active.append(reads)
    try:
        yield reads
    finally:
        _active.remove(reads)
        os.environ = real
        reads._modules = [module for name, module in list(sys.modules.items())
                          if name not in before]


def verify(record) -> bool:
    """Whether everything ``record`` (from :meth:`Reads.record`) saw is unchanged."""
    try:
        if record["cwd"] is not None and record["cwd"] != os.getcwd():
            return False
        if record["path"] != list(sys.path):
            return False
        if any(os.environ.get(name) != value
               for name, value in record["environment"].items()):
            return False
        if record["everything"] is not None and record["everything"] != _environment_digest():
            return False
        if any(_listing(folder) != listing for folder, listing in record["folders"].items()):
            return False
        return all(_file_digest(path) == digest for path, digest in record["files"].items())
    except (KeyError, TypeError, AttributeError):
        return False                  # a record of another shape: run cold


# ---------------------------------------------------------------- internals
def _hook(event, args):
    if _active:
        try:
            _active[-1].note(event, args)
        except Exception:             # an audit hook must never break the code it watches
            _active[-1].unverifiable = "the model file did something that cannot be recorded"


class _WatchedEnvironment(MutableMapping):
    """``os.environ`` that notes the variables read (writes pass through)."""

    def __init__(self, real, reads):
        self._real, self._reads = real, reads

    def __getitem__(self, name):
        if name not in self._reads._written:
            self._reads.environment.setdefault(name, self._real.get(name))
        return self._real[name]

    def __setitem__(self, name, value):
        self._reads._written.add(name)
        self._real[name] = value

    def __delitem__(self, name):
        self._reads._written.add(name)
        del self._real[name]

    def __iter__(self):
        self._reads.everything = True
        return iter(self._real)

    def __len__(self):
        self._reads.everything = True
        return len(self._real)

    def copy(self):
        self._reads.everything = True
        return self._real.copy()


def _module_files(modules) -> set:
    """The files modules were loaded from (sources, not bytecode)."""
    files = set()
    for module in modules:
        path = getattr(module, "__file__", None)
        if isinstance(path, str):
            files.add(os.path.abspath(path))
    return files


def _ignored(path) -> bool:
    """mechdyn's own files (in the key already) and the cache's (it changes by itself)."""
    from mechdyn.cache import cache_dir
    resolved = Path(path).resolve()
    folder = cache_dir()
    return resolved == _MECHDYN or _MECHDYN in resolved.parents or (folder is not None and
                                           folder.resolve() in resolved.parents)


def _file_digest(path) -> str | None:
    """The SHA-256 of a regular file, None for a missing one, ``"unverifiable"`` for a
    device, FIFO or socket."""
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    except FileNotFoundError:
        return None
    except IsADirectoryError:
        return "folder"
    except OSError:
        return "unverifiable"
    with os.fdopen(fd, "rb") as handle:
        info = os.fstat(handle.fileno())
        if stat.S_ISDIR(info.st_mode):
            return "folder"
        if not stat.S_ISREG(info.st_mode):
            return "unverifiable"
        digest = hashlib.sha256()
        for block in iter(lambda: handle.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def _source(path) -> str:
    """A compiled module (``__pycache__/name.cpython-311.pyc``) stands for its source."""
    if path.endswith(".pyc") and "__pycache__" in path:
        try:
            return importlib.util.source_from_cache(path)
        except ValueError:
            pass
    return path


def _listing(folder) -> str | None:
    try:
        names = sorted(os.listdir(folder))
    except OSError:
        return None
    return hashlib.sha256("\0".join(names).encode()).hexdigest()


def _environment_digest() -> str:
    items = sorted(os.environ.items())
    return hashlib.sha256(repr(items).encode()).hexdigest()

"""The trusted disk cache: a private directory of authenticated entries.

mechdyn keeps generated code on disk so a second run skips derivation and compilation.
Loading such an entry runs its code, so an entry is used only when this user's mechdyn
wrote it:

- the directory (``$MECHDYN_CACHE``, default ``$XDG_CACHE_HOME/mechdyn`` or
  ``~/.cache/mechdyn``; ``off`` disables it) is created private (0700) and refused,
  with one warning and no disk cache for the run, when another user owns it or others
  may write to it;
- every entry carries an HMAC-SHA256 of its name and bytes under a random 32-byte key,
  the file ``key`` (0600) inside the directory, made on first use. An entry whose MAC
  does not match (planted, copied, corrupted, truncated) is ignored, never executed,
  and the caller rebuilds and overwrites it;
- writes go to a temporary file renamed into place, so concurrent runs never see half
  an entry; a read-only or full directory costs the warm start, with one warning.

The trust model and its limits are in ``docs/security.md``.

>>> import os, tempfile
>>> from unittest import mock
>>> with mock.patch.dict(os.environ, MECHDYN_CACHE=tempfile.mkdtemp()):
...     store("example.json", {"answer": 42}), load("example.json"), load("other.json")
(True, {'answer': 42}, None)
"""
from __future__ import annotations

import errno
import hashlib
import hmac
import json
import os
import secrets
import shutil
import stat
import warnings
from pathlib import Path

from mechdyn.errors import MechdynWarning

__all__ = ["cache_dir", "load", "store", "load_bytes", "store_bytes", "write_failed",
           "CacheWarning"]

KEY_NAME = "key"
_KEY_BYTES = 32
_MAGIC = b"mechdyn-cache-1 "
_DISABLED = ("off", "0", "no", "false")
MAX_ENTRY_BYTES = 64 << 20     # larger entries are not read (a planted sparse file)
_warned: set = set()           # (directory, reason) pairs already warned about
_read_only: set = set()        # directories that refused a write: no more attempts


class CacheWarning(MechdynWarning):
    """The disk cache is not used (refused directory, unwritable, full)."""


def cache_dir() -> Path | None:
    """The cache directory, created private (0700) if missing; ``None`` when the disk
    cache is off or the directory cannot be trusted (then a :class:`CacheWarning` says
    why, once per directory and reason)."""
    setting = os.environ.get("MECHDYN_CACHE", "")
    if setting.lower() in _DISABLED:
        return None
    try:
        if setting:
            directory = Path(setting).expanduser()
        else:
            base = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
            directory = Path(base) / "mechdyn"
    except (RuntimeError, KeyError):           # no home directory to expand
        return _refuse(Path(setting or "~/.cache/mechdyn"), "there is no home directory")
    try:
        directory.mkdir(mode=0o700, parents=True, exist_ok=True)
        info = os.stat(directory)
    except OSError as error:
        return _refuse(directory, f"it cannot be created ({error.strerror or error})")
    problem = _untrusted(info, "directory")
    if problem:
        return _refuse(directory, problem)
    return directory


def load_bytes(name: str) -> bytes | None:
    """The bytes stored under ``name``, or ``None`` if there is no authentic entry
    (none, disk cache off, or an entry that fails authentication: never trusted)."""
    directory, key = _directory_and_key(create=False)
    if key is None:
        return None
    path = directory / _checked(name)
    try:
        with _open_private(path) as handle:
            blob = handle.read(MAX_ENTRY_BYTES + 1)
    except _Untrusted:                    # a directory, FIFO, huge or foreign file
        _discard(path)
        return None
    except OSError as error:
        if error.errno == errno.ELOOP:    # a symbolic link
            _discard(path)
        return None
    header, newline, data = blob.partition(b"\n")
    if not newline or not header.startswith(_MAGIC):
        return None
    expected = _mac(key, name, data).encode()
    return data if hmac.compare_digest(header[len(_MAGIC):], expected) else None


def store_bytes(name: str, data: bytes) -> bool:
    """Store ``data`` under ``name`` (atomically replacing any entry); ``False`` when
    the disk cache is off or the write failed (one warning per directory)."""
    directory, key = _directory_and_key(create=True)
    if key is None or directory in _read_only:
        return False
    path = directory / _checked(name)
    blob = _MAGIC + _mac(key, name, data).encode() + b"\n" + bytes(data)
    try:
        _write_atomically(path, blob)
    except OSError as error:
        write_failed(directory, error)
        return False
    return True


def write_failed(directory: Path, error: OSError):
    """Note that ``directory`` refused a write (read-only, full, a file size limit):
    one warning per directory and reason, and no more attempts by :func:`store_bytes`
    (also for what numba writes there, :mod:`mechdyn.numba_cache`)."""
    _read_only.add(directory)
    _warn(directory, f"cannot write to it ({_reason(error)}); runs go on without "
          "storing compiled code")


def refused(directory: Path) -> bool:
    """Whether ``directory`` refused a write in this process (:func:`write_failed`)."""
    return directory in _read_only


def load(name: str) -> dict | None:
    """The JSON object stored under ``name``, or ``None`` (missing, not authentic, or
    not a JSON object: the caller rebuilds it and stores it again)."""
    data = load_bytes(name)
    if data is None:
        return None
    try:
        value = json.loads(data)
    except ValueError:
        return None
    return value if isinstance(value, dict) else None


def store(name: str, value: dict) -> bool:
    """Store a JSON-serialisable dict under ``name`` (see :func:`store_bytes`)."""
    return store_bytes(name, json.dumps(value).encode())


# ------------------------------------------------------------------- internals
def _checked(name: str) -> str:
    """An entry name: one plain file name (no separators, no leading dot: the key and
    temporary files are never entries)."""
    if (not isinstance(name, str) or not name or name.startswith(".") or name == KEY_NAME
            or "/" in name or "\\" in name or "\0" in name or len(name) > 200):
        raise ValueError(f"cache entry name {name!r}: give a plain file name")
    return name


def _mac(key: bytes, name: str, data: bytes) -> str:
    """HMAC-SHA256 over the entry's name and bytes: an entry cannot be renamed into
    another's place, nor altered."""
    message = name.encode() + b"\0" + bytes(data)
    return hmac.new(key, message, hashlib.sha256).hexdigest()


def _directory_and_key(create: bool):
    directory = cache_dir()
    if directory is None:
        return None, None
    try:
        return directory, _key(directory, create)
    except OSError as error:
        _warn(directory, f"its key file cannot be made ({_reason(error)}); no disk cache")
        return None, None


def _key(directory: Path, create: bool) -> bytes | None:
    """The directory's HMAC key; a fresh one when missing (if ``create``) or not
    trustworthy (wrong owner, readable by others, wrong size: entries signed with it are
    then rebuilt)."""
    path = directory / KEY_NAME
    try:
        with _open_private(path) as handle:
            key = handle.read(_KEY_BYTES + 1)
        if len(key) == _KEY_BYTES:
            return key
        problem = f"{len(key)} bytes instead of {_KEY_BYTES}"
    except FileNotFoundError:
        if not create:
            return None
        problem = ""
    except _Untrusted as error:
        problem = str(error)
    except OSError as error:
        if error.errno != errno.ELOOP:
            raise
        problem = "is a symbolic link"
    if problem:
        _warn(directory, f"its key file {problem}: replaced by a new key (cached "
              "entries are rebuilt)")
    key = secrets.token_bytes(_KEY_BYTES)
    temporary = _temporary(path)
    try:
        _write_new(temporary, key)
        try:
            if problem:
                _discard(path)                     # the old key is not to be trusted
                os.replace(temporary, path)
            else:
                os.link(temporary, path)           # a concurrent run may have made one
        except FileExistsError:
            return _key(directory, create=False)   # another run made it first
        except OSError as error:
            if error.errno not in (errno.EPERM, errno.ENOTSUP, errno.EOPNOTSUPP):
                raise
            os.replace(temporary, path)            # no hard links here: last writer wins
    finally:
        temporary.unlink(missing_ok=True)
    return key


class _Untrusted(OSError):
    """A file this user's mechdyn did not make private."""


class _open_private:
    """Open a regular file for reading without following symbolic links and without
    blocking (a FIFO in its place), checking it is a regular file of at most
    ``MAX_ENTRY_BYTES``, owned by this user and not writable (nor, for the key,
    readable) by others."""

    def __init__(self, path: Path):
        self.path = path
        self.fd = os.open(path, os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0)
                          | getattr(os, "O_NONBLOCK", 0))

    def __enter__(self):
        try:
            info = os.fstat(self.fd)
            problem = _untrusted(info, "file", secret=self.path.name == KEY_NAME)
            if not problem and info.st_size > MAX_ENTRY_BYTES:
                problem = f"holds {info.st_size} bytes, more than {MAX_ENTRY_BYTES}"
            if problem:
                raise _Untrusted(problem)
            self.handle = os.fdopen(self.fd, "rb")
        except BaseException:
            os.close(self.fd)
            raise
        return self.handle

    def __exit__(self, *exc):
        self.handle.close()


def _untrusted(info, kind: str, secret: bool = False) -> str:
    """Why a directory or file (``os.stat`` result) is not to be trusted, or ``""``."""
    expected = stat.S_ISDIR if kind == "directory" else stat.S_ISREG
    if not expected(info.st_mode):
        return f"is not a {kind}"
    if not hasattr(os, "geteuid"):
        return ""                  # no POSIX owners and modes (Windows): not checked
    if info.st_uid != os.geteuid():
        return f"is owned by user id {info.st_uid}, not by this user ({os.geteuid()})"
    loose = stat.S_IRWXG | stat.S_IRWXO if secret else stat.S_IWGRP | stat.S_IWOTH
    if info.st_mode & loose:
        who = "read or written" if secret else "written"
        return (f"may be {who} by other users (mode {stat.S_IMODE(info.st_mode):o}; "
                f"expected {'600' if secret else '700'})")
    return ""


def _refuse(directory: Path, problem: str) -> None:
    _warn(directory, f"{problem}; compiled code is not cached on disk for this run "
          "(fix it, e.g. chmod 700, or set MECHDYN_CACHE to a private directory)")
    return None


def _warn(directory: Path, message: str):
    if (str(directory), message) in _warned:
        return
    _warned.add((str(directory), message))
    warnings.warn(f"mechdyn cache {directory}: {message}", CacheWarning, stacklevel=2)


def _reason(error: OSError) -> str:
    if error.errno == errno.ENOSPC:
        return "the disk is full"
    if error.errno in (errno.EROFS, errno.EACCES, errno.EPERM):
        return "it is read-only"
    return error.strerror or str(error)


def _temporary(path: Path) -> Path:
    return path.with_name(f".{path.name}.{os.getpid()}.{secrets.token_hex(4)}.tmp")


def _write_new(path: Path, data: bytes):
    """Write a new private (0600) file, refusing to follow or reuse anything there."""
    flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_NOFOLLOW", 0)
    fd = os.open(path, flags, 0o600)
    try:
        view = memoryview(data)
        while view:
            view = view[os.write(fd, view):]
    finally:
        os.close(fd)


def _write_atomically(path: Path, data: bytes):
    """Write ``data`` to ``path`` through a temporary file renamed into place: readers
    see the old entry or the new one, never half of one (a directory in the entry's
    place is discarded first)."""
    temporary = _temporary(path)
    try:
        _write_new(temporary, data)
        try:
            os.replace(temporary, path)
        except (IsADirectoryError, FileExistsError, OSError) as error:
            if error.errno not in (errno.EISDIR, errno.ENOTEMPTY, errno.EEXIST):
                raise
            _discard(path)
            os.replace(temporary, path)
    finally:
        temporary.unlink(missing_ok=True)


def _discard(path: Path):
    """Remove whatever stands in an entry's or the key's place inside the private
    directory (a file, link, FIFO or folder), so it is rebuilt."""
    try:
        if stat.S_ISDIR(os.lstat(path).st_mode):
            shutil.rmtree(path, ignore_errors=True)
        else:
            path.unlink()
    except OSError:
        pass

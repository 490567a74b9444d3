"""Files written whole or not at all: every file mechdyn writes (CSV, figures, HTML
reports, animations, sweep records) goes to a temporary file in the same folder and is
renamed into place only when complete, so a full disk or a crash mid-write leaves the
old file as it was and no partial file; the error names the file.

>>> import pathlib, tempfile
>>> path = pathlib.Path(tempfile.mkdtemp()) / "out.txt"
>>> with replacing(path) as handle:
...     _ = handle.write("complete")
>>> path.read_text()
'complete'
"""
from __future__ import annotations

import os
import secrets
from contextlib import contextmanager
from pathlib import Path

from mechdyn.errors import OutputError

__all__ = ["replacing", "write_text", "write_bytes", "OutputError"]


@contextmanager
def replacing(path, mode="w", **options):
    """A handle on a temporary file beside ``path`` (``open``'s ``mode`` and options),
    renamed to ``path`` when the block ends without an error; on any error the temporary
    file is removed, ``path`` is left untouched and an :class:`OutputError` naming it is
    raised (errors that are not about the file pass through unchanged)."""
    path = Path(path)
    temporary = path.with_name(f".{path.name}.{os.getpid()}.{secrets.token_hex(4)}.tmp")
    try:
        with open(temporary, mode, **options) as handle:
            yield handle
            handle.flush()
            os.fsync(handle.fileno())
        _keep_mode(path, temporary)
        os.replace(temporary, path)
    except OSError as error:
        raise OutputError(f"cannot write {path}: {_reason(error)}; "
                          f"{'the old file is kept' if path.is_file() else 'nothing written'}"
                          ) from error
    finally:
        try:
            temporary.unlink()
        except OSError:
            pass


def write_text(path, text: str, encoding="utf-8"):
    """Write ``text`` to ``path`` atomically (see :func:`replacing`)."""
    with replacing(path, "w", encoding=encoding) as handle:
        handle.write(text)
    return path


def write_bytes(path, data: bytes):
    """Write ``data`` to ``path`` atomically (see :func:`replacing`)."""
    with replacing(path, "wb") as handle:
        handle.write(data)
    return path


def _keep_mode(path, temporary):
    """The new file keeps the old one's permissions (a new one has open's usual ones)."""
    try:
        os.chmod(temporary, os.stat(path).st_mode & 0o7777)
    except OSError:
        pass


def _reason(error: OSError) -> str:
    import errno
    if error.errno == errno.ENOSPC:
        return "the disk is full"
    return error.strerror or str(error) or type(error).__name__

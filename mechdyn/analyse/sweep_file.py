"""A sweep's results file: rows appended as they finish, locked, and recorded so a rerun
resumes only the sweep that wrote it.

``FILE.csv`` holds the rows (a plain CSV file: the swept parameters, then the result
columns). Beside it:

- ``FILE.csv.meta.json`` records what the rows were computed for: the mechdyn version,
  the mechanism's declaration key (a hash of its elements and the scene's effects,
  outputs and stop conditions), the scene's initial values, times, method and
  tolerances, and the fixed parameter values. A rerun whose record differs is refused
  with a message naming each difference (``fresh=True`` starts afresh instead).
- ``FILE.csv.lock`` is the lock (:mod:`filelock`, an OS lock released even when the
  process is killed): a second sweep on the same file stops at once with a clear
  message, or waits up to ``wait`` seconds.

>>> import tempfile, pathlib
>>> path = pathlib.Path(tempfile.mkdtemp()) / "demo.csv"
>>> with SweepFile(path, ["P", "t_end", "error"], ["P"], {"fixed": {"R": 0.1}}) as table:
...     table.add({"P": 10.0, "t_end": 100.0, "error": ""})
>>> with SweepFile(path, ["P", "t_end", "error"], ["P"], {"fixed": {"R": 0.1}}) as table:
...     list(table.rows)                         # resumed
[(10.0,)]
>>> SweepFile(path, ["P", "t_end", "error"], ["P"], {"fixed": {"R": 0.2}})
Traceback (most recent call last):
...
mechdyn.analyse.sweep_file.SweepFileError: ...: the fixed parameter R was 0.1, now 0.2. Rerun with fresh=True (--fresh) to discard its rows, or give another out file
"""
from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np

from mechdyn.atomic import replacing, write_text
from mechdyn.errors import MechdynError

MAX_POINTS = 1_000_000       # default bound on a sweep's grid size (max_points= raises it)

__all__ = ["SweepFile", "SweepError", "SweepFileError", "TEXT_COLUMNS"]

TEXT_COLUMNS = ("reason", "error")
_FORMAT = "mechdyn sweep 1"


class SweepError(MechdynError, ValueError):
    """A sweep that cannot run as asked (a grid above its size limit, no workers).

    Examples
    --------
    >>> import mechdyn as md
    >>> model = md.load_model("shoe_brake")
    >>> try:
    ...     md.sweep(model.mechanism, model.scenes["braking"], model.params,
    ...              {"P": range(1, 11)}, max_points=5, progress=False)
    ... except md.SweepError as error:
    ...     print(type(error).__name__)
    SweepError
    """


class SweepFileError(SweepError):
    """An ``out`` file that is in use, or holds another sweep's rows.

    Examples
    --------
    A file that was not written by a sweep is never overwritten:

    >>> import mechdyn as md
    >>> model = md.load_model("shoe_brake")
    >>> import os, tempfile
    >>> out = os.path.join(tempfile.mkdtemp(), "brake.csv")
    >>> with open(out, "w") as file:
    ...     _ = file.write("P,t_end\\n20,50\\n")
    >>> try:
    ...     md.sweep(model.mechanism, model.scenes["braking"], model.params, {"P": [20]},
    ...              out=out, progress=False)
    ... except md.SweepFileError as error:
    ...     print(type(error).__name__)
    SweepFileError
    """


class SweepFile:
    """Rows by grid point, appended to a CSV file as they arrive (resumed if present).

    Parameters: ``path`` (None: rows in memory only), ``columns``, ``names`` (the swept
    columns, which key the rows), ``record`` (what the rows depend on, compared on
    resume), ``fresh`` (discard an existing file's rows), ``wait`` (seconds to wait for
    another sweep's lock). Use it as a context manager: the lock is held inside.
    """

    def __init__(self, path, columns, names, record, fresh=False, wait=0.0):
        self.columns, self.names, self.rows = list(columns), list(names), {}
        self._handle = self._writer = self._lock = None
        if path is None:
            return
        self.path = Path(path)
        self._lock = _acquire(self.path, wait)
        try:
            self._open(dict(record, format=_FORMAT, columns=self.columns), fresh)
        except BaseException:
            self.close()
            raise

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def add(self, row, write=True):
        """Keep ``row`` (a dict by column) and append it to the file, flushed."""
        row = {c: _value(c, row.get(c, "")) for c in self.columns}
        self.rows[tuple(row[n] for n in self.names)] = row
        if write and self._writer is not None:
            self._writer.writerow([_text(v) for v in row.values()])
            self._handle.flush()

    def close(self):
        if self._handle is not None:
            self._handle.close()
            self._handle = None
        if self._lock is not None:
            self._lock.release()
            self._lock = None

    # ---------------------------------------------------------------- internals
    def _open(self, record, fresh):
        meta = self.path.with_name(self.path.name + ".meta.json")
        has_rows = self.path.is_file() and _holds_a_line(self.path)
        if has_rows and not fresh:
            self._check_header()
            _compare(self.path, meta, record)
            self._resume()
            self._handle = open(self.path, "a", newline="")
            self._writer = csv.writer(self._handle)
            return
        _write_json(meta, record)                   # the record first, then the rows
        with replacing(self.path, "w", newline="") as handle:     # the header, whole
            csv.writer(handle).writerow(self.columns)
        self._handle = open(self.path, "a", newline="")
        self._writer = csv.writer(self._handle)

    def _check_header(self):
        with open(self.path, newline="") as handle:
            header = next(csv.reader(handle), [])
        if header != self.columns:
            raise SweepFileError(f"{self.path} holds another sweep (columns "
                                 f"{', '.join(header) or 'none'}); expected "
                                 f"{', '.join(self.columns)}: give a new out file or "
                                 "fresh=True (--fresh)")

    def _resume(self):
        text = self.path.read_text()
        if not text.endswith("\n"):              # a row cut off by a crash
            text = text[:text.rfind("\n") + 1]
            write_text(self.path, text)
        for values in list(csv.reader(text.splitlines()))[1:]:
            if len(values) == len(self.columns):
                self.add(dict(zip(self.columns, values)), write=False)


def _holds_a_line(path: Path) -> bool:
    """Whether the file holds one whole line (a header cut off by a crash is not)."""
    with open(path, "rb") as handle:
        return b"\n" in handle.read(1 << 16)


def _acquire(path: Path, wait: float):
    """The sweep's lock on ``path``, or a SweepFileError if another sweep holds it."""
    from filelock import FileLock, Timeout
    lock = FileLock(str(path) + ".lock", timeout=max(float(wait), 0.0))
    try:
        lock.acquire()
    except Timeout:
        waited = f" for {wait:g} s" if wait else ""
        raise SweepFileError(f"{path} is in use by another sweep (its lock {lock.lock_file} "
                             f"is held; waited{waited or ' not at all'}): let it finish, "
                             "give wait= (--wait SECONDS), or another out file") from None
    return lock


def _compare(path: Path, meta: Path, record: dict):
    """Refuse to resume rows computed for something else, naming every difference."""
    try:
        found = json.loads(meta.read_text())
    except FileNotFoundError:
        raise SweepFileError(f"{path} has no record of the sweep that wrote it ({meta.name} "
                             "is missing), so its rows cannot be trusted for this one. Rerun "
                             "with fresh=True (--fresh) to discard them, or give another out "
                             "file") from None
    except (OSError, ValueError) as error:
        raise SweepFileError(f"{meta} cannot be read ({error}). Rerun with fresh=True "
                             "(--fresh) to discard the rows, or give another out file") \
            from None
    differences = _differences(found if isinstance(found, dict) else {}, record)
    if differences:
        raise SweepFileError(f"{path} holds rows of another sweep: {'; '.join(differences)}. "
                             "Rerun with fresh=True (--fresh) to discard its rows, or give "
                             "another out file")


_WORDS = {"mechdyn": "the mechdyn version", "declaration": "the mechanism's declaration "
          "(elements, effects, outputs or stop conditions)", "mechanism": "the mechanism",
          "swept": "the swept parameters", "format": "the file format",
          "columns": "the columns"}


def _differences(found: dict, wanted: dict) -> list:
    out = []
    for key, value in wanted.items():
        old = found.get(key)
        if key in ("fixed", "scene") and isinstance(value, dict):
            old = old if isinstance(old, dict) else {}
            what = "the fixed parameter" if key == "fixed" else "the scene's"
            for name in sorted(set(value) | set(old)):
                if old.get(name) != value.get(name):
                    out.append(f"{what} {name} was {_said(old.get(name))}, now "
                               f"{_said(value.get(name))}")
        elif old != value:
            out.append(f"{_WORDS.get(key, key)} was {_said(old)}, now {_said(value)}")
    return out


def _said(value) -> str:
    if value is None:
        return "not given"
    if isinstance(value, list):
        return ", ".join(map(str, value)) or "none"
    return str(value)


def _write_json(path: Path, value: dict):
    write_text(path, json.dumps(value, indent=1) + "\n")


def _text(value):
    if isinstance(value, float):
        return "" if np.isnan(value) else repr(value)
    return value


def _value(column, value):
    if column in TEXT_COLUMNS:
        return str(value)
    return float(value) if value != "" else float("nan")

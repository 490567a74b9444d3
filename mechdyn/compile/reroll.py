"""Loops back into long straight-line generated code, so numba compiles a large model in
seconds: numba spends milliseconds on every statement it types and lowers, and a chain of
100 shafts has thousands of statements that differ only in their indices.

:func:`rerolled` rewrites a generated function (:func:`mechdyn.compile.codegen.function_source`)
with its temporaries in one work array ``_r`` and the state and parameters read from
``y`` and ``p`` in place. Statements are then levelled by their dependencies (a statement
comes after those that write what it reads or writes) and those of one level with the
same text up to the integers of their subscripts become one loop over a table of those
integers (a module-level constant ``int64`` array). Every statement computes the same
expression as before, so the results are the same to the last bit; only the order of
independent statements changes. Lines that are not plain assignments (loops, calls, the
allocation of work arrays) are fences: nothing moves across them.

>>> source = chr(10).join(["def f(t, y, p, out):", "    q0 = y[0]", "    q1 = y[1]",
...     "    q2 = y[2]", "    p0 = p[0]", "    _c0 = p0*q0", "    _c1 = p0*q1",
...     "    _c2 = p0*q2", "    out[0] = _c0", "    out[1] = _c1", "    out[2] = _c2"])
>>> text, tables = rerolled(source, "f", minimum=2)
>>> print(text, end="")
def f(t, y, p, out):
    _r = np.empty(3)
    for _k in range(3):
        _r[_f0[_k, 0]] = p[_f0[_k, 1]]*y[_f0[_k, 2]]
    for _k in range(3):
        out[_f1[_k, 0]] = _r[_f1[_k, 1]]
>>> tables["_f0"].tolist()
[[0, 0, 0], [1, 0, 1], [2, 0, 2]]
"""
from __future__ import annotations

import re

import numpy as np

__all__ = ["rerolled", "tables_text"]

_READ = re.compile(r"^    ([A-Za-z_]\w*) = ([yp])\[(\d+)\]$")
_ASSIGN = re.compile(r"^    ((?:_[ce]\d+)|(?:[A-Za-z_]\w*\[\d+(?:, \d+)?\])) (=|-=|\+=) (.+)$")
_NAME = re.compile(r"\b[A-Za-z_]\w*\b")
_SUBSCRIPT = re.compile(r"\b([A-Za-z_]\w*)\[(\d+)(?:, (\d+))?\]")


def rerolled(source: str, prefix: str, minimum: int = 4) -> tuple:
    """``(text, tables)``: ``source`` (one generated function) with loops over tables
    named ``_{prefix}0, _{prefix}1, ...`` where at least ``minimum`` statements share a
    form; ``tables`` maps those names to their ``int64`` arrays."""
    lines = source.rstrip("\n").split("\n")
    head = [lines[0]] + [line for line in lines[1:2] if line.lstrip().startswith('"""')]
    names, slots, segments, current = {}, {}, [], []
    for line in lines[len(head):]:
        read = _READ.match(line)
        if read:
            names[read.group(1)] = f"{read.group(2)}[{read.group(3)}]"
            continue
        assign = _ASSIGN.match(line)
        if assign and assign.group(1).startswith("_") and assign.group(1)[1] in "ce":
            slots[assign.group(1)] = f"_r[{len(slots)}]"
            names[assign.group(1)] = slots[assign.group(1)]
        line = _NAME.sub(lambda m: names.get(m.group(0), m.group(0)), line)
        if _ASSIGN.match(line):
            current.append(line)
        else:
            segments += [current, line]
            current = []
    segments.append(current)
    body, tables = [], {}
    for segment in segments:
        if isinstance(segment, str):
            body.append(segment)
            continue
        for group in _groups(segment):
            if len(group) < minimum:
                body += group
                continue
            name = f"_{prefix}{len(tables)}"
            template, rows = _table(group, name)
            tables[name] = np.array(rows, dtype=np.int64)
            body += [f"    for _k in range({len(rows)}):", "    " + template]
    allocation = [f"    _r = np.empty({len(slots)})"] if slots else []
    return "\n".join(head + allocation + body) + "\n", tables


def tables_text(tables) -> str:
    """Module-level definitions of the tables of :func:`rerolled`."""
    return "".join(f"{name} = np.array({table.tolist()}, dtype=np.int64)"
                   f".reshape({table.shape})\n" for name, table in tables.items())


def _groups(statements) -> list:
    """The statements by dependency level, then by form, each group in source order."""
    written, read, keyed = {}, {}, {}
    for line in statements:
        target, operator, expression = _ASSIGN.match(line).groups()
        sources = [m.group(0) for m in _SUBSCRIPT.finditer(expression)]
        level = 1 + max([written.get(key, 0) for key in sources + [target]]
                        + [read.get(target, 0) - 1], default=0)
        written[target] = level
        for key in sources:
            read[key] = max(read.get(key, 0), level + 1)
        keyed.setdefault((level, _SUBSCRIPT.sub(r"\1[]", line)), []).append(line)
    return [group for _, group in sorted(keyed.items(), key=lambda item: item[0][0])]


def _table(group, name) -> tuple:
    """The loop body reading its subscripts from the table ``name``, and the rows."""
    rows, template = [], None
    for line in group:
        numbers, column = [], iter(range(10 ** 6))

        def indexed(match):
            numbers.extend(int(g) for g in match.groups()[1:] if g is not None)
            inner = ", ".join(f"{name}[_k, {next(column)}]"
                              for g in match.groups()[1:] if g is not None)
            return f"{match.group(1)}[{inner}]"
        text = _SUBSCRIPT.sub(indexed, line)
        template = template or text
        rows.append(numbers)
    return template, rows

"""One table model for every view: plain text, HTML, LaTeX and Jupyter render the same
:class:`Table` (a header, rows of cells, an optional caption).

>>> table = Table(["quantity", "final", "unit"], [["phi", 1.5, "rad"], ["omega", 12.25, "rad/s"]])
>>> print(table.text())
quantity  final  unit
phi         1.5  rad
omega     12.25  rad/s
>>> table.latex().splitlines()[0]
'\\\\begin{tabular}{lrl}'
>>> print(Table(["method", "error"], [["RK45", 3.2e-05], ["Radau", None]],
...             formats=(None, ".1e")))
method  error
RK45    3.2e-05
Radau         -
"""
from __future__ import annotations

import html
from dataclasses import dataclass, field

__all__ = ["Table", "JUPYTER_STYLE", "escape"]

# Jupyter right-aligns table cells; text columns of mechdyn's views read left-aligned.
JUPYTER_STYLE = ("<style>.mechdyn table td, .mechdyn table th { text-align: left; "
                 "vertical-align: top; } .mechdyn table td.num { text-align: right; }"
                 "</style>")


def escape(text) -> str:
    """Text made safe for HTML (quotes too)."""
    return html.escape(str(text), quote=True)


def _cell(value, spec=None) -> str:
    if value is None:
        return "-"
    if spec and _is_number(value):
        return format(value, spec)
    if isinstance(value, float):
        return f"{value:.6g}"
    return str(value)


def _is_number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


@dataclass(frozen=True)
class Table:
    """Rows of cells under a header; numbers are shown with six significant digits (or
    the column's format spec in ``formats``, e.g. ``".1e"``) and aligned right, text
    left; ``None`` is a missing value, shown as ``-``."""
    header: list
    rows: list = field(default_factory=list)
    caption: str = ""
    formats: tuple = ()

    def _numeric(self) -> list:
        return [any(_is_number(row[j]) for row in self.rows) and
                all(_is_number(row[j]) or row[j] is None for row in self.rows)
                for j in range(len(self.header))]

    def _cells(self, row) -> list:
        specs = list(self.formats) + [None] * (len(row) - len(self.formats))
        return [_cell(value, spec) for value, spec in zip(row, specs)]

    def text(self) -> str:
        """Columns padded to their widest cell, two spaces apart."""
        cells = [list(map(str, self.header))] + [self._cells(row) for row in self.rows]
        widths = [max(len(row[j]) for row in cells) for j in range(len(self.header))]
        numeric = self._numeric()
        lines = ["  ".join(c.rjust(w) if numeric[j] and i else c.ljust(w)
                           for j, (c, w) in enumerate(zip(row, widths))).rstrip()
                 for i, row in enumerate(cells)]
        return "\n".join(([self.caption] if self.caption else []) + lines)

    def html(self) -> str:
        """A ``<table>``; numeric cells carry ``class='num'``."""
        head = "".join(f"<th>{escape(h)}</th>" for h in self.header)
        body = "".join(
            "<tr>" + "".join(f"<td class='num'>{escape(c)}</td>" if _is_number(v)
                             else f"<td>{escape(c)}</td>"
                             for v, c in zip(row, self._cells(row))) + "</tr>"
            for row in self.rows)
        caption = f"<caption>{escape(self.caption)}</caption>" if self.caption else ""
        return f"<table>{caption}<tr>{head}</tr>{body}</table>"

    def latex(self) -> str:
        """A ``tabular`` (cells as given: LaTeX in them is kept)."""
        spec = "".join("r" if n else "l" for n in self._numeric())
        rows = [" & ".join(map(str, self.header))] + \
            [" & ".join(self._cells(row)) for row in self.rows]
        return "\n".join([f"\\begin{{tabular}}{{{spec}}}", " \\\\\n".join(rows) + " \\\\",
                          "\\end{tabular}"])

    def _repr_html_(self) -> str:
        return f"<div class='mechdyn'>{JUPYTER_STYLE}{self.html()}</div>"

    def __str__(self) -> str:
        return self.text()

"""One table model for every view: plain text, HTML, LaTeX and Jupyter render the same
:class:`Table` (a header, rows of cells, an optional caption).

>>> table = Table(["quantity", "final", "unit"], [["phi", 1.5, "rad"], ["omega", 12.25, "rad/s"]])
>>> print(table.text())
quantity  final  unit
phi         1.5  rad
omega     12.25  rad/s
>>> table.latex().splitlines()[0]
'\\\\begin{tabular}{lrl}'
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


def _cell(value) -> str:
    if isinstance(value, float):
        return f"{value:.6g}"
    return str(value)


def _is_number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


@dataclass(frozen=True)
class Table:
    """Rows of cells under a header; numbers are shown with six significant digits and
    aligned right, text left."""
    header: list
    rows: list = field(default_factory=list)
    caption: str = ""

    def _numeric(self) -> list:
        return [bool(self.rows) and all(_is_number(row[j]) for row in self.rows)
                for j in range(len(self.header))]

    def text(self) -> str:
        """Columns padded to their widest cell, two spaces apart."""
        cells = [list(map(str, self.header))] + [[_cell(v) for v in row] for row in self.rows]
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
            "<tr>" + "".join(f"<td class='num'>{escape(_cell(v))}</td>" if _is_number(v)
                             else f"<td>{escape(v)}</td>" for v in row) + "</tr>"
            for row in self.rows)
        caption = f"<caption>{escape(self.caption)}</caption>" if self.caption else ""
        return f"<table>{caption}<tr>{head}</tr>{body}</table>"

    def latex(self) -> str:
        """A ``tabular`` (cells as given: LaTeX in them is kept)."""
        spec = "".join("r" if n else "l" for n in self._numeric())
        rows = [" & ".join(map(str, self.header))] + \
            [" & ".join(_cell(v) for v in row) for row in self.rows]
        return "\n".join([f"\\begin{{tabular}}{{{spec}}}", " \\\\\n".join(rows) + " \\\\",
                          "\\end{tabular}"])

    def _repr_html_(self) -> str:
        return f"<div class='mechdyn'>{JUPYTER_STYLE}{self.html()}</div>"

    def __str__(self) -> str:
        return self.text()

"""HTML views: the one-page derivation report, and the rich displays of Jupyter.

:func:`report` writes a self-contained page that needs no network: the derivation as
MathML (converted from LaTeX by latex2mathml; browsers lay MathML out natively), the
mechanism's elements and parameters, the scene, the results summary with its events and
units, the default figure as an embedded PNG and, on request, the work-precision table
of :mod:`mechdyn.analyse.precision`.

>>> import mechdyn as md
>>> model = md.load_model("models/shoe_brake.py")
>>> page = report(model.mechanism, model.scenes["braking"], model.params)
>>> page.failure, "<h2>Derivation</h2>" in page.html
('', True)
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp
from sympy.core.function import AppliedUndef

from mechdyn.declare.elements import is_structural
from mechdyn.errors import SimulationError
from mechdyn.derive.equations import printed_equations
from mechdyn.derive.latex import derivation_latex, derivation_steps, rhs_latex
from mechdyn.symbols import plain
from mechdyn.plotting import figure_html
from mechdyn.tabular import JUPYTER_STYLE, escape

__all__ = ["report", "Report", "mechanism_html"]

_STYLE = """
body { font-family: system-ui, sans-serif; max-width: 1100px; margin: 2em auto;
       padding: 0 1em; color: #222; line-height: 1.4; }
h1 { border-bottom: 2px solid #345; padding-bottom: .2em; }
h2 { color: #345; margin-top: 1.6em; }
table { border-collapse: collapse; margin: .5em 0; }
th, td { border: 1px solid #ccc; padding: .25em .6em; text-align: left;
         vertical-align: top; }
th { background: #eef2f5; }
td.num { text-align: right; font-variant-numeric: tabular-nums; }
td.math { overflow-x: auto; max-width: 850px; }
pre { background: #f6f8fa; padding: .8em; overflow-x: auto; }
img { max-width: 100%; }
.failed { color: #a00; font-weight: bold; }
.note { color: #555; font-size: .9em; }
math[display=block] { margin: .2em 0; }
"""


@dataclass(frozen=True)
class Report:
    """A report page: ``html``, the ``result`` (partial if the run failed, None if
    nothing was integrated) and the ``failure`` message (empty when the run succeeded)."""
    html: str
    result: object
    failure: str

    def write(self, path):
        """Save the page (UTF-8) and return the path."""
        from mechdyn.atomic import write_text
        write_text(path, self.html)
        return path


def report(mechanism, scene, params, precision=False) -> Report:
    """The derivation, scene, results and figures of one scene as one HTML page.

    Parameters
    ----------
    mechanism : Mechanism
    scene : Scene
    params : dict
        Parameter values (symbols or names).
    precision : bool
        Add the work-precision table and figure (runs each integrator at several
        tolerances: seconds to minutes).

    Returns
    -------
    Report
        A failed simulation does not raise: the page shows the failure and the partial
        result, and ``Report.failure`` holds the message.

    Examples
    --------
    >>> import mechdyn as md
    >>> model = md.load_model("models/shoe_brake.py")
    >>> page = report(model.mechanism, model.scenes["braking"], model.params)
    >>> page.html.count("data:image/png;base64,")       # the default figure
    1
    """
    from mechdyn.declare.parameters import ParameterSet
    params = ParameterSet(params, mechanism=mechanism, scene=scene)   # before deriving
    eqs = mechanism.equations(scene)
    failure = ""
    try:
        result = mechanism.simulate(scene, params)
    except SimulationError as error:
        result, failure = error.partial, str(error)
    sections = [
        _section("Derivation", _derivation(printed_equations(mechanism, scene))),
        _section("Mechanism", _elements(mechanism, eqs)
                 + _parameters(params, eqs, mechanism.parameter_units)),
        _section("Scene", _scene(scene)),
        _section("Results", _results(result, failure)),
    ]
    if precision:
        sections.append(_section("Accuracy", _precision(mechanism, scene, params)))
    title = f"{mechanism.name} — scene {scene.name}"
    return Report(_page(title, sections), result, failure)


# ------------------------------------------------------------------ Jupyter views
def mechanism_html(mechanism) -> str:
    """A mechanism as HTML: its elements and the derivation (MathML)."""
    eqs = mechanism.equations()
    return (f"<div class='mechdyn'>{JUPYTER_STYLE}<h3>{_e(mechanism.name)}</h3>"
            + _elements(mechanism, eqs)
            + _derivation(printed_equations(mechanism), source=False) + "</div>")


# --------------------------------------------------------------------- sections
def _page(title, sections) -> str:
    return (f"<!DOCTYPE html>\n<html lang='en'><head><meta charset='utf-8'>"
            f"<title>{_e(title)}</title><style>{_STYLE}</style></head><body>"
            f"<h1>{_e(title)}</h1><p class='note'>Made by mechdyn. The page is self-contained "
            f"(formulas in MathML, figures embedded): it needs no network.</p>"
            + "".join(sections) + "</body></html>\n")


def _section(heading, body) -> str:
    return f"<section><h2>{_e(heading)}</h2>{body}</section>"


def _derivation(eqs, source=True) -> str:
    intro = (f"<p>Coordinates {_math(', '.join(sp.latex(q) for q in eqs.q))}"
             + (f"; left out in this scene: {_e(', '.join(eqs.excluded))}"
                if eqs.excluded else "") + ".</p>")
    rows = []
    for label, lhs, _, rhs in derivation_steps(eqs):
        right = rhs_latex(rhs)
        rows.append(f"<tr><td>{_e(label)}</td><td class='math'>"
                    f"{_display(lhs + ' = ' + right)}</td></tr>")
    table = "<table><tr><th>step</th><th>expression</th></tr>" + "".join(rows) + "</table>"
    if not source:
        return intro + table
    return (intro + table + "<details><summary>LaTeX source of the derivation</summary>"
            f"<pre>{_e(derivation_latex(eqs))}</pre></details>")


def _elements(mechanism, eqs) -> str:
    rows = []
    for name, element in mechanism.elements.items():
        kind = type(element).__name__.lower()
        used = ("always" if is_structural(element)       # links, loops, joints
                else "yes" if name in eqs.elements else "no")
        values = ",\\quad ".join(f"\\mathrm{{{key}}} = {sp.latex(_plain(value))}"
                           for key, value in element.expressions().items() if value != 0)
        tags = ", ".join(element.tags)
        rows.append(f"<tr><td>{_e(name)}</td><td>{kind}</td><td>{_e(tags)}</td>"
                    f"<td>{_e(used)}</td><td>{_math(values)}</td></tr>")
    return ("<table><tr><th>element</th><th>kind</th><th>tags</th><th>in scene</th>"
            "<th>declaration</th></tr>" + "".join(rows) + "</table>")


def _parameters(params, eqs, units) -> str:
    """The table of the values (SI) of the parameters the equations use."""
    needed = {str(s) for s in eqs.parameters}
    rows = [f"<tr><td>{_math(sp.latex(sp.Symbol(str(k))))}</td>"
            f"<td class='num'>{_e(_number(v))}</td><td>{_e(units.get(str(k), ''))}</td></tr>"
            for k, v in params.items() if str(k) in needed]
    return ("<h3>Parameters</h3><table><tr><th>parameter</th><th>value</th><th>unit</th>"
            "</tr>" + "".join(rows) + "</table>")


def _scene(scene) -> str:
    facts = [("effects", "all elements" if scene.effects is None else ", ".join(scene.effects)),
             ("rigid springs", ", ".join(name for name, _ in scene.rigid) or "none"),
             ("stop when", " or ".join(repr(c) for c in scene.until) or "—"),
             ("time limit", f"{scene.time_limit:g} s"),
             ("outputs", ", ".join(label for label, _ in scene.labelled_outputs()) or "none"),
             ("integration", f"{scene.method}, rtol {scene.rtol:g}, atol {scene.atol}")]
    rows = "".join(f"<tr><th>{_e(k)}</th><td>{_e(v)}</td></tr>" for k, v in facts)
    initial = "".join(f"<tr><td>{_math(sp.latex(_plain(key)))}</td>"
                      f"<td class='math'>{_math(sp.latex(_plain(sp.sympify(value))))}</td></tr>"
                      for key, value in scene.initial.items())
    return (f"<table>{rows}</table><h3>Initial state</h3><table><tr><th>state</th>"
            f"<th>value</th></tr>{initial}</table>")


def _results(result, failure) -> str:
    parts = [f"<p class='failed'>{_e(failure)}</p>"] if failure else []
    return "".join(parts) + (result.html() if result is not None else "")


def _precision(mechanism, scene, params) -> str:
    try:
        from mechdyn.analyse.precision import work_precision
    except ImportError:
        return "<p class='note'>mechdyn.analyse.precision is not available in this version.</p>"
    table = work_precision(mechanism, scene, params, repeats=1)
    return ("<p>Errors are relative to each state's largest magnitude; event errors "
            "relative to the run's duration; times exclude compilation.</p>"
            + table.table().html() + figure_html(table.plot(), "work-precision diagram"))


# ----------------------------------------------------------------------- pieces
def _plain(expr):
    """Coordinates and their derivatives written as the plain symbols (phi, phidot)."""
    expr = expr.xreplace({d: plain(d) for d in expr.atoms(sp.Derivative)})
    return expr.xreplace({f: plain(f) for f in expr.atoms(AppliedUndef)})


def _number(value) -> str:
    try:
        return f"{float(value):.6g}"
    except (TypeError, ValueError):
        return str(value)


def _math(latex, display="inline") -> str:
    """LaTeX as MathML (latex2mathml); the source in <code> if it is not installed."""
    if not latex:
        return ""
    try:
        from latex2mathml.converter import convert
    except ImportError:
        return f"<code>{_e(latex)}</code>"
    return convert(latex.replace("\\mathrm{", "\\text{"), display=display)  # words


def _display(latex) -> str:
    return _math(latex, display="block")


_e = escape

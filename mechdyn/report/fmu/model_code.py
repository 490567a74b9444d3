"""The model-specific C of an FMU: a scene's equations ``M(q) q'' = f`` as the functions
the FMI glue (``fmi2_glue.c``) calls.

The expressions are the ones the compiled backend generates
(:mod:`mechdyn.compile.generate`): the derived mass matrix and smooth forcing, the
scene's outputs (:func:`mechdyn.compile.output_code.outputs`), the kinetic and
potential energy, the stop conditions, and every ``Piecewise``, ``Min``, ``Max``,
``Abs``, ``sign`` or ``Heaviside`` of the state locked by a flag
(:class:`mechdyn.compile.generate.Switches`) whose switching function is an event
indicator. The C functions:

- ``md_system``: the lower triangle of ``M`` (row by row) and ``f``; the glue solves
  ``M a = f`` by a dense Cholesky factorisation;
- ``md_outputs``: the scene's outputs, then ``T``, ``V``;
- ``md_indicators``: the stop conditions (``expression - value``), then the switching
  functions.
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from mechdyn.compile.codegen import safe_symbols
from mechdyn.compile.generate import Switches
from mechdyn.compile.output_code import outputs as scene_outputs
from mechdyn.report.fmu.c_code import c_function
from mechdyn.symbols import t

__all__ = ["ModelCode", "model_code"]


@dataclass
class ModelCode:
    """What the FMU computes: ``coordinates`` (names), ``parameters`` (symbols, sorted
    by name: the layout of ``p``), ``outputs`` (``(label, item)``), ``stops``
    (``(label, direction)``), ``switches`` (their count) and ``source`` (C)."""
    coordinates: list
    parameters: list
    outputs: list
    stops: list
    switches: int
    source: str

    @property
    def dof(self) -> int:
        return len(self.coordinates)


def model_code(eqs, selected) -> ModelCode:
    """The C of a scene's equations ``eqs`` (``selected``: the scene's
    :class:`~mechdyn.derive.selection.Selection`, its outputs and stop conditions)."""
    n = eqs.dof
    outputs = scene_outputs(eqs, selected)
    stops = [(repr(c), c.direction, eqs.to_plain(c.expression - c.value))
             for c in selected.until]
    switches = Switches(set(eqs.q) | set(eqs.u) | {t})
    mass = switches.lock(eqs.mass_matrix)
    forcing = switches.lock(eqs.smooth_forcing)
    output_exprs = [switches.lock(e) for _, e, _ in outputs]
    output_exprs += [switches.lock(eqs.kinetic_energy), switches.lock(eqs.potential_energy)]
    stop_exprs = [switches.lock(e) for _, _, e in stops]
    indicators = stop_exprs + list(switches.functions)
    everything = [mass, forcing, *output_exprs, *indicators]
    known = set(eqs.q) | set(eqs.u) | {t} | set(switches.flags)
    params = sorted(set().union(*(sp.sympify(e).free_symbols for e in everything)) - known,
                    key=lambda s: s.name)
    q_names, u_names = safe_symbols("q", n), safe_symbols("u", n)
    p_names = safe_symbols("p", len(params))
    rename = dict(zip(eqs.q, q_names)) | dict(zip(eqs.u, u_names)) | dict(zip(params, p_names))
    rename |= dict(zip(switches.flags, safe_symbols("w", len(switches.flags))))
    rename[t] = sp.Symbol("t", real=True)

    def r(expr):
        return sp.sympify(expr).xreplace(rename)
    states = {f"q{i}": f"x[{i}]" for i in range(n)} | {f"u{i}": f"x[{n + i}]" for i in range(n)}
    locals_ = {f"p{j}": f"p[{j}]" for j in range(len(params))}
    locals_ |= {f"w{k}": f"w[{k}]" for k in range(len(switches.flags))}
    lower = [(i, j) for i in range(n) for j in range(i + 1)]
    system = [r(mass[i, j]) for i, j in lower] + [r(f) for f in forcing]
    system_what = [f"mass matrix M[{i}][{j}]" for i, j in lower] + \
        [f"forcing f[{i}]" for i in range(n)]
    output_what = [f"output {label!r}" for label, _, _ in outputs] + \
        ["kinetic energy", "potential energy"]
    stop_what = [f"stop condition {label!r}" for label, _, _ in stops]
    legend = ["/* x = [" + ", ".join(map(str, (*eqs.q, *eqs.u))) + "]",
              "   p = [" + ", ".join(s.name for s in params) + "]"]
    legend += [f"   w[{k}]: the side of {f}" for k, f in enumerate(switches.functions)]
    source = "\n\n".join([
        "\n".join(legend).replace("*/", "* /") + " */",
        c_function("md_system", states, locals_, system, what=system_what),
        c_function("md_outputs", states, locals_, [r(e) for e in output_exprs],
                   what=output_what),
        c_function("md_indicators", states, locals_, [r(e) for e in indicators],
                   what=stop_what + [f"switching function {f}" for f in switches.functions])])
    return ModelCode(coordinates=[str(q) for q in eqs.q], parameters=params,
                     outputs=[(label, item) for label, _, item in outputs],
                     stops=[(label, direction) for label, direction, _ in stops],
                     switches=len(switches.functions), source=source)

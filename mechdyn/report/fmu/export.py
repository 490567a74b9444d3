"""A scene of a mechanism as an FMI 2.0 Model Exchange FMU (see the user guide's "A
mechanism as an FMU", docs/guide/fmu.md): the checks, the variables and the archive.

States are the coordinates and speeds, parameters the scene's parameters (with their
units and the given values as start values), inputs the parameters named in
``inputs`` (or the single-symbol value of a load named there), outputs the scene's
outputs and the kinetic, potential and total energy. Friction, one-way clutches, lossy
gears, stops and closed loops are refused with an :class:`FmuError` naming them.
"""
from __future__ import annotations

import hashlib
import re
import uuid
from pathlib import Path

import sympy as sp

from mechdyn.declare.dimensions import known_dimensions
from mechdyn.declare.elements import Constraint, Load
from mechdyn.declare.output_units import output_units
from mechdyn.declare.parameters import ParameterSet
from mechdyn.declare.scene import Scene
from mechdyn.derive.selection import select
from mechdyn.report.fmu.build import FmuError, build_fmu, find_compiler
from mechdyn.report.fmu.c_code import FmuExpressionError
from mechdyn.report.fmu.calculated import calculated_code, calculated_parameters
from mechdyn.report.fmu.description import Variable, model_description, unit_of
from mechdyn.report.fmu.model_code import model_code
from mechdyn.units import dimension
from mechdyn.version import __version__

__all__ = ["export_fmu"]

ENERGIES = ("kinetic_energy", "potential_energy", "energy")
RESERVED = ("time",)        # FMI's independent variable: FMPy's result column of the time


def export_fmu(mechanism, scene, params, path, inputs=(), start=None) -> Path:
    """Write ``scene`` of ``mechanism`` as the FMU ``path`` (``.fmu``) with parameter
    values ``params``; ``inputs``: names of parameters (or of loads whose value is one
    parameter) the FMU reads from outside; ``start``: the state ``[q..., u...]`` to start
    from instead of the scene's initial values (a later phase of a duty cycle, as
    ``simulate(start=...)``). Returns the path."""
    path = _checked_path(path)
    if not isinstance(scene, Scene):
        raise FmuError(f"export_fmu() needs a md.Scene, got {scene!r}")
    values = ParameterSet(params, mechanism=mechanism, scene=scene)   # before any work
    find_compiler()                                  # say so before deriving anything
    eqs = mechanism.equations(scene)
    _refuse_switching_elements(eqs, scene, mechanism.elements)
    try:
        code = model_code(eqs, select(mechanism, scene))
    except FmuExpressionError as error:
        raise FmuError(f"scene {scene.name!r}: {error}") from None
    names, dependent = calculated_parameters(values.dependent(),
                                             [s.name for s in code.parameters])
    p = values.vector(names)
    marked = _inputs(inputs, names, mechanism, scene, dependent)
    y0 = _initial_state(mechanism, scene, values, start)
    variables, units = _variables(mechanism, scene, eqs, code, (names, p, dependent),
                                  marked, y0)
    calculated, where = calculated_code(names, dependent)
    guid = _guid(code.source + calculated, variables)
    source = _model_source(code, p, y0, scene, guid, (calculated, where))
    identifier = _identifier(f"{mechanism.name}_{scene.name}")
    description = model_description(
        name=f"{mechanism.name} ({scene.name})", identifier=identifier, guid=guid,
        description=f"mechdyn: mechanism {mechanism.name!r}, scene {scene.name!r}",
        variables=variables, units=units, n_indicators=len(code.stops) + code.switches,
        experiment=(scene.t_start, scene.time_limit, scene.rtol), tool=f"mechdyn {__version__}")
    return build_fmu(path, identifier, source, description)


def _checked_path(path) -> Path:
    path = Path(path)
    if path.suffix.lower() != ".fmu":
        raise FmuError(f"{path}: an FMU's file name ends in .fmu")
    if path.is_dir():
        raise FmuError(f"{path}: is a folder; give a file name")
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.is_dir():
        raise FmuError(f"{path}: no folder {folder}")
    return path


def _refuse_switching_elements(eqs, scene, elements):
    """Elements whose modes switch at run time (mechdyn's driver decides them) have no
    FMU form yet: a named refusal."""
    refused = []
    for friction in eqs.frictions:
        what = {"one_way": "one-way clutch", "gear": "lossy gear"}.get(friction.kind,
                                                                       "friction")
        refused.append(f"{what} {friction.name!r} (stick/slip modes)")
    for stop in dict.fromkeys(c.element for c in eqs.contacts):
        refused.append(f"stop {stop!r} (impacts and resting contact)")
    meshes = {g.constraint for g in eqs.gears}          # a lossy gear's own constraint
    loops = dict.fromkeys(name for i, c in enumerate(eqs.constraints) if i not in meshes
                          for name, e in elements.items()
                          if isinstance(e, Constraint) and c.name in e.labels)
    refused += [f"closed loop {name!r} (a constrained system)" for name in loops]
    if refused:
        raise FmuError(f"scene {scene.name!r} cannot be exported as an FMU yet: "
                       f"{'; '.join(refused)}. An FMU holds smooth equations M(q) q'' = f "
                       "with switch and stop events; leave these elements out of the "
                       "scene's effects to export the rest")


def _inputs(inputs, names, mechanism, scene, dependent) -> set:
    """Parameter names the FMU reads as inputs (a load's name stands for its value's
    one symbol); a calculated one (``dependent``) cannot be one."""
    marked = set()
    for item in [inputs] if isinstance(inputs, str) else list(inputs or ()):
        name = item.name if isinstance(item, sp.Symbol) else str(item)
        element = mechanism.elements.get(name)
        if isinstance(element, Load):
            if not isinstance(element.value, sp.Symbol):
                raise FmuError(f"input {name!r}: the load's value {element.value} is not a "
                               "single parameter; declare it with one (e.g. M_ctrl) and "
                               "name that symbol as the input")
            name = element.value.name
        if name not in names:
            raise FmuError(f"input {item!r}: not a parameter of scene {scene.name!r} "
                           f"(its parameters: {', '.join(names) or 'none'})")
        if name in dependent:
            raise FmuError(f"input {item!r}: parameter {name} is given as {dependent[name]}, "
                           "calculated from the others; give it a number to read it as "
                           "an input")
        marked.add(name)
    return marked


def _initial_state(mechanism, scene, values, start) -> list:
    """The start values of the states: the scene's initial values, or ``start``."""
    import numpy as np
    from mechdyn.simulate.simulation import initial_state
    compiled = mechanism.compile(scene)
    if start is None:
        if not scene.initial:
            raise FmuError(f"scene {scene.name!r} has no initial values (a later phase of a "
                           "duty cycle): give the state to start from, export_fmu(..., "
                           f"start=[{', '.join(compiled.state_names)}])")
        return [float(v) for v in initial_state(compiled, mechanism, scene, values.numbers)]
    y0 = np.array(start, dtype=float)
    if y0.shape != (2 * compiled.dof,) or not np.all(np.isfinite(y0)):
        raise FmuError(f"scene {scene.name!r}: start must hold {2 * compiled.dof} finite "
                       f"values ({', '.join(compiled.state_names)}), got {list(start)!r}")
    return [float(v) for v in y0]


def _variables(mechanism, scene, eqs, code, parameter_values, marked, y0) -> tuple:
    """The variables in value-reference order and the units they use;
    ``parameter_values``: the parameters' names, values and calculated ones."""
    units = {}

    def unit(text):
        found = unit_of(text) if text else None
        if found is None:
            return ""
        units[found[0]] = found[1]
        return found[0]
    known = known_dimensions(mechanism)
    n = code.dof
    texts = [_coordinate_units(mechanism, known, name, eqs.q[i])
             for i, name in enumerate(code.coordinates)]
    states = [Variable(name, "state", f"coordinate {name}", unit(texts[i][0]), y0[i])
              for i, name in enumerate(code.coordinates)]
    states += [Variable(str(eqs.u[i]), "state", f"speed of {name}", unit(texts[i][1]),
                        y0[n + i]) for i, name in enumerate(code.coordinates)]
    derivatives = [Variable(f"der({v.name})", "derivative", f"time derivative of {v.name}",
                            unit(texts[i % n][1 + i // n]), derivative_of=i + 1)
                   for i, v in enumerate(states)]
    users = _parameter_users(mechanism, eqs)
    parameters = []
    names, p, dependent = parameter_values
    for name, value in zip(names, p):
        kind = "input" if name in marked else "calculated" if name in dependent else \
            "parameter"
        text = mechanism.parameter_units.get(name)
        si = known[sp.Symbol(name)].si if text else ""
        about = f"{name} = {dependent[name]}; " if name in dependent else ""
        parameters.append(Variable(name, kind, about + users.get(name, ""),
                                   unit(si if si != "1" else ""),
                                   None if name in dependent else value))
    out_units = output_units(mechanism, scene)
    outputs = [Variable(label, "output", f"scene output {item}" if item != label
                        else f"scene output", unit(out_units.get(label, "")))
               for label, item in code.outputs]
    outputs += [Variable(name, "output", name.replace("_", " "), unit("J")) for name in ENERGIES]
    variables = states + derivatives + parameters + outputs
    seen = {}
    for v in variables:
        if v.name in RESERVED or (v.name.startswith("der(") and v.kind != "derivative"):
            raise FmuError(f"scene {scene.name!r}: {v.kind} {v.name!r} takes a name FMI "
                           "tools reserve (the time, derivatives); rename it (outputs="
                           "{'new name': ...})")
        if v.name in seen:
            raise FmuError(f"scene {scene.name!r}: {v.kind} {v.name!r} has the name of a "
                           f"{seen[v.name]}; an FMU's variables need distinct names "
                           "(label the output: outputs={'new name': ...})")
        seen[v.name] = v.kind
    return variables, units


def _coordinate_units(mechanism, known, name, q) -> tuple:
    """SI texts of a coordinate, its speed and its acceleration (``rad`` for angles)."""
    dim = known[q]
    if dim.dimensionless and mechanism.units.get(name, "rad") != "1":    # an angle
        return "rad", "rad/s", "rad/s^2"
    return tuple("" if d.si == "1" else d.si
                 for d in (dim, dim / dimension("s"), dim / dimension("s^2")))


def _parameter_users(mechanism, eqs) -> dict:
    """Parameter name -> "used by link 'rotor', load 'motor'" (the scene's elements)."""
    users = {}
    for name, element in mechanism.elements.items():
        if name not in eqs.elements and type(element).__name__ != "Link":
            continue
        symbols = set().union(*(sp.sympify(e).free_symbols
                                for e in element.expressions().values() if e is not None))
        for s in symbols:
            users.setdefault(s.name, []).append(f"{type(element).__name__.lower()} {name!r}")
    return {k: "used by " + ", ".join(v) for k, v in users.items()}


def _guid(source: str, variables) -> str:
    text = source + "".join(f"{v.name}|{v.kind}|{v.start}" for v in variables)
    return "{" + str(uuid.UUID(hashlib.sha256(text.encode()).hexdigest()[:32])) + "}"


def _identifier(text: str) -> str:
    """A C identifier (the binary's name) from a model and scene name."""
    identifier = re.sub(r"\W+", "_", text, flags=re.ASCII).strip("_") or "mechdyn_model"
    return ("m_" + identifier) if identifier[0].isdigit() else identifier


def _model_source(code, p, y0, scene, guid, calculated) -> str:
    """model.c: sizes and start values, the model's functions (``calculated``: the C of
    ``md_calculated`` and the indices it writes), then the glue."""
    calculated_source, where = calculated

    def array(values):
        return "{" + ", ".join(repr(float(v)) for v in list(values) + [0.0]) + "}"
    directions = "{" + ", ".join(str(int(d)) for _, d in code.stops) + (", " if code.stops
                                                                       else "") + "0}"
    header = [
        "/* Generated by mechdyn: the equations M(q) q'' = f of a scene as C for an",
        "   FMI 2.0 Model Exchange FMU. Build: cc -shared -fPIC -O2 -o ID.so model.c -lm */",
        f"#define MODEL_GUID \"{guid}\"",
        f"#define NQ {code.dof}", f"#define NP {len(p)}", f"#define NOUT {len(code.outputs)}",
        f"#define NSTOP {len(code.stops)}", f"#define NSW {code.switches}",
        f"#define START_TIME {float(scene.t_start)!r}",
        f"#define STOP_TIME {float(scene.time_limit)!r}",
        "#include <math.h>",
        "#ifndef M_PI", "#define M_PI 3.14159265358979323846", "#endif",
        "#ifndef M_E", "#define M_E 2.71828182845904523536", "#endif",
        f"static const double START_X[] = {array(y0)};",
        f"static const double START_P[] = {array(p)};",
        f"static const int STOP_DIRECTION[] = {directions};",
        f"#define NCALC {len(where)}",
        "static const int CALCULATED[] = {" + "".join(f"{j}, " for j in where) + "0};", ""]
    return "\n".join(header) + code.source + "\n\n" + calculated_source + \
        '\n\n#include "fmi2_glue.c"\n'

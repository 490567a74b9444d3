"""The SI unit of each output of a scene, from the declared parameter units: an
element's force or moment (energy per unit of what it acts along,
``Element.output_along``: a load's ``along``, a spring's ``stretch``), a slip speed, a
mesh loss, power in W, an expression's own dimension.

>>> import sympy as sp, mechdyn as md
>>> phi = md.coordinate("phi")
>>> J, M = sp.symbols("J M", positive=True)
>>> m = md.Mechanism("drive", [phi], units={J: "kg*m^2", M: "N*m"})
>>> _ = m.link("rotor", J=J, angle=phi)
>>> _ = m.load("motor", M, along=phi)
>>> output_units(m, md.Scene("start", initial={phi: 0}, t_end=1, outputs=["motor"]))
{'motor': 'N*m'}
"""
import sympy as sp

from mechdyn.declare.constraints import Constraint
from mechdyn.declare.dimensions import (ENERGY, TIME, Misfit, MissingUnit, _plain, dimension_of,
                                        known_dimensions)


def output_units(mechanism, scene) -> dict:
    """The SI unit of each of a scene's outputs, by label (see the module)."""
    known = {sp.Symbol(s.name): d for s, d in known_dimensions(mechanism).items()}

    def dimension(expr):
        try:
            return dimension_of(_plain(expr), known)
        except (Misfit, MissingUnit):
            return None
    units = {}
    for label, item in scene.labelled_outputs():
        if isinstance(item, str) and item.startswith("power:"):
            units[label] = "W"
            continue
        name, _, suffix = item.rpartition(".") if isinstance(item, str) else ("", "", "")
        element = mechanism.elements.get(item) if isinstance(item, str) else None
        if name in mechanism.elements and suffix in ("slip", "loss", "mode"):
            element, along = mechanism.elements[name], None
            if suffix != "mode" and element.output_along() is not None:
                along = dimension(element.output_along())
            units[label] = "" if along is None else \
                (along / TIME).si if suffix == "slip" else (ENERGY / along).si
        elif element is not None and element.output_along() is not None:
            along = dimension(element.output_along())    # the output's work per unit of it
            units[label] = (ENERGY / along).si if along is not None else ""
        elif isinstance(item, sp.Basic):
            dim = dimension(item)
            units[label] = dim.si if dim is not None and not dim.dimensionless else ""
        else:
            units[label] = ""
    for element in mechanism.elements.values():     # a loop's multipliers: the force (or
        if isinstance(element, Constraint):          # moment) that closes it, per equation
            for label, equation in element.expressions().items():
                along = dimension(equation)
                units.setdefault(label, (ENERGY / along).si if along is not None else "")
    return units

"""``modelDescription.xml`` of an exported mechanism (FMI 2.0 Model Exchange): its
variables with units and descriptions, in the value-reference layout of the glue
(``fmi2_glue.c``): states ``[q, u]``, their derivatives, parameters
(inputs among them), the scene's outputs and the energies.

>>> unit_of("N*m"), unit_of("kg*m^2"), unit_of("1/s"), unit_of("rad/s"), unit_of("")
(('N.m', {'kg': 1, 'm': 2, 's': -2}), ('kg.m2', {'kg': 1, 'm': 2}), ('1/s', {'s': -1}), ('rad/s', {'s': -1, 'rad': 1}), None)
"""
from __future__ import annotations

from dataclasses import dataclass
from xml.sax.saxutils import quoteattr

from mechdyn.units import dimension

__all__ = ["Variable", "model_description", "unit_of"]

_BASE_UNITS = {"[mass]": "kg", "[length]": "m", "[time]": "s", "[current]": "A",
               "[temperature]": "K", "[substance]": "mol", "[luminosity]": "cd"}


@dataclass
class Variable:
    """One scalar variable: ``kind`` "state", "derivative", "parameter", "calculated"
    (a parameter computed from others), "input" or "output"; ``start`` for states,
    parameters and inputs; ``derivative_of`` the
    (1-based) index of a derivative's state."""
    name: str
    kind: str
    description: str = ""
    unit: str = ""
    start: float | None = None
    derivative_of: int | None = None


def unit_of(text: str):
    """``(FMI unit name, base-unit exponents)`` of an SI unit text (``rad...`` for
    angles), ``None`` for a dimensionless or fractional one."""
    angle = text.startswith("rad")
    if angle:
        text = "1" + text[len("rad"):]
    if not text:
        return None
    exponents = {}
    powers = dict(dimension(text).exponents)
    for base, unit in _BASE_UNITS.items():
        if base in powers:
            if powers[base].denominator != 1:
                return None
            exponents[unit] = int(powers[base])
    if angle:
        exponents["rad"] = 1
    if not exponents:
        return None
    name = text.replace("*", ".").replace("^", "")
    if angle:
        name = "rad" + name[1:] if name.startswith("1/") or name == "1" else "rad." + name
    return name, exponents


_KINDS = {  # kind -> causality, variability, initial
    "state": ("local", "continuous", "exact"),
    "derivative": ("local", "continuous", None),
    "parameter": ("parameter", "tunable", "exact"),
    "calculated": ("calculatedParameter", "tunable", "calculated"),
    "input": ("input", "continuous", None),
    "output": ("output", "continuous", None),
}


def model_description(*, name, identifier, guid, description, variables, units, n_indicators,
                      experiment, tool) -> str:
    """The XML text; ``variables`` in value-reference order, ``units`` an FMI unit name
    -> exponents, ``experiment`` ``(start, stop, tolerance)``."""
    lines = ['<?xml version="1.0" encoding="UTF-8"?>',
             f'<fmiModelDescription fmiVersion="2.0" modelName={quoteattr(name)} '
             f'guid={quoteattr(guid)} description={quoteattr(description)} '
             f'generationTool={quoteattr(tool)} variableNamingConvention="flat" '
             f'numberOfEventIndicators="{n_indicators}">',
             f'  <ModelExchange modelIdentifier="{identifier}" '
             'canNotUseMemoryManagementFunctions="true" canGetAndSetFMUstate="false" '
             'canSerializeFMUstate="false" providesDirectionalDerivative="false">',
             '    <SourceFiles>', '      <File name="model.c"/>', '    </SourceFiles>',
             '  </ModelExchange>']
    if units:
        lines.append("  <UnitDefinitions>")
        for unit, exponents in sorted(units.items()):
            bases = " ".join(f'{base}="{power}"' for base, power in exponents.items())
            lines += [f"    <Unit name={quoteattr(unit)}>", f"      <BaseUnit {bases}/>",
                      "    </Unit>"]
        lines.append("  </UnitDefinitions>")
    start, stop, tolerance = experiment
    lines.append(f'  <DefaultExperiment startTime="{start!r}" stopTime="{stop!r}" '
                 f'tolerance="{tolerance!r}"/>')
    lines.append("  <ModelVariables>")
    for reference, v in enumerate(variables):
        causality, variability, initial = _KINDS[v.kind]
        attributes = [f"name={quoteattr(v.name)}", f'valueReference="{reference}"']
        if v.description:
            attributes.append(f"description={quoteattr(v.description)}")
        attributes += [f'causality="{causality}"', f'variability="{variability}"']
        if initial:
            attributes.append(f'initial="{initial}"')
        real = []
        if v.unit:
            real.append(f"unit={quoteattr(v.unit)}")
        if v.start is not None:
            real.append(f'start="{float(v.start)!r}"')
        if v.derivative_of is not None:
            real.append(f'derivative="{v.derivative_of}"')
        lines += [f"    <ScalarVariable {' '.join(attributes)}>",
                  f"      <Real {' '.join(real)}/>".replace("<Real />", "<Real/>"),
                  "    </ScalarVariable>"]
    lines.append("  </ModelVariables>")
    outputs = [i + 1 for i, v in enumerate(variables) if v.kind == "output"]
    derivatives = [i + 1 for i, v in enumerate(variables) if v.kind == "derivative"]
    calculated = [i + 1 for i, v in enumerate(variables) if v.kind == "calculated"]
    lines.append("  <ModelStructure>")
    for tag, indices in (("Outputs", outputs), ("Derivatives", derivatives),
                         ("InitialUnknowns", sorted(outputs + derivatives + calculated))):
        if indices:
            lines += [f"    <{tag}>"] + [f'      <Unknown index="{i}"/>' for i in indices] + \
                [f"    </{tag}>"]
    lines += ["  </ModelStructure>", "</fmiModelDescription>", ""]
    return "\n".join(lines)

"""Values a scene was given with units, checked against the mechanism's units.

A scene is made without its mechanism, so a value typed with a unit — an initial value
``"1500 rpm"``, a stop value ``md.reaches(h, "20 mm")`` — is converted to SI when the
scene is made (the SI value does not depend on the unit expected) and its text kept;
here, once the mechanism is known, each text is checked against the unit of what it
gives a value to: a coordinate's declared unit (rad by default), its speed's unit/s, a
stop expression's dimension (from the declared units); :func:`check_scene` also checks
that stop conditions and initial expressions compare like with like. A misfit is a
:class:`~mechdyn.errors.SceneError` naming the scene, the state or condition and the
text.

>>> import sympy as sp, mechdyn as md
>>> x = md.coordinate("x")
>>> cart = md.Mechanism("cart", [x], units={x: "m"})
>>> state_unit(cart, md.speed(x))
'm/s'
>>> scene = md.Scene("push", initial={x: "20 mm", md.speed(x): "2 kN"}, t_end=1)
>>> check_given(cart, scene)
Traceback (most recent call last):
...
mechdyn.errors.SceneError: scene 'push': initial value of xdot = '2 kN': kN is a force but m/s (a velocity) is expected
"""
from __future__ import annotations

import sympy as sp

from mechdyn.declare.dimensions import (Misfit, MissingUnit, _by_name, _plain, _same, dimension_of,
                                        known_dimensions)
from mechdyn.errors import MechdynError, SceneError
from mechdyn.symbols import is_coordinate, plain, t

__all__ = ["state_unit", "check_given", "check_scene"]


def state_unit(mechanism, key):
    """The SI unit of a coordinate (its declared unit, rad by default), of its speed
    (unit/s) or acceleration (unit/s^2); None for anything else."""
    if is_coordinate(key):
        name, order = key.func.__name__, 0
    elif isinstance(key, sp.Derivative) and is_coordinate(key.expr) and \
            len(key.variable_count) == 1 and key.variable_count[0][0] == t:
        name, order = key.expr.func.__name__, key.variable_count[0][1]
    else:
        return None
    if name not in {q.func.__name__ for q in mechanism.coordinates}:
        return None
    unit = mechanism.units.get(name, "rad")
    if order == 0:
        return unit
    per = "/s" if order == 1 else f"/s^{order}"
    return f"1{per}" if unit.strip() in ("", "1") else f"{unit}{per}" \
        if "/" not in unit else f"({unit}){per}"


def check_given(mechanism, scene):
    """Check every value ``scene`` was given with a unit (see the module)."""
    from mechdyn.units import to_si
    for key, text in scene.given.items():
        unit = state_unit(mechanism, key)
        if unit is None:
            continue                      # not a state: initial_state names the key
        try:
            to_si(text, unit)
        except MechdynError as error:
            raise SceneError(f"scene {scene.name!r}: initial value of {plain(key)} = "
                             f"{_without_text(error, text)}") from None
    for condition in scene.until:
        if not condition.given:
            continue
        unit = _expression_unit(mechanism, scene, condition)
        if unit is None:
            continue                      # a decimal in the expression: unknowable
        try:
            to_si(condition.given, unit)
        except MechdynError as error:
            raise SceneError(f"scene {scene.name!r}: stop condition {condition!r}: "
                             f"{_without_text(error, condition.given)}") from None


def _without_text(error, text) -> str:
    """The unit error's message, starting with the text once."""
    message = str(error)
    return message if message.startswith(repr(text)) else f"{text!r}: {message}"


def _expression_unit(mechanism, scene, condition):
    """The unit a stop condition's value must have: the state's own unit for a
    coordinate or speed, else the SI unit of the expression's dimension (an angle
    counted in it, so Hz is refused where radians per second are meant)."""
    unit = state_unit(mechanism, condition.expression)
    if unit is not None:
        return unit
    try:
        dim = dimension_of(_plain(condition.expression),
                           _by_name(known_dimensions(mechanism)))
    except MissingUnit as missing:
        raise SceneError(f"scene {scene.name!r}: stop condition {condition!r}: the value "
                         f"{condition.given!r} has a unit, but {missing} in the expression "
                         "has none (declare its unit in Mechanism(units=...), or give the "
                         "value as an SI number)") from None
    except Misfit as misfit:
        raise SceneError(f"scene {scene.name!r}: stop condition {condition!r}: "
                         f"{misfit}") from None
    if dim is None:
        return None
    angular = any(mechanism.units.get(q.func.__name__, "rad") == "rad"
                  for q in mechanism.coordinates
                  if condition.expression.has(q))
    if angular and not any(base in ("[mass]", "[length]") for base, _ in dim.exponents):
        si = dim.si
        return "rad" + si[1:] if si.startswith("1/") else "rad" if si == "1" else si
    return dim.si


def check_scene(mechanism, scene):
    """Stop conditions compare like with like; initial values fit their states (also
    those typed with units, :func:`check_given`)."""
    check_given(mechanism, scene)
    known = _by_name(known_dimensions(mechanism))
    for condition in scene.until:
        _same_in_scene(scene, condition, [condition.expression, condition.value], known,
                       f"stop condition {condition!r} ", f"stop condition {condition!r}")
    for key, value in scene.initial.items():
        if isinstance(value, sp.Basic):
            _same_in_scene(scene, key, [key, value], known,
                           f"initial value of {_plain(key)} = {_plain(value)}: ",
                           f"initial value of {_plain(key)}")


def _same_in_scene(scene, key, expressions, known, misfit_says, missing_says):
    """:func:`_same` for one entry of ``scene``; a misfit is a SceneError that starts
    with ``misfit_says``, a symbol without a unit one that names ``missing_says``."""
    try:
        _same(key, [_plain(e) for e in expressions], known, {})
    except Misfit as misfit:
        raise SceneError(f"scene {scene.name!r}: {misfit_says}{misfit}") from None
    except MissingUnit as missing:
        raise SceneError(f"scene {scene.name!r}: {missing_says} uses {missing}, which has "
                         "no unit") from None

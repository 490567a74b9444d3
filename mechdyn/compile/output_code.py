"""Outputs of a scene as plain expressions for the generated ``outputs`` function.

An output is an element's name (its force along its own ``along``: a spring's
``k * stretch``, a damper's, a load's value, a friction's ``-magnitude * sign`` with the
run-time sign), ``power:NAME`` (an element's power), ``NAME.slip`` (a friction's sliding
speed), a sympy expression, or a closed loop's name (its multipliers). Outputs known
only at run time (a stuck element's holding force, a stop's contact force, a lossy
gear's mesh and loss moments, ``NAME.mode``) are generated as 0 and filled in by
:mod:`mechdyn.simulate.mode_outputs`.

>>> import mechdyn as md
>>> from mechdyn.derive.selection import select
>>> model = md.load_model("models/shoe_brake.py")
>>> scene = md.Scene("b", initial={}, t_end=1, outputs=["shoe", "shoe.slip"])
>>> eqs = model.mechanism.equations(scene)
>>> [(label, str(expr)) for label, expr, _ in outputs(eqs, select(model.mechanism, scene))]
[('shoe', '-2*P*R*f*sign(phidot)'), ('shoe.slip', 'phidot')]
"""
from __future__ import annotations

import sympy as sp

from mechdyn.derive.equations import element_output
from mechdyn.errors import SceneError

__all__ = ["outputs", "slip_signed", "friction_signed"]


def slip_signed(friction, sign):
    """A friction's magnitude with ``|rate|`` written ``sign * rate`` (the run-time sign:
    equal while it slides, and the rate is 0 while it is stuck), so that a magnitude of
    the sliding speed's size (a Stribeck curve, a table) needs no switching function."""
    return friction.magnitude.xreplace({sp.Abs(friction.rate): sign * friction.rate,
                                        sp.Abs(-friction.rate): sign * friction.rate})


def friction_signed(expr, eqs, signs):
    """Replace ``sign(rate)`` of each friction by its run-time sign parameter (and
    ``|rate|`` by ``sign * rate``)."""
    replace = {}
    for fr, s in zip(eqs.frictions, signs):
        replace.update({sp.sign(fr.rate): s, sp.Heaviside(fr.rate): s,
                        sp.Abs(fr.rate): s * fr.rate, sp.Abs(-fr.rate): s * fr.rate})
    return sp.sympify(expr).xreplace(replace)


def outputs(eqs, selected) -> list:
    """``(label, plain expression, item)`` for each output a scene's selection
    ``selected`` (:class:`~mechdyn.derive.selection.Selection`) asks for (``item``: an
    element name or ``power:NAME``; an expression as text)."""
    result, scene_name = [], selected.scene_name
    for label, item in selected.outputs:
        if isinstance(item, str):
            if item.startswith("power:"):
                name = item[len("power:"):]
                if name not in eqs.powers and name in {g.name for g in eqs.gears}:
                    result.append((label, sp.S.Zero, item))     # the gear's loss: run time
                    continue
                if name not in eqs.powers:
                    raise SceneError(f"scene {scene_name!r}: output {item!r}: no load "
                                     f"{name!r} in the scene (loads: {sorted(eqs.powers)})")
                result.append((label, eqs.powers[name], item))
                continue
            if item in selected.loops:                   # its multipliers (simulate)
                result += [(component, sp.S.Zero, item) for component in selected.loops[item]]
                continue
            if "." in item and item.rsplit(".", 1)[1] in _SUFFIXES:
                result.append((label, _coupling_output(eqs, scene_name, item), item))
                continue
            result.append((label, element_output(eqs, scene_name, item, selected.elements),
                           item))
        elif isinstance(item, sp.Basic):
            result.append((label, eqs.to_plain(sp.sympify(item)), label))
        else:
            raise SceneError(f"scene {scene_name!r}: output {item!r} is neither an element "
                             "name, 'power:NAME', nor a sympy expression")
    return result


_SUFFIXES = ("slip", "mode", "loss")


def _coupling_output(eqs, scene_name, item):
    """``NAME.slip`` (the sliding speed of a friction, one-way clutch or lossy gear),
    ``NAME.mode`` (+1/-1 sliding, 0 stuck, 2 free; a stop: 0 open, +1/-1 resting on its
    lower/upper limit) and ``NAME.loss`` (a lossy gear's loss moment); the last two are
    filled in at run time (:mod:`mechdyn.simulate.mode_outputs`)."""
    name, suffix = item.rsplit(".", 1)
    friction = next((fr for fr in eqs.frictions if fr.name == name), None)
    stop = any(c.element == name for c in eqs.contacts)
    if suffix == "slip" and friction is not None:
        return friction.rate
    if (suffix == "mode" and (friction is not None or stop)) or \
            (suffix == "loss" and friction is not None and friction.kind == "gear"):
        return sp.S.Zero
    raise SceneError(f"scene {scene_name!r}: output {item!r}: no friction, one-way clutch,"
                     f" stop or lossy gear {name!r} in the scene with a {suffix!r} output")



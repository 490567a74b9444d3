"""The printed laws of the elements that switch (frictions, one-way clutches, stops,
lossy gears): shared by the expanded and the textbook derivation.

>>> import mechdyn as md
>>> eqs = md.load_model("models/hard_stop.py").mechanism.equations()
>>> [(text, str(law)) for _, _, text, law in coupling_steps(eqs)][:2]
[('g[end stop.lower]', 'theta + theta_0 >= 0'), ('dg+[end stop.lower]/dt', '-e*gdot')]
"""
from __future__ import annotations

import sympy as sp

from mechdyn.derive.budget import Budget
from mechdyn.symbols import dotted_symbol

__all__ = ["coupling_steps"]


def coupling_steps(eqs) -> list:
    """The laws of the elements that switch: static limits of frictions and one-way
    clutches (``lambda^max``), the one-way condition, the stops' gaps and impact law, a
    lossy gear's loss moment as a function of its mesh moment ``tau``."""
    steps = []
    for fr in eqs.frictions:
        name = f"\\text{{{fr.name}}}"
        if fr.kind == "one_way":
            steps.append(("one-way", f"\\dot{{s}}_{{{name}}}", f"ds[{fr.name}]/dt",
                          sp.Ge(fr.rate, 0)))
        at_rest = {sp.Abs(fr.rate): 0, sp.Abs(-fr.rate): 0}
        limit = fr.peak * fr.magnitude.xreplace(at_rest)
        if fr.kind == "one_way" and fr.release != 0:
            limit = sp.Max(limit, fr.release)
        if fr.kind != "gear" and (fr.peak != 1 or fr.kind == "one_way"):
            steps.append(("static limit", f"\\lambda^{{\\max}}_{{{name}}}",
                          f"lambda_max[{fr.name}]", Budget().tidy(limit)))
    for contact in eqs.contacts:
        name = f"\\text{{{contact.name}}}"
        steps.append(("stop", f"g_{{{name}}}", f"g[{contact.name}]", sp.Ge(contact.gap, 0)))
        steps.append(("impact", f"\\dot{{g}}^{{+}}_{{{name}}}", f"dg+[{contact.name}]/dt",
                      -contact.restitution * dotted_symbol("g", 1)))   # g' before
    for gear in eqs.gears:
        tau = sp.Symbol(f"tau_{gear.name}")
        eta_forward, eta_backward, bearing_forward, bearing_backward = gear.law
        loss = (1 - eta_forward) * tau + bearing_forward
        if not (eta_backward.is_number and eta_backward <= 0):
            loss = sp.Max(loss, (1 - 1 / eta_backward) * tau + bearing_backward)
        name = f"\\text{{{gear.name}}}"
        steps.append(("mesh loss", f"\\tau_{{\\mathrm{{loss}}, {name}}}",
                      f"tau_loss[{gear.name}]", loss))
        friction = eqs.frictions[gear.friction]
        for qi, entry in zip(eqs.q, friction.gradient):
            if entry != 0:
                steps.append(("generalized force", f"Q_{{{name}, {sp.latex(qi)}}}",
                              f"Q[{gear.name}, {qi}]",
                              -entry * sp.Symbol(f"tau_loss_{gear.name}")))
    return steps

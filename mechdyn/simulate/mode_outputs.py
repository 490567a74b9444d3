"""Outputs known only at run time, from the friction modes: a stuck element's holding
force, a stop's contact force, a lossy gear's mesh moment (``NAME``), loss moment
(``NAME.loss``) and loss power (``power:NAME``), and modes (``NAME.mode``: +1/-1 sliding,
0 stuck, 2 free; a stop: 0 open, +1/-1 resting on its lower/upper limit). The
generated ``outputs`` function gives 0 for them (:mod:`mechdyn.compile.output_code`).

>>> import mechdyn as md
>>> model = md.load_model("models/shoe_brake.py")
>>> scene = md.Scene("b", initial={model.mechanism.coordinates[0]: 0,
...                                md.speed(model.mechanism.coordinates[0]): 10},
...                  t_end=10, outputs=["shoe", "shoe.mode"])
>>> res = model.mechanism.simulate(scene, model.params)
>>> res.outputs_at([1.0, 9.0])["shoe.mode"].tolist()      # sliding, then stuck (at 5 s)
[1.0, 0.0]
"""
from __future__ import annotations

__all__ = ["run_time_outputs"]


def run_time_outputs(modes, t, y, mode, items, values) -> list:
    """``values`` (the generated outputs at ``(t, y)``) with those known only at run
    time filled in; ``items``: what each output asks for (an element name,
    ``NAME.mode``, ``NAME.loss``, ``power:NAME``); ``modes``: the
    :class:`~mechdyn.simulate.friction.FrictionModes`, ``mode`` the segment's mode."""
    stuck = {modes.names[k] for k in mode.stuck if k < modes.k}
    wanted = [(i, item) for i, item in enumerate(items) if _run_time(modes, item, stuck)]
    if not wanted:
        return values
    _, forces, solution = modes.forces(t, y, mode)
    rates = modes.view(t, y, mode).rates
    gears = {name: (k, c) for name, k, c in modes.gears}
    values = list(values)
    for i, item in wanted:
        if item.startswith("power:"):
            k, _ = gears[item[6:]]
            values[i] = forces[k] * rates[k]
        elif item in gears:
            values[i] = -solution.loops[gears[item][1]]        # the mesh moment tau
        elif item.endswith(".loss"):
            values[i] = -forces[gears[item[:-5]][0]]
        elif item.endswith(".mode"):
            values[i] = _mode_number(modes, item[:-5], mode)
        elif item in modes.contact_elements:
            values[i] = sum(_side(modes, j) * forces[modes.k + j]
                            for j, owner in enumerate(modes.contact_elements) if owner == item)
        else:
            values[i] = forces[modes.names.index(item)]
    return values


def _run_time(modes, item, stuck) -> bool:
    gear_names = {name for name, _, _ in modes.gears}
    return (item.startswith("power:") and item[6:] in gear_names) or item in gear_names \
        or item.endswith((".mode", ".loss")) or item in modes.contact_elements \
        or item in stuck


def _side(modes, j) -> int:
    return 1 if modes.contact_names[j].endswith(".lower") else -1


def _mode_number(modes, name, mode) -> float:
    stuck = set(mode.stuck)
    if name in modes.names:
        k = modes.names.index(name)
        return 2.0 if k in mode.free else (0.0 if k in stuck else float(mode.signs[k]))
    return float(sum(_side(modes, j) for j, owner in enumerate(modes.contact_elements)
                     if owner == name and modes.k + j in stuck))

"""What a scene takes of a mechanism, as data for the later stages: the elements its
equations are made of, its loops, outputs and stop conditions. Code generation
(:mod:`mechdyn.compile`) works from this and the equations alone, without going back to
the declarations.

>>> import mechdyn as md
>>> phi = md.coordinate("phi")
>>> disc = md.Mechanism("disc", [phi])
>>> _ = disc.link("disc", J=2, angle=phi)
>>> _ = disc.load("drive", 6, along=phi)
>>> _ = disc.load("brake", -1, along=phi, tags=["braking"])
>>> chosen = select(disc, md.Scene("coast", effects=["braking"], initial={}, t_end=1,
...                                outputs=["brake"]))
>>> chosen.names, list(chosen.elements), chosen.outputs
(('brake',), ['disc', 'brake'], (('brake', 'brake'),))
"""
from __future__ import annotations

from dataclasses import dataclass

from mechdyn.declare.elements import Constraint, is_structural
from mechdyn.declare.scene import selection

__all__ = ["Selection", "select"]


@dataclass(frozen=True)
class Selection:
    """A scene's part of a mechanism: ``names`` of the loads it includes, its ``rigid``
    springs (together what its equations are derived under), ``elements`` (name
    -> element: the links, loops and joints and those loads, in declaration order),
    ``loops`` (loop name -> the labels of its scalar constraints), the scene's name,
    ``outputs`` (``(label, item)``) and stop conditions ``until`` (none without a scene)."""
    names: tuple
    rigid: tuple
    elements: dict
    loops: dict
    scene_name: str | None = None
    outputs: tuple = ()
    until: tuple = ()


def select(mechanism, scene=None) -> Selection:
    """The :class:`Selection` of ``scene`` (all elements without one), checked (a
    :class:`~mechdyn.errors.SceneError` names an unknown effect or rigid spring)."""
    names, rigid = selection(mechanism, scene)
    chosen = set(names)
    elements = {name: element for name, element in mechanism.elements.items()
                if name in chosen or is_structural(element)}
    loops = {name: tuple(element.labels) for name, element in elements.items()
             if isinstance(element, Constraint)}
    if scene is None:
        return Selection(names, rigid, elements, loops)
    return Selection(names, rigid, elements, loops, scene.name,
                     tuple(scene.labelled_outputs()), tuple(scene.until))

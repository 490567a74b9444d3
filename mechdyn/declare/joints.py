"""Joints: where two links meet, for kinetostatics (the reactions they carry).

A joint takes no part in the equations of motion; :mod:`mechdyn.analyse.joint_reactions`
solves for the force (and moment) each one transmits.
"""
from __future__ import annotations

from dataclasses import dataclass

from mechdyn.declare.element_base import Element, as_expression
from mechdyn.errors import DeclarationError

__all__ = ["Joint"]


@dataclass(frozen=True)
class Joint(Element):
    """A joint between two links (``"frame"`` for the fixed frame), for kinetostatics.

    ``kind``: ``"revolute"`` (a pin at the point ``at``: force, no moment),
    ``"prismatic"`` (a slide along the angle ``direction``: force normal to it and a
    moment; ``at`` is the point of the slider the normal force is referred to) or
    ``"weld"`` (rigidly joined, e.g. a flywheel keyed on the crank: force and moment).
    The reaction of a joint is the force (and moment) the first link exerts on the second.

    Examples
    --------
    >>> import mechdyn as md
    >>> phi = md.coordinate("phi")
    >>> crank = md.Mechanism("crank", [phi])
    >>> _ = crank.link("crank", J=1, angle=phi)
    >>> crank.joint("O", ("frame", "crank"), at=(0, 0)).kind
    'revolute'
    """
    links: tuple = ()
    at: tuple = ()
    kind: str = "revolute"
    direction: object = None

    def __post_init__(self):
        super().__post_init__()
        what = f"joint {self.name!r}"
        links = self.links
        if isinstance(links, str) or len(links) != 2 or not all(isinstance(n, str)
                                                                  for n in links):
            raise DeclarationError(f"{what}: links must be two link names (or 'frame'), "
                                   f"got {links!r}")
        if links[0] == links[1]:
            raise DeclarationError(f"{what}: joins {links[0]!r} to itself")
        object.__setattr__(self, "links", tuple(links))
        if self.kind not in ("revolute", "prismatic", "weld"):
            raise DeclarationError(f"{what}: kind must be 'revolute', 'prismatic' or "
                                   f"'weld', got {self.kind!r}")
        if not (isinstance(self.at, (tuple, list)) and len(self.at) == 2):
            raise DeclarationError(f"{what}: at must be the point (x, y), got {self.at!r}")
        object.__setattr__(self, "at", tuple(as_expression(v, f"{what}: at")
                                             for v in self.at))
        if (self.kind == "prismatic") != (self.direction is not None):
            raise DeclarationError(f"{what}: a prismatic joint needs direction= (the angle "
                                   "of its slide), other joints take none")
        if self.direction is not None:
            self.convert("direction")

    def expressions(self):
        out = {"x": self.at[0], "y": self.at[1]}
        if self.direction is not None:
            out["direction"] = self.direction
        return out

"""Constraints: the closed loops of a mechanism, ``g(q, t) = 0`` between its coordinates.

>>> import sympy as sp, mechdyn as md
>>> a, b = md.coordinate("a"), md.coordinate("b")
>>> md.declare.constraints.Constraint("loop", terms=[(1, a), (1, b), (-2, 0)]).labels
('loop.x', 'loop.y')
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from mechdyn.declare.element_base import Element, as_expression
from mechdyn.errors import DeclarationError

__all__ = ["Constraint"]


@dataclass(frozen=True)
class Constraint(Element):
    """Holonomic constraints ``g(q, t) = 0`` between the coordinates (a closed loop).

    ``equations``: the scalar expressions that vanish; ``components``: their names
    (``"x"``, ``"y"`` of a vector loop, empty for one constraint); ``terms``: a vector
    loop's ``(length, angle)`` pairs, ``sum length e^{i angle} = 0`` (empty otherwise).
    Like links, constraints are always part of the mechanism (never a scene's effect).
    """
    equations: tuple = ()
    components: tuple = ()
    terms: tuple = ()

    def __post_init__(self):
        super().__post_init__()
        if self.terms:
            pairs = []
            for k, term in enumerate(self.terms):
                if not (isinstance(term, (tuple, list)) and len(term) == 2):
                    raise DeclarationError(
                        f"loop {self.name!r}: term {k + 1} is {term!r}; give each term as "
                        "(length, angle), meaning length * e^(i angle)")
                pairs.append((as_expression(term[0], f"loop {self.name!r}: length {k + 1}"),
                              as_expression(term[1], f"loop {self.name!r}: angle {k + 1}")))
            object.__setattr__(self, "terms", tuple(pairs))
            object.__setattr__(self, "equations", (
                sp.Add(*[l * sp.cos(a) for l, a in pairs]),
                sp.Add(*[l * sp.sin(a) for l, a in pairs])))
            object.__setattr__(self, "components", ("x", "y"))
        else:
            equations = self.equations
            if not isinstance(equations, (tuple, list)):
                equations = (equations,)
            object.__setattr__(self, "equations", tuple(
                as_expression(g, f"constraint {self.name!r}") for g in equations))
        if not self.equations:
            raise DeclarationError(f"constraint {self.name!r}: no equation given")

    @property
    def labels(self) -> tuple:
        """The names of the scalar constraints: ``NAME.x``, ``NAME.y`` or ``NAME``."""
        if self.components:
            return tuple(f"{self.name}.{c}" for c in self.components)
        if len(self.equations) == 1:
            return (self.name,)
        return tuple(f"{self.name}[{k}]" for k in range(len(self.equations)))

    def expressions(self):
        return dict(zip(self.labels, self.equations))

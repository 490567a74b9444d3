"""The derived equations as data: :class:`Equations` (``M(q) q'' = f(q, q', t)`` in plain
symbols, the reduced quantities of one DOF, LaTeX) and its friction, contact, lossy-gear
and loop-closure terms, made by :func:`mechdyn.derive.lagrange.derive`."""
from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp

from mechdyn.errors import DerivationError
from mechdyn.symbols import t

__all__ = ["Equations", "FrictionTerm", "ContactTerm", "GearTerm", "ConstraintTerm"]


@dataclass(frozen=True)
class FrictionTerm:
    """A Coulomb friction element in plain symbols: magnitude, the gradient of its
    ``along`` expression, its sliding rate and the velocity-only part of its second
    derivative (``s'' = gradient . q'' + bias``); ``kind`` "friction", "one_way" (a
    one-way clutch: ``release`` its smallest breakaway moment) or "gear" (the mesh loss
    of a lossy gear, along ``ratio * output``; its magnitude comes from the gear's law
    at run time); ``peak`` the static factor."""
    name: str
    magnitude: sp.Expr
    gradient: sp.Matrix
    rate: sp.Expr
    bias: sp.Expr
    kind: str = "friction"
    peak: sp.Expr = sp.S.One
    release: sp.Expr = sp.S.Zero


@dataclass(frozen=True)
class ContactTerm:
    """One limit of a hard stop in plain symbols: ``gap`` (``side * (along - limit)``,
    non-negative while open), its gradient, rate and bias (as :class:`FrictionTerm`),
    the ``restitution`` and the stop's ``element`` name; ``name`` is ``STOP.lower`` or
    ``STOP.upper``."""
    name: str
    element: str
    gap: sp.Expr
    gradient: sp.Matrix
    rate: sp.Expr
    bias: sp.Expr
    restitution: sp.Expr


@dataclass(frozen=True)
class GearTerm:
    """A lossy gear: its mesh constraint's index in ``Equations.constraints``, its loss
    element's index in ``Equations.frictions`` and its ``law`` ``(eta_forward,
    eta_backward, bearing_forward, bearing_backward)`` in plain symbols."""
    name: str
    constraint: int
    friction: int
    law: tuple


@dataclass(frozen=True)
class ConstraintTerm:
    """A scalar holonomic constraint ``g(q, t) = 0`` of a closed loop in plain symbols:
    its ``expression`` g, its ``gradient`` dg/dq (a column over ``Equations.q``) and the
    velocity and time part of its second derivative (``g'' = gradient . q'' + bias``).
    With constraints the equations read ``M q'' = f + G' lambda``, ``G q'' = -bias``."""
    name: str
    expression: sp.Expr
    gradient: sp.Matrix
    bias: sp.Expr


@dataclass
class Equations:
    """Lagrange's equations of a mechanism (or of a scene's selection of it).

    Attributes: ``coordinates`` (functions of t), ``q``, ``u``, ``a`` (plain symbols of
    coordinates, speeds, accelerations), ``mass_matrix`` and ``forcing`` (``M a = f``),
    ``kinetic_energy``, ``potential_energy``, ``dissipation``, ``generalized_forces``
    (element name -> column), ``powers`` (element name -> power), ``frictions``,
    ``eliminated`` (coordinate -> expression, from rigid springs), ``elements`` (names
    included), ``excluded`` (names left out), ``rigid`` (names made rigid),
    ``constraints`` (the closed loops' :class:`ConstraintTerm` s: ``M a = f + G' lambda``
    with ``G a = -bias``), ``independent`` (plain symbols of the independent coordinates),
    ``contacts`` (the stops' limits, :class:`ContactTerm`), ``gears`` (:class:`GearTerm`),
    ``works`` (element name -> its :class:`~mechdyn.declare.element_base.Work` in plain
    symbols), ``acting`` (element name -> the element: the printed derivation asks it
    for its terms in named quantities),
    ``coordinate_units`` (plain symbol -> declared unit), ``named_values`` (of the
    printed equations: symbol -> ``(number, label)`` it stands for, standard gravity's
    ``g``; empty in the equations the numerics use).
    """
    name: str
    coordinates: tuple
    q: tuple
    u: tuple
    a: tuple
    mass_matrix: sp.Matrix
    inertial_forcing: sp.Matrix
    kinetic_energy: sp.Expr
    potential_energy: sp.Expr
    dissipation: sp.Expr
    generalized_forces: dict
    powers: dict
    frictions: tuple
    eliminated: dict
    elements: tuple
    excluded: tuple
    rigid: tuple
    rheonomic: bool
    links: dict = field(default_factory=dict)
    to_plain: object = None
    constraints: tuple = ()
    independent: tuple = ()
    contacts: tuple = ()
    gears: tuple = ()
    works: dict = field(default_factory=dict)
    acting: dict = field(default_factory=dict)
    coordinate_units: dict = field(default_factory=dict)
    named_values: dict = field(default_factory=dict)

    # --------------------------------------------------------------- the system
    @property
    def dof(self) -> int:
        return len(self.q)

    @property
    def forcing(self) -> sp.Matrix:
        """Right-hand side ``f``: generalized forces plus velocity-dependent inertia terms
        (friction appears with ``sign`` of its sliding rate)."""
        total = self.inertial_forcing
        for column in self.generalized_forces.values():
            total = total + column
        return total

    @property
    def smooth_forcing(self) -> sp.Matrix:
        """The forcing without the friction elements (they switch; see simulate)."""
        friction_names = {fr.name for fr in self.frictions}
        total = self.inertial_forcing
        for name, column in self.generalized_forces.items():
            if name not in friction_names:
                total = total + column
        return total

    @property
    def switching(self) -> tuple:
        """Names of the elements whose modes switch at run time: frictions, one-way
        clutches, lossy gears, stops."""
        stops = [c.element for c in self.contacts]
        return tuple(fr.name for fr in self.frictions) + tuple(dict.fromkeys(stops))

    @property
    def eqs(self) -> list:
        """The equations as a list of ``sp.Eq(sum_j M_ij a_j, f_i)``."""
        lhs = self.mass_matrix * sp.Matrix(self.a)
        return [sp.Eq(lhs[i], self.forcing[i]) for i in range(self.dof)]

    @property
    def parameters(self) -> tuple:
        """Symbols other than coordinates, speeds and time, sorted by name."""
        exprs = [self.mass_matrix, self.forcing, self.kinetic_energy, self.potential_energy]
        exprs += [fr.magnitude for fr in self.frictions]
        known = set(self.q) | set(self.u) | {t}
        free = set().union(*(e.free_symbols for e in exprs)) - known
        return tuple(sorted(free, key=lambda s: s.name))

    # ------------------------------------------------------------ one DOF only
    def _one_dof(self, what):
        if self.dof != 1:
            names = ", ".join(str(q) for q in self.q)
            raise DerivationError(
                f"{what} is defined for one-DOF mechanisms; {self.name!r} has {self.dof} "
                f"coordinates ({names}). Use equations() (mass matrix and forcing), or make "
                "springs rigid in a scene to reduce it")
        if self.rheonomic:
            raise DerivationError(
                f"{what}: positions of {self.name!r} depend explicitly on time t (an imposed "
                "motion), so the textbook one-DOF form does not apply; use equations()")

    @property
    def reduced_inertia(self) -> sp.Expr:
        """``I_red = sum m (v_S/omega)^2 + J (omega_i/omega)^2`` (= ``M_11``)."""
        self._one_dof("reduced_inertia")
        return self.mass_matrix[0, 0]

    @property
    def reduced_moment(self) -> sp.Expr:
        """``M_red``: the generalized force of every load, spring, damper, gravity and
        friction, reduced to the coordinate."""
        self._one_dof("reduced_moment")
        return sp.Add(*[column[0] for column in self.generalized_forces.values()])

    @property
    def textbook_equation(self) -> sp.Eq:
        """``I_red eps + 1/2 dI_red/dphi omega^2 = M_red``."""
        inertia = self.reduced_inertia
        q, u, a = self.q[0], self.u[0], self.a[0]
        return sp.Eq(inertia * a + sp.diff(inertia, q) / 2 * u**2, self.reduced_moment)

    def _repr_latex_(self):
        from mechdyn.derive.latex import equations_latex
        return "$\\displaystyle " + equations_latex(self) + "$"



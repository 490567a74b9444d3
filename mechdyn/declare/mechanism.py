"""The Mechanism: generalized coordinates, links and loads, declared in Python.

>>> import sympy as sp, mechdyn as md
>>> phi = md.coordinate("phi")
>>> J1, m3, l, M1, F3 = sp.symbols("J_1 m_3 l M_1 F_3", positive=True)
>>> yoke = md.Mechanism("Scotch yoke", coordinates=[phi])
>>> yoke.link("crank", J=J1, angle=phi)
Link(name='crank', tags=(), m=0, J=J_1, x=0, y=0, angle=phi(t))
>>> _ = yoke.link("yoke", m=m3, x=l * sp.cos(phi))
>>> _ = yoke.load("drive", M1, along=phi)
>>> _ = yoke.load("resistance", F3, along=l * sp.cos(phi))
>>> yoke.reduced_inertia()
J_1 + l**2*m_3*sin(phi)**2
>>> yoke.reduced_moment()
-F_3*l*sin(phi) + M_1
"""
from __future__ import annotations

import sympy as sp
from sympy.core.function import AppliedUndef

from mechdyn.declare.couplings import Couplings
from mechdyn.declare.contract import checked_expressions
from mechdyn.declare.names import check_coordinates, check_parameters
from mechdyn.declare.elements import (FRAME, Constraint, Damper, Element, Friction, Gravity, Joint,
                                      Link, Load, Spring)
from mechdyn.errors import DeclarationError
from mechdyn.symbols import is_coordinate, t

__all__ = ["Mechanism"]

_WORDS = {"q": "the coordinates", "v": "speeds", "t": "the time t"}


class Mechanism(Couplings):
    """A machine: generalized coordinates, links (inertia and kinematics) and loads.

    Parameters
    ----------
    name : str
        Shown in reports.
    coordinates : list
        Generalized coordinates made with :func:`mechdyn.coordinate`.
    units : dict, optional
        Units of coordinates (``{x: "m"}``; default ``"rad"``) and of parameters
        (``{P: "N", R: "m", I: "kg*m^2", f: "1"}``). With parameter units declared,
        the dimension of every element's contribution to every equation is checked
        (:meth:`check_dimensions`, also when the equations are derived).
    independent : list, optional
        With closed loops (:meth:`loop`, :meth:`constraint`): the independent
        coordinates (a crank angle), whose initial values a scene gives; the others are
        dependent, assembled from the loops. Default: the first ``n - m`` coordinates
        (``m`` scalar constraints).

    Raises
    ------
    DeclarationError
        No coordinates, a coordinate that is not one, or one declared twice.

    Examples
    --------
    >>> import sympy as sp, mechdyn as md
    >>> phi = md.coordinate("phi")
    >>> J1, m3, l = sp.symbols("J_1 m_3 l", positive=True)
    >>> yoke = md.Mechanism("Scotch yoke", [phi], units={J1: "kg*m^2", m3: "kg", l: "m"})
    >>> _ = yoke.link("crank", J=J1, angle=phi)
    >>> _ = yoke.link("yoke", m=m3, x=l * sp.cos(phi))
    >>> yoke.reduced_inertia()
    J_1 + l**2*m_3*sin(phi)**2
    >>> list(yoke.elements)
    ['crank', 'yoke']
    """

    def __init__(self, name: str, coordinates, units=None, independent=None):
        coordinates = list(coordinates)
        if not coordinates:
            raise DeclarationError(f"mechanism {name!r}: give at least one coordinate")
        for q in coordinates:
            if not is_coordinate(q):
                raise DeclarationError(
                    f"mechanism {name!r}: {q!r} is not a coordinate; "
                    "make coordinates with md.coordinate('name')")
        names = [q.func.__name__ for q in coordinates]
        for n in names:
            if names.count(n) > 1:
                raise DeclarationError(f"mechanism {name!r}: coordinate {n!r} declared twice")
        check_coordinates(name, coordinates)
        self.name = name
        self.coordinates = tuple(coordinates)
        self.units = {}
        self.parameter_units = {}
        self.elements: dict[str, Element] = {}
        self._speeds = {sp.Derivative(q, t) for q in self.coordinates}
        self._derived = {}
        self._memo = {}                 # per scene: cache key, output units
        self._independent = None
        if independent is not None:
            chosen = [independent] if is_coordinate(independent) else list(independent)
            for q in chosen:
                if q not in self.coordinates:
                    raise DeclarationError(
                        f"mechanism {name!r}: independent coordinate {q!r} is not one of "
                        f"its coordinates {_names(coordinates)}")
            self._independent = tuple(chosen)
        self._dimensions_checked = False
        self.declare_units(units or {})

    def declare_units(self, units: dict):
        """Declare units of coordinates and parameters (``{x: "m", P: "kN"}``; ``"1"``
        for a dimensionless parameter); see the class docstring."""
        from mechdyn.parse import ValueTextError, unit_terms
        for key, unit in units.items():
            if not isinstance(unit, str):
                raise DeclarationError(f"mechanism {self.name!r}: the unit of {key} must "
                                       f"be a text such as 'N*m', got {unit!r}")
            try:
                if unit.strip() not in ("", "1"):
                    unit_terms(unit)
            except ValueTextError as error:
                raise DeclarationError(f"mechanism {self.name!r}: unit of {key}: "
                                       f"{error}") from None
            if key in self.coordinates:
                self._check_coordinate_unit(key, unit)
                self.units[key.func.__name__] = unit
            elif isinstance(key, sp.Symbol) and key != t:
                self.parameter_units[key.name] = unit
            else:
                raise DeclarationError(
                    f"mechanism {self.name!r}: units given for {key}, which is neither one "
                    f"of its coordinates {_names(self.coordinates)} nor a parameter symbol")
        self._derived.clear()
        self._memo.clear()
        self._dimensions_checked = False

    def _check_coordinate_unit(self, q, unit):
        """Coordinates are computed in SI (rad, m): a unit of another scale (deg, mm)
        would label radians as degrees, so it is refused."""
        from mechdyn.units import si_factor
        if unit.strip() not in ("", "1") and abs(si_factor(unit) - 1) > 1e-12:
            raise DeclarationError(
                f"mechanism {self.name!r}: coordinate {q.func.__name__} declared in "
                f"{unit!r}: coordinates are computed in SI units (rad, m, 1), so its values "
                f"would not be in {unit}; declare it in an SI unit and show it in {unit} "
                f"with res.summary(units={{'{q.func.__name__}': '{unit}'}}) or plot(units=...)")

    # ----------------------------------------------------------------- declaring
    def add(self, element: Element) -> Element:
        """Add an element (all the declaring methods below come here)."""
        if element.name in self.elements:
            raise DeclarationError(
                f"mechanism {self.name!r}: an element named {element.name!r} exists already "
                f"({type(self.elements[element.name]).__name__.lower()}); names must be unique")
        if element.name == FRAME:
            raise DeclarationError(f"mechanism {self.name!r}: {FRAME!r} names the fixed "
                                   "frame in joints; give the element another name")
        known = self._parameter_names()
        for attribute, expr in checked_expressions(element).items():
            self._check_dependencies(element, attribute, expr)
            check_parameters(_what(element, attribute), expr, known, self.coordinates)
        for index, point in enumerate(getattr(element, "points", ())):
            for axis, expr in zip("xy", point):
                self._check_dependencies(element, f"point {index} {axis}", expr)
        self._check_link_names(element)
        self.elements[element.name] = element
        self._names_seen = (len(self.elements), known)
        self._derived.clear()
        self._memo.clear()
        self._dimensions_checked = False
        return element

    def link(self, name, m=0, J=0, x=0, y=0, angle=0, tags=(), points=()) -> Link:
        """A rigid link: mass ``m`` at ``(x, y)``, inertia ``J`` about its centre of
        mass, rotation ``angle`` (expressions of the coordinates); ``points``, pairs
        ``(x, y)`` of expressions, are what an animation draws (joints, ends)."""
        return self.add(Link(name, m=m, J=J, x=x, y=y, angle=angle, tags=tags,
                             points=points))

    def load(self, name, value, along, efficiency=None, tags=(), on=()) -> Load:
        """A force or moment ``value`` acting along ``along`` (see :class:`Load`);
        ``on``: the link (or two links) it acts on, for joint reactions."""
        return self.add(Load(name, value=value, along=along, efficiency=efficiency,
                             tags=tags, on=on))

    def spring(self, name, k, stretch, tags=()) -> Spring:
        """A linear spring of stiffness ``k`` on ``stretch``."""
        return self.add(Spring(name, k=k, stretch=stretch, tags=tags))

    def damper(self, name, c, stretch, tags=()) -> Damper:
        """A viscous damper of coefficient ``c`` on the rate of ``stretch``."""
        return self.add(Damper(name, c=c, stretch=stretch, tags=tags))

    def gravity(self, g=None, name="gravity", tags=()) -> Gravity:
        """Gravity ``g`` acting along -y on every link; without ``g`` standard gravity,
        9.81 m/s^2 (printed as ``g`` in the derivation)."""
        return self.add(Gravity(name, g=g, tags=tags))

    def friction(self, name, moment, along, peak=1, tags=()) -> Friction:
        """Coulomb friction of magnitude ``moment`` along ``along`` (a brake); at rest
        it holds up to ``peak * moment`` (breakaway, static friction)."""
        return self.add(Friction(name, moment=moment, along=along, peak=peak, tags=tags))

    def loop(self, name, *terms, tags=()) -> Constraint:
        """A closed vector loop ``sum length_i e^(i angle_i) = 0``: two scalar
        constraints (``NAME.x``, ``NAME.y``). Each term is ``(length, angle)``, e.g. a
        four-bar ``(a, phi), (b, theta_2), (-c, theta_3), (-d, 0)``; lengths and angles
        are expressions of the coordinates (a slider's travel is a length)."""
        if len(terms) == 1 and isinstance(terms[0], list):
            terms = tuple(terms[0])
        if len(terms) < 2:
            raise DeclarationError(f"loop {name!r}: a closed loop needs at least two terms "
                                   "(length, angle)")
        return self.add(Constraint(name, terms=tuple(terms), tags=tags))

    def constraint(self, name, g, tags=()) -> Constraint:
        """A holonomic constraint ``g(q, t) = 0`` (one expression, or a list of them)."""
        return self.add(Constraint(name, equations=g, tags=tags))

    def joint(self, name, links, at, kind="revolute", direction=None, tags=()) -> Joint:
        """A joint for kinetostatics: ``links`` (two link names, ``"frame"`` for the
        fixed frame) joined at the point ``at = (x, y)``; ``kind`` ``"revolute"``,
        ``"prismatic"`` (with the slide's angle ``direction``) or ``"weld"``. Its
        reaction is the force the first link exerts on the second."""
        return self.add(Joint(name, links=links, at=at, kind=kind, direction=direction,
                              tags=tags))

    # ---------------------------------------------------------------- closed loops
    @property
    def constraints(self) -> dict:
        """The loops and constraints by name."""
        return {n: e for n, e in self.elements.items() if isinstance(e, Constraint)}

    @property
    def joints(self) -> dict:
        """The joints by name."""
        return {n: e for n, e in self.elements.items() if isinstance(e, Joint)}

    @property
    def independent(self) -> tuple:
        """The independent coordinates.

        All of them without loops; with loops the ones given as ``independent=``, or
        else the first ``n - m``. Checked: ``m`` scalar constraints must leave at
        least one."""
        m = sum(len(c.equations) for c in self.constraints.values())
        n = len(self.coordinates)
        if m >= n:
            raise DeclarationError(
                f"mechanism {self.name!r}: {m} scalar constraints on {n} coordinates "
                f"{_names(self.coordinates)} leave no degree of freedom; declare the "
                "dependent coordinates as coordinates too, or remove a constraint")
        if self._independent is None:
            return self.coordinates[:n - m]
        if len(self._independent) != n - m:
            raise DeclarationError(
                f"mechanism {self.name!r}: {len(self._independent)} independent coordinates "
                f"{_names(self._independent)} but {n} coordinates and {m} scalar "
                f"constraints leave {n - m} degrees of freedom")
        return self._independent

    @property
    def dependent(self) -> tuple:
        """The coordinates the loops determine."""
        chosen = self.independent
        return tuple(q for q in self.coordinates if q not in chosen)

    def _parameter_names(self) -> dict:
        """name -> (parameter symbol, where it is declared) over the elements so far
        (a copy of the names seen at the last ``add``: elements are only ever added, and
        checking them all again at every ``add`` made a 600-element chain take minutes)."""
        seen = getattr(self, "_names_seen", None)
        if seen is None or seen[0] != len(self.elements):
            known = {}
            for element in self.elements.values():
                for attribute, expr in element.expressions().items():
                    check_parameters(_what(element, attribute), expr, known, self.coordinates)
            seen = self._names_seen = (len(self.elements), known)
        return dict(seen[1])

    def _check_link_names(self, element):
        links = {n for n, e in self.elements.items() if isinstance(e, Link)}
        if isinstance(element, Joint):
            names, what = element.links, f"joint {element.name!r}"
        elif isinstance(element, Load):
            names, what = element.on, f"load {element.name!r}: on"
        else:
            return
        for n in names:
            if n != FRAME and n not in links:
                raise DeclarationError(f"{what}: {n!r} is not a link of {self.name!r} "
                                       f"(links: {sorted(links)}, or {FRAME!r}); declare "
                                       "the links first")

    def _check_dependencies(self, element, attribute, expr):
        what = f"{type(element).__name__.lower()} {element.name!r}: {attribute} = {expr}"
        if isinstance(element, Constraint) and attribute in element.labels:
            allowed = "qt"
            if not expr.atoms(AppliedUndef) & set(self.coordinates):
                raise DeclarationError(
                    f"{what}: does not involve the coordinates {_names(self.coordinates)}; "
                    "a constraint must tie coordinates together")
        else:
            allowed = element.DEPENDS.get(attribute, "qt")          # points: like x, y
        coords = set(self.coordinates)
        for d in expr.atoms(sp.Derivative):
            if d not in self._speeds:
                raise DeclarationError(
                    f"{what}: {d} is not the speed of a declared coordinate "
                    f"(declared: {_names(self.coordinates)})")
            if "v" not in allowed:
                raise DeclarationError(f"{what}: may not depend on speeds "
                                       f"(allowed: {_allowed_words(allowed)})")
        bare = expr.subs({d: 0 for d in expr.atoms(sp.Derivative)}) if "v" in allowed else expr
        for f in expr.atoms(AppliedUndef):
            if f not in coords:
                raise DeclarationError(
                    f"{what}: {f} is not a declared coordinate of mechanism {self.name!r} "
                    f"(declared: {_names(self.coordinates)})")
        if "q" not in allowed and bare.atoms(AppliedUndef):
            raise DeclarationError(f"{what}: must be constant, not depend on the coordinates")
        if "t" not in allowed and t in expr.free_symbols:
            raise DeclarationError(f"{what}: must not depend on the time t")
        if attribute in element.MOVING and not (expr.atoms(AppliedUndef) & coords):
            raise DeclarationError(
                f"{what}: does not depend on the coordinates {_names(self.coordinates)}, "
                "so it never moves and does no work")

    # ------------------------------------------------------------------ viewing
    def __repr__(self):
        kinds = {}
        for e in self.elements.values():
            kinds[type(e).__name__.lower()] = kinds.get(type(e).__name__.lower(), 0) + 1
        parts = ", ".join(f"{n} {k}{'s' if n > 1 else ''}" for k, n in kinds.items())
        return f"Mechanism({self.name!r}, coordinates {_names(self.coordinates)}; {parts})"

    def __getstate__(self):
        """Pickled (e.g. for sweep workers) without the caches of derived equations."""
        return {**self.__dict__, "_derived": {}, "_memo": {}}


def _what(element, attribute) -> str:
    return f"{type(element).__name__.lower()} {element.name!r}: {attribute}"


def _names(coordinates):
    return "[" + ", ".join(q.func.__name__ for q in coordinates) + "]"


def _allowed_words(allowed):
    return ", ".join(_WORDS[c] for c in allowed) or "constants only"

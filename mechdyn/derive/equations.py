"""A mechanism's derived equations, remembered per selection of elements, with the
dimension checks that run when parameter units are declared; the reduced quantities and
transmission functions read from them.

>>> import sympy as sp, mechdyn as md
>>> phi = md.coordinate("phi")
>>> J, M = sp.symbols("J M", positive=True)
>>> drive = md.Mechanism("drive", [phi])
>>> _ = drive.link("rotor", J=J, angle=phi)
>>> _ = drive.load("motor", M, along=phi)
>>> reduced_inertia(drive), reduced_moment(drive)
(J, M)
"""
from mechdyn.declare.contract import call
from mechdyn.declare.dimensions import check_elements, check_equations
from mechdyn.declare.scene_units import check_scene
from mechdyn.declare.scene import selection
from mechdyn.derive import transmission
from mechdyn.derive.lagrange import derive, element_works
from mechdyn.errors import SceneError
from mechdyn.keys import content, foreign

__all__ = ["equations", "printed_equations", "foreign_works", "check_dimensions",
           "reduced_inertia", "reduced_moment", "transmission_functions", "element_output"]


def equations(mechanism, scene=None):
    """Lagrange's equations ``M(q) q'' = f(q, q', t)`` (an :class:`Equations`), for all
    elements or for those a :class:`Scene` calls for; derived once per selection, and
    again when an element whose class is defined outside mechdyn now gives another
    :class:`~mechdyn.declare.element_base.Work` (its code may read a module constant)."""
    key = selection(mechanism, scene)
    eqs = mechanism._derived.get(key)
    if eqs is None or any(content(work) != content(eqs.works[name])
                          for name, work in foreign_works(mechanism, scene).items()):
        eqs = derive(mechanism, *key)
        if mechanism.parameter_units:
            check_dimensions(mechanism)
            check_equations(eqs, mechanism)
        mechanism._derived[key] = eqs
    return eqs


def printed_equations(mechanism, scene=None):
    """The equations as the printed derivation writes them: :func:`equations` of the
    elements' printed forms (standard gravity as ``g``, with its value in
    ``named_values``); the same object when no element prints otherwise.

    >>> import sympy as sp, mechdyn as md
    >>> phi = md.coordinate("phi")
    >>> pendulum = md.Mechanism("pendulum", [phi])
    >>> _ = pendulum.link("bob", m=2, y=-sp.cos(phi))
    >>> _ = pendulum.gravity()
    >>> equations(pendulum).potential_energy, printed_equations(pendulum).potential_energy
    (-19.62*cos(phi), -2*g*cos(phi))
    """
    eqs = equations(mechanism, scene)
    key = ("printed",) + selection(mechanism, scene)
    if key not in mechanism._derived:
        if any(call(mechanism.elements[name], "printed")[1] for name in eqs.works):
            printed = derive(mechanism, *key[1:], printed=True)
            mechanism._derived[key] = eqs if not printed.named_values else printed
        else:
            mechanism._derived[key] = eqs
    return mechanism._derived[key]


def foreign_works(mechanism, scene=None) -> dict:
    """``{name: Work}`` of the elements of ``scene`` whose class is defined outside
    mechdyn, evaluated now: what they produce is their part of every key
    (``docs/caching.md``)."""
    names, rigid = selection(mechanism, scene)
    rigid_names = {name for name, _ in rigid}
    chosen = [name for name in names if name not in rigid_names
              and foreign(type(mechanism.elements[name]))]
    return element_works(mechanism, chosen, rigid) if chosen else {}


def check_dimensions(mechanism, scene=None):
    """Check the dimension of every element's contribution to every equation (and, with
    a scene, its stop conditions and initial values); raises a :class:`DeclarationError`
    naming the element and both dimensions."""
    if not mechanism._dimensions_checked:
        check_elements(mechanism)
        mechanism._dimensions_checked = True
    if scene is not None:
        eqs = equations(mechanism, scene)
        if not mechanism.parameter_units:        # equations() checks when units exist
            check_equations(eqs, mechanism)
        check_scene(mechanism, scene)


def reduced_inertia(mechanism, scene=None):
    """The reduced (equivalent) moment of inertia of a one-DOF mechanism; with closed
    loops an expression of the crank angle and the dependent coordinates."""
    eqs = equations(mechanism, scene)
    return transmission.reduced_inertia(eqs) if eqs.constraints else eqs.reduced_inertia


def reduced_moment(mechanism, scene=None):
    """The reduced moment of a one-DOF mechanism (includes gravity and springs)."""
    eqs = equations(mechanism, scene)
    return transmission.reduced_moment(eqs) if eqs.constraints else eqs.reduced_moment


def transmission_functions(mechanism, order=1, scene=None) -> dict:
    """Of a one-DOF linkage: ``dq/dphi`` (``order=1``) or ``d2q/dphi2`` (2, written in
    the first-order ones, ``theta_2'``) of each dependent coordinate, by its plain symbol."""
    eqs = equations(mechanism, scene)
    return transmission.ratios(eqs) if order == 1 else transmission.second_ratios(eqs)


def element_output(eqs, scene_name, name, elements):
    """The force or moment element ``name`` records as an output (its own
    :meth:`~mechdyn.declare.elements.Element.output`), in the plain symbols of ``eqs``."""
    element = elements.get(name) if name in eqs.elements else None
    if element is None:
        raise SceneError(f"scene {scene_name!r}: output {name!r} is not an element of the "
                         f"scene (elements: {list(eqs.elements)})")
    value = call(element, "output", eqs)
    if value is None:
        raise SceneError(f"scene {scene_name!r}: output {name!r}: a "
                         f"{type(element).__name__.lower()} has no single force to record; "
                         "ask for an expression instead")
    return value

"""Closed-form solutions of the one-DOF equation of motion, the five-case classification
and inverse dynamics (the driving moment a prescribed motion needs).

``I_red(phi) eps + 1/2 I_red'(phi) omega^2 = M_red`` integrates in closed form when
``I_red`` is constant and ``M_red`` depends on one of ``t``, ``phi``, ``omega`` (cases 1
and 2), or when ``I_red = I(phi)`` and ``M_red = M(phi)`` (case 3, the energy integral).
Cases 4 and 5 (``M_red`` of ``phi`` and ``omega``, or any other mixed dependence) need
numerical integration (``mech.simulate``). Float parameters become exact rationals
(``0.6 -> 3/5``), so the closed forms are exact. Coulomb friction ``-F sign(omega)`` takes
its sign from the initial speed; the closed form then ends where the sliding does.

>>> import sympy as sp, mechdyn as md
>>> phi = md.coordinate("phi")
>>> brake = md.Mechanism("brake", [phi])
>>> _ = brake.link("disc", J=sp.Symbol("I"), angle=phi)
>>> _ = brake.friction("shoe", 0.8, along=phi)
>>> braking = md.Scene("braking", initial={phi: 0, md.speed(phi): 100}, until=md.stopped(phi))
>>> sol = md.closed_form(brake, braking, {sp.Symbol("I"): 0.4})
>>> sol.classification.case, sol["omega(t)"], sol["phi(t)"]
(1, 100 - 2*t, -t**2 + 100*t)
>>> sol.stop.t, sol.stop.phi
(50, 2500)
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from mechdyn.declare.elements import as_expression
from mechdyn.errors import MechdynError, SceneError
from mechdyn.declare.parameters import ParameterSet
from mechdyn.declare.parameters import exact_floats as _exact
from mechdyn.symbols import t

__all__ = ["AnalyticError", "Classification", "classify"]

_QUAD = {"epsabs": 0.0, "epsrel": 1e-12, "limit": 400}          # relations
_STATS_QUAD = {"epsabs": 1e-12, "epsrel": 1e-12, "limit": 400}   # mean and RMS
_ROLE_WORDS = {"t": "the time", "phi": "the position", "omega": "the speed"}


class AnalyticError(MechdynError, ValueError):
    """A question the closed-form solver cannot answer (several degrees of freedom, a
    case that needs numerical integration, an integral sympy cannot do).

    Examples
    --------
    >>> import mechdyn as md
    >>> x, y = md.coordinates("x y")
    >>> table = md.Mechanism("table", [x, y])
    >>> _ = table.link("slide", m=1, x=x, y=y)
    >>> try:
    ...     md.classify(table)
    ... except md.AnalyticError as error:
    ...     print(type(error).__name__)
    AnalyticError
    """


# ------------------------------------------------------------------- the problem
@dataclass(frozen=True)
class _Problem:
    """A one-DOF machine under a scene, in plain symbols, parameters substituted."""
    name: str
    q: sp.Symbol
    u: sp.Symbol
    inertia: sp.Expr
    moment: sp.Expr
    start: dict          # role -> value: "t", "phi", "omega"
    friction: bool       # a friction sign was fixed from the initial speed

    def role(self, name):
        return {"t": t, "phi": self.q, "omega": self.u}[name]


def _substitution(mech, scene, params):
    """Exact values of the given parameters (keys: symbols or names) by symbol."""
    return ParameterSet(params, mechanism=mech, scene=scene).exact()


def _one_dof(mech, scene, what):
    eqs = mech.equations(scene)
    if eqs.dof != 1:
        names = ", ".join(str(q) for q in eqs.q)
        raise AnalyticError(
            f"{what}: {mech.name!r} has {eqs.dof} coordinates ({names}); closed forms and "
            "the five cases are for one-DOF machines. Simulate it with "
            "mech.simulate(scene, params), or make springs rigid in the scene to reduce it")
    return eqs


def _fix_friction_sign(moment, q, u, direction):
    """Replace ``sign(c u)`` (``c`` free of position, speed and time) by its value while
    sliding in ``direction``."""
    fixed = {}
    for s in moment.atoms(sp.sign):
        ratio = sp.simplify(s.args[0] / u)
        if not ratio.has(u, q, t):
            fixed[s] = sp.sign(ratio) * direction
    return moment.xreplace(fixed), bool(fixed)


def _reduced(mech, scene, params, what, drive=None):
    """Equations, parameter substitution, exact I_red and M_red (without ``drive``)."""
    subs = _substitution(mech, scene, params)              # checked before deriving
    eqs = _one_dof(mech, scene, what)
    moment = eqs.reduced_moment
    if drive is not None:
        left_out = [n for n in eqs.generalized_forces
                    if n == drive or drive in mech.elements[n].tags]
        if not left_out:
            raise AnalyticError(f"{what}: no load named or tagged {drive!r} in "
                                f"{mech.name!r} (loads: {', '.join(eqs.generalized_forces)})")
        moment = moment - sp.Add(*[eqs.generalized_forces[n][0] for n in left_out])
    return (eqs, subs, _exact(eqs.reduced_inertia.xreplace(subs)),
            _exact(moment.xreplace(subs)))


def _problem(mech, scene, params, what):
    eqs, subs, inertia, moment = _reduced(mech, scene, params, what)
    q, u = eqs.q[0], eqs.u[0]
    start = {"t": sp.S.Zero, "phi": sp.S.Zero, "omega": sp.S.Zero}
    direction = sp.S.One
    if scene is not None:
        from mechdyn.declare.scene_units import check_given
        check_given(mech, scene)
        coordinate = eqs.coordinates[0]
        for role, key in (("phi", coordinate), ("omega", sp.Derivative(coordinate, t))):
            if key not in scene.initial:
                raise SceneError(f"scene {scene.name!r} gives no initial value of {key}")
            start[role] = _exact(as_expression(scene.initial[key], f"initial {key}")
                                 .xreplace(subs))
        start["t"] = _exact(sp.Float(scene.t_start))
        direction = sp.sign(start["omega"])
    one_way = [name for name in eqs.switching if name not in
               {f.name for f in eqs.frictions if f.kind == "friction"}]
    if one_way:
        raise AnalyticError(f"{what}: {mech.name!r} has stops or one-way elements "
                            f"({', '.join(one_way)}) whose modes are decided numerically: "
                            "use mech.simulate(scene, params)")
    if direction == 0 and eqs.frictions:
        raise AnalyticError(
            f"{what}: {mech.name!r} starts at rest with friction "
            f"({', '.join(f.name for f in eqs.frictions)}); whether it sticks or slides is "
            "decided numerically: use mech.simulate(scene, params)")
    moment, friction = _fix_friction_sign(moment, q, u, direction)
    return _Problem(mech.name, q, u, inertia, moment, start, friction), eqs


# ------------------------------------------------------------------ classification
@dataclass(frozen=True)
class Classification:
    """Which of the five cases of the one-DOF equation of motion a scene falls in.

    ``case`` 1-5; ``inertia_varies`` (``I_red`` a function of the position);
    ``moment_depends_on``: the roles among ``"t"``, ``"phi"``, ``"omega"`` that
    ``M_red`` depends on; ``closed_form``: cases 1-3; ``description``: in words.

    Examples
    --------
    >>> import sympy as sp, mechdyn as md
    >>> phi = md.coordinate("phi")
    >>> fan = md.Mechanism("fan", [phi])
    >>> _ = fan.link("rotor", J=2, angle=phi)
    >>> _ = fan.load("air", -sp.Symbol("k") * md.speed(phi)**2, along=phi)
    >>> kind = md.classify(fan)
    >>> kind.case, kind.inertia_varies, kind.moment_depends_on, kind.closed_form
    (2, False, ('omega',), True)
    """
    case: int
    inertia_varies: bool
    moment_depends_on: tuple
    closed_form: bool
    description: str

    def __str__(self):
        return self.description


def _classify(problem):
    varies = problem.inertia.has(problem.q)
    roles = tuple(r for r in ("t", "phi", "omega") if problem.moment.has(problem.role(r)))
    if not varies:
        case = {(): 1, ("t",): 2, ("phi",): 2, ("omega",): 2}.get(roles, 4)
    else:
        case = 3 if roles in ((), ("phi",)) else 5
    inertia = (f"I_red a function of the position {problem.q}" if varies
               else "I_red constant")
    moment = ("M_red constant" if not roles else "M_red a function of " + " and ".join(
        f"{_ROLE_WORDS[r]} {problem.role(r)}" for r in roles))
    if len(roles) > 1:
        moment += " (mixed)"
    how = {1: "uniformly accelerated motion, closed form",
           2: "one quadrature, closed form",
           3: "the energy integral, closed form"}.get(
        case, "needs numerical integration (mech.simulate)")
    return Classification(case, varies, roles, case <= 3,
                          f"case {case}: {inertia}, {moment}: {how}")


def classify(mech, scene=None, params=None) -> Classification:
    """Which of the five cases a one-DOF machine (under a scene) falls in.

    Parameters
    ----------
    mech : Mechanism
    scene : Scene, optional
        Selects the effects; its initial speed fixes the sign of Coulomb friction.
    params : dict, optional
        Parameter values (a zero value can remove a dependence).

    Returns
    -------
    Classification

    Examples
    --------
    >>> import sympy as sp, mechdyn as md
    >>> phi = md.coordinate("phi")
    >>> fan = md.Mechanism("fan", [phi])
    >>> _ = fan.link("rotor", J=2, angle=phi)
    >>> _ = fan.load("air", -sp.Symbol("k") * md.speed(phi)**2, along=phi)
    >>> print(md.classify(fan))
    case 2: I_red constant, M_red a function of the speed phidot: one quadrature, closed form
    """
    problem, _ = _problem(mech, scene, params, "classify")
    return _classify(problem)



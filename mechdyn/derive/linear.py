"""Linearisation: state-space matrices ``x' = A x + B w``, ``y = C x + D w`` about an
operating point.

The state is ``x = [q, q']`` (coordinates, then speeds: ``phi, phidot``), the inputs
``w`` are parameters chosen as inputs (a motor moment, a load force), the outputs ``y``
coordinates, speeds, element names (a spring's moment, a load's value) or expressions.
With ``M(q) q'' = f(q, q', t, w)`` and ``a0`` the acceleration at the point,

    A = [[0, I], [-M^-1 d(M a0 - f)/dq, M^-1 df/dq']],   B = [[0], [M^-1 df/dw]],

exact also away from equilibrium (the slope of ``M`` times ``a0`` counts). Coulomb
friction is left out (it does not linearise), as in :func:`mechdyn.natural_frequencies`,
whose poles are the eigenvalues of ``A``.

>>> import sympy as sp, mechdyn as md
>>> x = md.coordinate("x")
>>> m, k, c = sp.symbols("m k c", positive=True)
>>> F = sp.Symbol("F", real=True)
>>> oscillator = md.Mechanism("oscillator", [x])
>>> _ = oscillator.link("mass", m=m, x=x)
>>> _ = oscillator.spring("spring", k, stretch=x)
>>> _ = oscillator.damper("damper", c, stretch=x)
>>> _ = oscillator.load("force", F, along=x)
>>> system = oscillator.linearize(params={m: 2, k: 800, c: 8, F: 0}, inputs=[F],
...                               outputs=["spring"])
>>> system.A, system.B.T, system.C
(array([[   0.,    1.],
       [-400.,   -4.]]), array([[0. , 0.5]]), array([[800.,   0.]]))
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import sympy as sp

from mechdyn.errors import MechdynError, ParameterError
from mechdyn.derive.equations import element_output
from mechdyn.derive.modal import _numeric, _operating_point
from mechdyn.declare.parameters import ParameterSet
from mechdyn.symbols import is_coordinate, plain, t

__all__ = ["StateSpace", "linearize"]


@dataclass(frozen=True)
class StateSpace:
    """``x' = A x + B w``, ``y = C x + D w`` (numpy arrays) with the names of the
    ``states``, ``inputs`` and ``outputs``, the operating point ``x0``, ``w0``.

    Examples
    --------
    >>> import sympy as sp, mechdyn as md
    >>> x = md.coordinate("x")
    >>> F = sp.Symbol("F")
    >>> oscillator = md.Mechanism("oscillator", [x], units={x: "m"})
    >>> _ = oscillator.link("mass", m=2, x=x)
    >>> _ = oscillator.spring("spring", 50, stretch=x)
    >>> _ = oscillator.load("force", F, along=x)
    >>> model = md.linearize(oscillator, params={F: 0}, inputs=[F], outputs=[x])
    >>> model
    <StateSpace: 2 states, 1 inputs, 1 outputs>
    >>> model.states, model.inputs, model.outputs, model.poles
    (('x', 'xdot'), ('F',), ('x',), array([0.+5.j, 0.-5.j]))
    """
    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    states: tuple
    inputs: tuple
    outputs: tuple
    x0: np.ndarray
    w0: np.ndarray

    def __repr__(self):
        return (f"<StateSpace: {len(self.states)} states, {len(self.inputs)} inputs, "
                f"{len(self.outputs)} outputs>")

    @property
    def poles(self) -> np.ndarray:
        """Eigenvalues of ``A``."""
        return np.linalg.eigvals(self.A)

    def frequency_response(self, omega) -> np.ndarray:
        """``C (j omega I - A)^-1 B + D`` at each angular frequency: shape
        ``(len(omega), outputs, inputs)``."""
        eye = np.eye(len(self.A))
        return np.array([self.C @ np.linalg.solve(1j * w * eye - self.A, self.B) + self.D
                         for w in np.atleast_1d(omega)])

    def to_control(self):
        """The same system as a python-control ``StateSpace`` (needs ``control``)."""
        try:
            import control
        except ImportError:
            raise MechdynError("to_control() needs python-control: pip install control "
                               "(or mechdyn[control])") from None
        return control.ss(self.A, self.B, self.C, self.D, states=list(self.states),
                          inputs=list(self.inputs), outputs=list(self.outputs))


def linearize(mechanism, scene=None, at=None, params=None, inputs=(), outputs=()) -> StateSpace:
    """The state-space model of ``mechanism`` (the scene's effects) about ``at``.

    Parameters
    ----------
    mechanism : Mechanism
    scene : Scene, optional
        Selects the effects and rigid springs.
    at : dict, optional
        The operating point: coordinates, speeds (``md.speed(q)``) and ``md.t``; zero
        where not given.
    params : dict
        Values of every parameter; those of the inputs are their operating values.
    inputs : list
        Parameter symbols (or names) that act as inputs.
    outputs : list
        Coordinates, speeds, element names or expressions; default all states.

    Returns
    -------
    StateSpace

    Examples
    --------
    >>> import sympy as sp, mechdyn as md
    >>> x = md.coordinate("x")
    >>> F = sp.Symbol("F")
    >>> oscillator = md.Mechanism("oscillator", [x], units={x: "m"})
    >>> _ = oscillator.link("mass", m=2, x=x)
    >>> _ = oscillator.spring("spring", 50, stretch=x)
    >>> _ = oscillator.load("force", F, along=x)
    >>> model = md.linearize(oscillator, params={F: 0}, inputs=[F], outputs=[x])
    >>> model.A, model.B
    (array([[  0.,   1.],
           [-25.,   0.]]), array([[0. ],
           [0.5]]))
    """
    values = ParameterSet(params, mechanism=mechanism, scene=scene).by_symbol()
    eqs = mechanism.equations(scene)
    q, u = list(eqs.q), list(eqs.u)
    n = len(q)
    point = _operating_point(eqs, at)
    by_name = {s.name: s for s in values}
    symbols = [_input_symbol(w, by_name, eqs) for w in inputs]
    fixed = {s: v for s, v in values.items()}
    forcing = eqs.smooth_forcing
    mass = _numeric(eqs.mass_matrix, point, fixed, "mass", eqs.name)
    f0 = _numeric(forcing, point, fixed, "forcing", eqs.name).reshape(-1)
    a0 = np.linalg.solve(mass, f0)
    acceleration = sp.Matrix(sp.symbols(f"_a0:{n}"))
    residual = eqs.mass_matrix * acceleration - forcing
    at_a0 = {**fixed, **dict(zip(acceleration, a0))}
    dq = _numeric(residual.jacobian(q), point, at_a0, "stiffness", eqs.name)
    du = _numeric(forcing.jacobian(u), point, fixed, "damping", eqs.name)
    dw = (_numeric(forcing.jacobian(symbols), point, fixed, "input", eqs.name)
          if symbols else np.zeros((n, 0)))
    A = np.block([[np.zeros((n, n)), np.eye(n)],
                  [-np.linalg.solve(mass, dq), np.linalg.solve(mass, du)]])
    B = np.vstack([np.zeros((n, len(symbols))), np.linalg.solve(mass, dw)])
    labels, exprs = _outputs(mechanism, eqs, outputs)
    states = q + u
    y = sp.Matrix(exprs)
    C = _numeric(y.jacobian(states), point, fixed, "output", eqs.name) if exprs else \
        np.zeros((0, 2 * n))
    D = (_numeric(y.jacobian(symbols), point, fixed, "output", eqs.name)
         if exprs and symbols else np.zeros((len(exprs), len(symbols))))
    x0 = np.array([point[s] for s in states])
    w0 = np.array([values[s] for s in symbols])
    return StateSpace(A, B, C.reshape(len(exprs), 2 * n), D.reshape(len(exprs), len(symbols)),
                      tuple(map(str, states)), tuple(map(str, symbols)), tuple(labels), x0, w0)


def _input_symbol(w, by_name, eqs):
    name = w.name if isinstance(w, sp.Symbol) else str(w)
    present = {s.name: s for s in eqs.parameters}
    if name not in present:
        raise ParameterError(f"linearize: input {name!r} is not a parameter of the "
                             f"equations ({', '.join(sorted(present))})")
    if name not in by_name:
        raise ParameterError(f"linearize: give the operating value of input {name!r} "
                             "in params")
    return by_name[name]


def _outputs(mechanism, eqs, outputs):
    """Labels and plain expressions of the outputs (all states by default)."""
    if not outputs:
        states = list(eqs.q) + list(eqs.u)
        return [str(s) for s in states], states
    labels, exprs = [], []
    for item in outputs:
        if isinstance(item, str):
            if item not in mechanism.elements:
                raise MechdynError(f"linearize: output {item!r} is not an element of "
                                   f"{mechanism.name!r}")
            expr = element_output(eqs, item, item, mechanism.elements)
            labels.append(item)
        else:
            expr = eqs.to_plain(sp.sympify(item))
            labels.append(str(plain(item)) if _is_state(item) else str(expr))
        if expr.has(sp.sign):
            raise MechdynError(f"linearize: output {item!r} holds Coulomb friction, "
                               "which does not linearise")
        exprs.append(expr)
    return labels, exprs


def _is_state(item):
    return is_coordinate(item) or (isinstance(item, sp.Derivative) and
                                   is_coordinate(item.expr) and item.variable_count == ((t, 1),))

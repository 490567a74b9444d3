"""Linear analysis at an operating point: natural frequencies, mode shapes, damping.

At an operating point ``(q0, u0, t0)`` take the mass matrix ``M = M(q0)`` and the
stiffness ``K``, the Hessian of the potential energy (springs, gravity). The undamped
modes solve ``K phi = omega^2 M phi`` (``scipy.linalg.eigh``); a mode without stiffness
(a drive train turning as a whole) is a rigid-body mode of frequency zero. The equations
``M q'' = f(q, q', t)`` linearised there, with ``C = -df/du`` (dampers, the slope of a
motor characteristic) and ``-df/dq`` (springs and every other position-dependent force),
give the state matrix ``[[0, I], [M^-1 df/dq, M^-1 df/du]]``: its eigenvalues (poles)
are the exact damped behaviour, and each mode's damping ratio comes from its pole. Coulomb friction is left out (it does
not linearise).

>>> import sympy as sp, mechdyn as md
>>> a, b = md.coordinates("a b")
>>> pair = md.Mechanism("two discs", [a, b])
>>> _ = pair.link("disc a", J=1, angle=a)
>>> _ = pair.link("disc b", J=1, angle=b)
>>> _ = pair.spring("shaft", 50, stretch=a - b)
>>> modes = md.natural_frequencies(pair)
>>> modes.omega                  # rad/s: the rigid-body mode, then sqrt(2 k / J)
array([ 0., 10.])
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg
import scipy.optimize
import sympy as sp

from mechdyn.errors import DerivationError, ParameterError
from mechdyn.declare.parameters import ParameterSet, missing_values
from mechdyn.symbols import plain, t

__all__ = ["Modes", "natural_frequencies"]

_RIGID = 1e-9        # omega^2 below this fraction of the largest one counts as zero


@dataclass(frozen=True)
class Modes:
    """The linear modes of a mechanism at an operating point.

    Attributes
    ----------
    coordinates : tuple of str
        Names of the coordinates, the rows of ``shapes`` and of the matrices.
    omega, hz : ndarray
        Undamped natural frequencies in rad/s and Hz, ascending; rigid-body modes are 0.
    shapes : ndarray
        Mode shapes as columns, scaled so the largest component is +1.
    damping_ratios : ndarray or None
        Damping ratio ``-Re s / |s|`` of the state-matrix eigenvalue ``s`` (pole) that
        belongs to each mode (the oscillating pole with ``|s|`` closest to its
        ``omega``); NaN for rigid-body and overdamped modes; None without damping.
    poles : ndarray
        Eigenvalues of the state matrix (exact damped behaviour, 2 per coordinate).
    mass, stiffness, damping : ndarray
        The matrices ``M``, ``K`` (Hessian of the potential energy) and ``C = -df/du``
        at the operating point.

    Examples
    --------
    Two discs on a shaft: a rigid-body mode and ``omega^2 = k (1/J_1 + 1/J_2)``:

    >>> import mechdyn as md
    >>> phi_1, phi_2 = md.coordinates("phi_1 phi_2")
    >>> shaft = md.Mechanism("two discs", [phi_1, phi_2])
    >>> _ = shaft.link("motor", J=1, angle=phi_1)
    >>> _ = shaft.link("load", J=4, angle=phi_2)
    >>> _ = shaft.spring("shaft", 500, stretch=phi_2 - phi_1)
    >>> modes = md.natural_frequencies(shaft)
    >>> modes.omega.round(9), modes.rigid_body_modes
    (array([ 0., 25.]), 1)
    >>> modes.shapes[:, 1]
    array([ 1.  , -0.25])
    """
    coordinates: tuple
    omega: np.ndarray
    hz: np.ndarray
    shapes: np.ndarray
    damping_ratios: np.ndarray | None
    poles: np.ndarray
    mass: np.ndarray
    stiffness: np.ndarray
    damping: np.ndarray

    @property
    def rigid_body_modes(self) -> int:
        """How many modes have zero frequency."""
        return int(np.count_nonzero(self.omega == 0))

    def __repr__(self):
        return (f"<Modes of {', '.join(self.coordinates)}: "
                f"{', '.join(f'{f:.6g}' for f in self.hz[:6])}"
                f"{', ...' if len(self.hz) > 6 else ''} Hz>")


def natural_frequencies(mechanism, scene=None, params=None, at=None) -> Modes:
    """Natural frequencies, mode shapes and damping of ``mechanism`` linearised at an
    operating point.

    Parameters
    ----------
    mechanism : Mechanism
    scene : Scene, optional
        Selects the effects and the rigid springs (as for ``mechanism.equations``).
    params : dict, optional
        Numerical values of every parameter (keys: symbols or names).
    at : dict, optional
        The operating point: coordinates, speeds (``md.speed(q)``) and ``md.t``; those
        not given are zero.

    Returns
    -------
    Modes

    Examples
    --------
    >>> import sympy as sp, mechdyn as md
    >>> x = md.coordinate("x")
    >>> m, k, c = sp.symbols("m k c", positive=True)
    >>> oscillator = md.Mechanism("oscillator", [x])
    >>> _ = oscillator.link("mass", m=m, x=x)
    >>> _ = oscillator.spring("spring", k, stretch=x)
    >>> _ = oscillator.damper("damper", c, stretch=x)
    >>> modes = md.natural_frequencies(oscillator, params={m: 1, k: 400, c: 4})
    >>> modes.omega, modes.damping_ratios
    (array([20.]), array([0.1]))
    """
    values = ParameterSet(params, mechanism=mechanism, scene=scene).by_symbol()
    eqs = mechanism.equations(scene)
    q, u = list(eqs.q), list(eqs.u)
    point = _operating_point(eqs, at)
    forcing = eqs.smooth_forcing
    matrices = {"mass": eqs.mass_matrix,
                "stiffness": sp.hessian(eqs.potential_energy, q),
                "damping": -forcing.jacobian(u),
                "jacobian": -forcing.jacobian(q)}
    mass, stiffness, damping, jacobian = (_numeric(expr, point, values, name, eqs.name)
                                          for name, expr in matrices.items())
    squares, vectors = scipy.linalg.eigh(stiffness, mass)
    scale = np.abs(squares).max(initial=0.0)
    if np.any(squares < -_RIGID * scale):
        raise DerivationError(
            f"{eqs.name!r}: the operating point is unstable (omega^2 = "
            f"{squares.min():.6g} < 0: a mode with negative stiffness)")
    squares = np.where(squares <= _RIGID * scale, 0.0, squares)
    omega = np.sqrt(squares)
    shapes = vectors / _largest(vectors)
    n = len(q)
    state = np.block([[np.zeros((n, n)), np.eye(n)],
                      [-np.linalg.solve(mass, jacobian), -np.linalg.solve(mass, damping)]])
    poles = np.linalg.eigvals(state)
    ratios = _damping_ratios(omega, poles) if np.any(damping) else None
    return Modes(coordinates=tuple(str(s) for s in q), omega=omega, hz=omega / (2 * np.pi),
                 shapes=shapes, damping_ratios=ratios, poles=poles,
                 mass=mass, stiffness=stiffness, damping=damping)


def _operating_point(eqs, at) -> dict:
    """Plain-symbol values of the operating point; coordinates and speeds default to 0."""
    point = {s: 0.0 for s in (*eqs.q, *eqs.u)}
    point[t] = 0.0
    for key, value in (at or {}).items():
        symbol = key if key == t else _plain(key)
        if symbol not in point:
            raise ParameterError(
                f"operating point: {key} is not a coordinate, speed or md.t of "
                f"{eqs.name!r} (kept coordinates: {', '.join(map(str, eqs.q))})")
        point[symbol] = _number(value, f"operating point {key}")
    return point


def _plain(key):
    if isinstance(key, sp.Symbol):
        return key
    try:
        return plain(key)
    except TypeError:
        raise ParameterError(f"operating point: {key!r} is not a coordinate or a speed") \
            from None


def _number(value, what) -> float:
    if isinstance(value, str):
        raise ParameterError(f"{what}: got the string {value!r}; give a number")
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise ParameterError(f"{what}: {value!r} is not a number") from None
    if not np.isfinite(number):
        raise ParameterError(f"{what}: {value!r} is not finite")
    return number


def _numeric(matrix, point, values, what, name) -> np.ndarray:
    """A sympy matrix evaluated at the operating point with the parameter values."""
    numeric = matrix.xreplace(values).xreplace(point)
    missing = set().union(*(e.free_symbols for e in numeric))
    if missing:
        raise missing_values(sorted(map(str, missing)), f"the {what} matrix", name)
    return np.array(numeric.evalf(), dtype=float)


def _damping_ratios(omega, poles) -> np.ndarray:
    """Damping ratio ``-Re s / |s|`` of the oscillating pole matched to each elastic
    mode (closest ``|s|`` to its ``omega``); NaN for rigid-body and overdamped modes."""
    ratios = np.full(omega.shape, np.nan)
    elastic = np.flatnonzero(omega > 0)
    oscillating = poles[poles.imag > 0]
    if elastic.size and oscillating.size:
        cost = np.abs(np.log(np.abs(oscillating)[None, :] / omega[elastic, None]))
        modes, chosen = scipy.optimize.linear_sum_assignment(cost)
        s = oscillating[chosen]
        ratios[elastic[modes]] = -s.real / np.abs(s)
    return ratios


def _largest(vectors) -> np.ndarray:
    """Per column, the component of largest magnitude (with its sign)."""
    rows = np.argmax(np.abs(vectors), axis=0)
    return vectors[rows, np.arange(vectors.shape[1])]

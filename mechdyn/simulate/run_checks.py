"""Checks of a run: its budget, the mass matrix at the start, the state after a chunk,
and the diagnosis of a failure (the text that names why the equations fail there).

>>> Budget(max_steps=10).exceeded(steps=11, elapsed=0.1)
'11 steps exceed the step budget of 10'
"""
from __future__ import annotations

import math

import numpy as np

from mechdyn.compile.generated import SingularMassError
from mechdyn.errors import SimulationError

__all__ = ["Budget", "check_mass", "check_scales", "check_finite", "diagnosis",
           "mass_margin", "check_singular_mass", "state_text"]

# Magnitudes whose squares and products stay far from overflow and underflow (the
# solvers' error norms and Jacobians square them); beyond, a named error, not garbage.
COMFORT = 1e150
_SCALED = {"mass": "the mass matrix (reduced inertia)", "forcing": "the generalized forces",
           "friction_magnitude": "a friction magnitude", "contact_gap": "a stop's gap"}


class Budget:
    """Limits of a run's work: ``max_steps`` accepted steps and ``max_wall_time``
    seconds (None: unbounded)."""

    def __init__(self, max_steps=None, max_wall_time=None):
        self.max_steps, self.max_wall_time = max_steps, max_wall_time

    def exceeded(self, steps, elapsed):
        """What is exceeded, in words, or None."""
        if self.max_steps is not None and steps > self.max_steps:
            return f"{steps} steps exceed the step budget of {self.max_steps}"
        if self.max_wall_time is not None and elapsed > self.max_wall_time:
            return (f"{elapsed:.3g} s of wall time exceed the budget of "
                    f"{self.max_wall_time} s")
        return None


def check_mass(compiled, terms, t, y) -> float:
    """Refuse a start where the mass matrix is not positive definite (on the motions
    closed loops allow); returns the mass matrix's scale (its largest entry)."""
    mass = terms["mass"]
    scale = float(np.max(np.abs(mass), initial=0.0))
    if compiled.constraints:
        from mechdyn.simulate.friction import allowed_motions
        basis = allowed_motions(terms["constraint_gradient"], compiled.dof)
        if not np.all(np.linalg.eigvalsh(basis.T @ mass @ basis) > 0):
            raise SingularMassError(", ".join(compiled.coordinates), t, y)
        return scale
    diagonal = np.diag(mass)
    if np.count_nonzero(mass) == np.count_nonzero(diagonal):   # diagonal: its entries
        if np.all(diagonal > 0):
            return scale
        worst = int(np.argmin(diagonal))
        raise SingularMassError(compiled.coordinates[worst], t, y)
    try:
        np.linalg.cholesky(mass)
    except np.linalg.LinAlgError:
        worst = int(np.argmin(np.diag(mass))) if compiled.dof else 0
        raise SingularMassError(compiled.coordinates[worst], t, y) from None
    return scale


def check_scales(compiled, terms, t, y, name):
    """Refuse a start whose inertias, forces or state lie far outside floating-point
    comfort (beyond ``1e150``, or an inertia below ``1e-150``: accelerations of its
    inverse size): such a run fails in the solvers' linear algebra or ends with a wrong
    answer; other units cure it. (Small forces and states are harmless.)"""
    parts = [(_SCALED[key], np.ravel(terms[key])) for key in _SCALED if key in terms]
    parts.append(("the initial state", np.ravel(y)))
    parts.append(("the start time t", np.array([t])))
    for what, values in parts:
        sizes = np.abs(values[np.isfinite(values) & (values != 0)])
        tiny = what == _SCALED["mass"] and len(sizes) and sizes.max() < 1 / COMFORT
        if len(sizes) and (sizes.max() > COMFORT or tiny):
            worst = sizes.max()
            if what == "the initial state":
                what += f" ({state_text(compiled, y)})"
            raise SimulationError(
                f"scene {name!r}: a value of magnitude {worst:.3g} in {what} at the start "
                f"lies far outside the range floating-point arithmetic handles safely "
                f"({1 / COMFORT:.0e} to {COMFORT:.0e}); state the model in other units "
                "(e.g. mm, g, ms) so its numbers come nearer to 1")


def check_finite(compiled, t, y):
    if not all(map(math.isfinite, np.asarray(y, dtype=float).ravel().tolist())):
        raise SimulationError(f"integration failed at t = {t:.6g} s: the state became "
                              f"non-finite ({state_text(compiled, y)})")


def diagnosis(compiled, p, t, y, mass_scale) -> str:
    """Why the equations fail at a state: an evaluation fault or a mass matrix that is
    (nearly) singular there (a dead centre of the chosen coordinate)."""
    try:
        values = np.asarray(compiled.rhs(t, y, p), dtype=float)
        mass = compiled.terms(t, y, p)["mass"]
        eigenvalues = np.linalg.eigvalsh(mass)
    except (ArithmeticError, ValueError, np.linalg.LinAlgError) as error:
        return (f". The equations cannot be evaluated there: {type(error).__name__}: "
                f"{error}")
    scale = max(abs(eigenvalues[-1]), mass_scale, 1e-300)
    if eigenvalues[0] <= 1e-6 * scale:
        return (f". The mass matrix is nearly singular there (smallest eigenvalue "
                f"{eigenvalues[0]:.3g} of {eigenvalues[-1]:.3g}): the reduced inertia of "
                f"{', '.join(compiled.coordinates)} vanishes at this configuration, a "
                "dead centre of the chosen coordinate")
    if not np.all(np.isfinite(values)):
        return ". The equations give non-finite values there (overflow or division by zero)"
    return ""


def mass_margin(mass, mass_scale) -> tuple:
    """How far the mass matrix is from singular, free of the coordinates' units: the
    smallest eigenvalue of ``M`` scaled to a unit diagonal (with one coordinate: of
    ``M`` against ``mass_scale``, its size at the start), and its eigenvector.

    >>> mass_margin(np.array([[2.0, 2.0], [2.0, 2.0]]), 2.0)[0] < 1e-15
    True
    """
    mass = np.asarray(mass, dtype=float)
    diagonal = np.sqrt(np.maximum(np.diag(mass), 1e-300))
    if len(mass) == 1:
        return float(mass[0, 0] / max(mass_scale, 1e-300)), np.ones(1)
    values, vectors = np.linalg.eigh(mass / np.outer(diagonal, diagonal))
    return float(values[0]), vectors[:, 0]


def check_singular_mass(compiled, p, t, y, mass_scale, floor):
    """Raise :class:`SingularMassError` where the mass matrix at ``(t, y)`` is singular
    to within ``floor`` (:func:`mass_margin`): after a failing method (floor ``eps /
    rtol``: the accelerations there are rounding above the tolerance) no other method
    is tried, since one that steps over the singular position returns numbers past it;
    floor None: raise whatever the margin (the watched margin fell through its floor)."""
    try:
        margin, vector = mass_margin(compiled.terms(t, y, p)["mass"], mass_scale)
    except (ArithmeticError, ValueError, np.linalg.LinAlgError):
        if floor is None:
            raise SingularMassError(", ".join(compiled.coordinates), t, y) from None
        return
    if floor is not None and not margin < floor:
        return
    moving = ", ".join(name for name, c in zip(compiled.coordinates, vector)
                       if abs(c) > 0.1 * np.max(np.abs(vector)))
    error = SingularMassError(moving, t, y)
    error.args = (f"{error}: the mass matrix scaled to a unit diagonal has smallest "
                  f"eigenvalue {margin:.3g} at {state_text(compiled, y)}",)
    raise error


def state_text(compiled, y) -> str:
    return ", ".join(f"{name} = {value:.6g}" for name, value in zip(compiled.state_names, y))

"""Balancing the first harmonic of the shaking force with counterweights.

At a uniform crank speed ``omega`` the shaking force (``-sum m a_S``) of a one-DOF
linkage is periodic in the crank angle. Written as a complex number ``F_x + i F_y``,
its first harmonic is two rotating vectors,

    F_1 = omega^2 (c_plus e^(i phi) + c_minus e^(-i phi)),

one turning with the crank and one against it. A counterweight of mass-radius product
``m r`` on the crank at the angle ``beta`` ahead of the crank angle (at
``r e^(i (phi + beta))`` from the crank's pivot) adds ``omega^2 m r e^(i beta)`` to
``c_plus``, so ``m r e^(i beta) = -c_plus`` cancels the forward part. The backward part
needs a mass on a shaft turning at ``-phi`` (geared 1 : -1 to the crank, Lanchester's
balancer): ``m r e^(i gamma) = -c_minus`` at ``r e^(i (gamma - phi))``. A slider-crank's
textbook values follow: ``c_plus = m_1 r_1 + (m_rot + m_rec / 2) r``, ``c_minus =
m_rec r / 2`` (rod split statically between pin and piston).

>>> import sympy as sp, mechdyn as md
>>> phi = md.coordinate("phi")
>>> yoke = md.Mechanism("Scotch yoke", [phi])
>>> _ = yoke.link("crank", J=1, angle=phi)
>>> _ = yoke.link("yoke", m=2, x=0.1 * sp.cos(phi))
>>> plan = md.balance(yoke, {})
>>> round(plan.crank.mass_radius, 12), round(plan.counter_rotating.mass_radius, 12)
(0.1, 0.1)
>>> round(float(np.degrees(plan.crank.angle)), 6)      # opposite the crank pin
180.0
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mechdyn.analyse.joint_reactions import shaking

__all__ = ["Counterweight", "Balance", "balance"]


@dataclass(frozen=True)
class Counterweight:
    """A counterweight: ``mass_radius`` (kg m) at ``angle`` (rad) ahead of the crank
    angle (for the counter-rotating shaft: at ``angle - phi``).

    Examples
    --------
    >>> import numpy as np, sympy as sp, mechdyn as md
    >>> phi = md.coordinate("phi")
    >>> yoke = md.Mechanism("Scotch yoke", [phi])
    >>> _ = yoke.link("crank", J=1, angle=phi)
    >>> _ = yoke.link("yoke", m=2, x=0.1 * sp.cos(phi))
    >>> plan = md.balance(yoke, {})
    >>> weight = plan.crank
    >>> round(weight.mass_radius, 12), round(float(np.degrees(weight.angle)), 6)
    (0.1, 180.0)
    """
    mass_radius: float
    angle: float

    def mass(self, radius) -> float:
        """The mass that gives this product at ``radius``."""
        return self.mass_radius / radius

    def __str__(self):
        return f"m r = {self.mass_radius:.6g} kg m at {np.degrees(self.angle):.4g} deg"


@dataclass(frozen=True)
class Balance:
    """The first harmonic of the shaking force per ``omega^2`` (``forward``,
    ``backward``: complex amplitudes ``c_plus``, ``c_minus``, in kg m), the
    counterweights that cancel them (``crank``, ``counter_rotating``), and the
    amplitude of every harmonic (``harmonics[k]``, kg m per ``omega^2``).

    Examples
    --------
    >>> import numpy as np, sympy as sp, mechdyn as md
    >>> phi = md.coordinate("phi")
    >>> yoke = md.Mechanism("Scotch yoke", [phi])
    >>> _ = yoke.link("crank", J=1, angle=phi)
    >>> _ = yoke.link("yoke", m=2, x=0.1 * sp.cos(phi))
    >>> plan = md.balance(yoke, {})
    >>> np.round([plan.forward.real, plan.backward.real], 12)   # c_plus = c_minus = m r / 2
    array([0.1, 0.1])
    >>> np.round([plan.forward.imag, plan.backward.imag], 12) + 0.0
    array([0., 0.])
    >>> plan.harmonics[1:3].round(12)                   # first harmonic only
    array([0.2, 0. ])
    """
    forward: complex
    backward: complex
    crank: Counterweight
    counter_rotating: Counterweight
    harmonics: np.ndarray

    def __str__(self):
        return (f"first harmonic of the shaking force: forward {abs(self.forward):.6g}, "
                f"backward {abs(self.backward):.6g} kg m (times omega^2); crank "
                f"counterweight {self.crank}; counter-rotating {self.counter_rotating}")


def _weight(amplitude: complex) -> Counterweight:
    return Counterweight(float(abs(amplitude)), float(np.angle(-amplitude)) % (2 * np.pi))


def balance(mech, params, scene=None, guess=None, points=256, start=0.0) -> Balance:
    """Counterweights cancelling the first harmonic of the shaking force of a one-DOF
    mechanism turning uniformly (crank angle from ``start`` over a revolution).

    Returns
    -------
    Balance

    Examples
    --------
    A Scotch yoke's 2 kg slide on a 0.1 m crank shakes with ``m r omega^2 cos(phi)``
    along x: half turns with the crank, half against it:

    >>> import numpy as np, sympy as sp, mechdyn as md
    >>> phi = md.coordinate("phi")
    >>> yoke = md.Mechanism("Scotch yoke", [phi])
    >>> _ = yoke.link("crank", J=1, angle=phi)
    >>> _ = yoke.link("yoke", m=2, x=0.1 * sp.cos(phi))
    >>> plan = md.balance(yoke, {})
    >>> round(plan.crank.mass_radius, 12), round(plan.counter_rotating.mass_radius, 12)
    (0.1, 0.1)
    """
    phi = start + 2 * np.pi * np.arange(points) / points
    force, _ = shaking(mech, params, phi, omega=1.0, scene=scene, guess=guess)
    complex_force = force[0] + 1j * force[1]
    forward = np.mean(complex_force * np.exp(-1j * phi))
    backward = np.mean(complex_force * np.exp(1j * phi))
    spectrum = np.abs(np.fft.fft(complex_force)) / points
    harmonics = spectrum[:points // 2] + np.r_[0.0, spectrum[:-(points // 2):-1]]
    return Balance(complex(forward), complex(backward), _weight(forward), _weight(backward),
                   harmonics)

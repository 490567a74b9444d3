"""scipy's explicit Runge-Kutta solvers with the error control of mechdyn's kernels.

Three changes to how scipy's ``RK45``, ``RK23`` and ``DOP853`` judge a step, so that the
accuracy asked for is the accuracy delivered (docs/hard-cases.md, "What the tolerance
means"):

- **Revolving coordinates** (the equations repeat after a turn of 2 pi: the angle enters
  only through sines and cosines) are weighed on the scale of one revolution,
  ``atol + rtol min(|y|, 2 pi)``, not relative to their size: a crank angle that has
  grown to 500 rad would otherwise be allowed 80 times the phase error per step.
- **A blind estimate does not grow the step.** The embedded estimate vanishes where the
  local error changes sign (once a revolution when one state carries it); an estimate
  more than 100 times below the last trusted one keeps the step (as the kernels'
  ``blind_guard``, :mod:`mechdyn.kernels.dop853`).
- **DOP853's blended estimate is floored** at ``ERROR_FLOOR`` times its 5th-order part:
  Hairer's ``err5^2 / sqrt(err5^2 + 0.01 err3^2)`` falls far below ``err5`` when the
  3rd-order estimate is large, and on the slider-crank it accepted steps 10 times over
  the tolerance (the global error at rtol 1e-10 exceeded the one at 1e-9).

>>> import numpy as np
>>> solver = guarded("DOP853")(lambda t, y: [y[1], -np.sin(y[0])], 0.0, [0.0, 3.0], 50.0,
...                            rtol=1e-8, atol=1e-10, revolving=[0])
>>> while solver.status == "running":
...     _ = solver.step()
>>> round(float(solver.t), 6), bool(solver.y[0] > 60)             # it went over the top
(50.0, True)
"""
from __future__ import annotations

import numpy as np
from scipy.integrate import DOP853, RK23, RK45

from mechdyn.errors import DependencyError

__all__ = ["guarded", "ERROR_FLOOR", "BLIND_DROP", "REVOLUTION"]

ERROR_FLOOR = 0.1            # DOP853's estimate is at least this part of its 5th-order one
BLIND_DROP = 1e-2            # an estimate this far below the last trusted one is blind
_TRUST_DECAY = 0.1           # ... and the trusted value decays (a real fall shows)
REVOLUTION = 2 * np.pi


# scipy has no public hook for a step's error norm: ``RungeKutta._estimate_error_norm(K,
# h, scale)``, called by ``_step_impl`` on every step, and the fields it reads (``atol``,
# ``rtol``, ``error_estimator_order``, DOP853's ``E5``) are its internals. A scipy that
# renamed the method would quietly skip the override (the steps taken with scipy's own
# control), so each class is checked once, when first used, and a missing name is a
# DependencyError; tests/test_third_party_internals.py pins that the override is called.
_HOOK = "_estimate_error_norm"
_FIELDS = ("atol", "rtol", "error_estimator_order")
_CHECKED = set()


def _check_internals(solver):
    cls = type(solver)
    if cls in _CHECKED:
        return
    if not callable(getattr(super(_Guarded, solver), _HOOK, None)):
        raise DependencyError("scipy", f"{cls.__mro__[2].__name__}.{_HOOK}",
                              "mechdyn's error control of the explicit methods")
    for name in _FIELDS + (("E5",) if isinstance(solver, DOP853) else ()):
        if not hasattr(solver, name):
            raise DependencyError("scipy", f"{cls.__mro__[2].__name__}.{name}",
                                  "mechdyn's error control of the explicit methods")
    _CHECKED.add(cls)


class _Guarded:
    """The changed error norm, mixed into a scipy RK solver class."""

    def __init__(self, fun, t0, y0, t_bound, revolving=(), **options):
        super().__init__(fun, t0, y0, t_bound, **options)
        _check_internals(self)
        self.revolving = np.asarray(revolving, dtype=int)
        self.trusted = 0.0
        # a step kept as it is: SAFETY * norm ** (-1 / (order + 1)) = 1
        self.kept = 0.9 ** (self.error_estimator_order + 1)

    def _estimate_error_norm(self, K, h, scale):
        if self.revolving.size:
            scale = scale.copy()
            atol = np.broadcast_to(self.atol, scale.shape)[self.revolving]
            scale[self.revolving] = np.minimum(scale[self.revolving],
                                               atol + self.rtol * REVOLUTION)
        norm = self._norm(K, h, scale)
        if norm < 1:                                   # accepted: is it blind?
            if self.trusted > 0 and norm < BLIND_DROP * self.trusted:
                self.trusted *= _TRUST_DECAY
                return max(norm, self.kept)
            self.trusted = norm
        return norm

    def _norm(self, K, h, scale):
        return super()._estimate_error_norm(K, h, scale)


class _GuardedDOP853(_Guarded, DOP853):
    def _norm(self, K, h, scale):
        blended = super()._norm(K, h, scale)
        fifth = np.linalg.norm(np.dot(K.T, self.E5) / scale) / np.sqrt(scale.size)
        return max(blended, ERROR_FLOOR * abs(h) * fifth)


class _GuardedRK45(_Guarded, RK45):
    pass


class _GuardedRK23(_Guarded, RK23):
    pass


_CLASSES = {"DOP853": _GuardedDOP853, "RK45": _GuardedRK45, "RK23": _GuardedRK23}


def guarded(method):
    """The solver class for an explicit ``method`` ("DOP853", "RK45", "RK23"); it takes
    ``revolving``: the indices of the states weighed on one revolution."""
    return _CLASSES[method]

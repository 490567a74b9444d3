"""The mesh loss of a lossy gear (MSL ``LossyGear``), as a function of the moment the
input side passes into the gear.

With ``tau`` that moment (MSL's ``flange_a.tau``) and the gear turning forward, the loss
moment is ``L(tau) = max(q1(tau), q2(tau))`` with ``q1 = (1 - eta_forward) tau +
bearing_forward`` (the input drives) and ``q2 = (1 - 1/eta_backward) tau +
bearing_backward`` (the output drives). The two lines meet at MSL's ``tau_bf_a``, so the
larger one is exactly MSL's quadrant choice; ``L`` is convex and never negative. Turning
backward the loss is ``-L(-tau)``. At rest the gear holds while the loss moment ``l`` it
needs satisfies ``-L(-tau) <= l <= L(tau)`` (the laws at zero speed, MSL's
``tauLossMin_m``, ``tauLossMax_p``). A backward efficiency of 0 or less has no line q2:
``L`` is infinite where the output would drive (``tau < 0``): the gear is self-locking.

>>> law = LossLaw(0.5, 0.5, 0.0, 0.0)
>>> law.loss(10.0), law.loss(-10.0)       # input drives: 50 %; output drives: 1/0.5 - 1
(5.0, 10.0)
>>> LossLaw(0.4, 0.0, 0.0, 0.0).loss(-1.0)  # self-locking: the output cannot drive
inf
"""
from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["LossLaw"]


@dataclass(frozen=True)
class LossLaw:
    """The loss law of one gear at one state: efficiencies and bearing moments."""
    eta_forward: float
    eta_backward: float
    bearing_forward: float
    bearing_backward: float

    @property
    def self_locking(self) -> bool:
        return self.eta_backward <= 0

    def lines(self) -> list:
        """``(slope, offset)`` of the lines whose maximum is ``L``: q1, then q2 (absent
        for a self-locking gear)."""
        out = [(1 - self.eta_forward, self.bearing_forward)]
        if not self.self_locking:
            out.append((1 - 1 / self.eta_backward, self.bearing_backward))
        return out

    def loss(self, x, tolerance=0.0) -> float:
        """``L(x)``: infinite for a self-locking gear at ``x <= tolerance`` below its
        corner (the output drives, or balances exactly)."""
        if self.self_locking and x <= tolerance:
            return math.inf
        return max(slope * x + offset for slope, offset in self.lines())

    def piece(self, x, tolerance=0.0) -> int:
        """The line that gives ``L(x)``: 0 (q1) or 1 (q2, or the self-locking corner)."""
        if self.self_locking:
            return 1 if x <= tolerance else 0
        (s1, o1), (s2, o2) = self.lines()
        return 0 if s1 * x + o1 >= s2 * x + o2 else 1

    def holding_interval(self, tau, tolerance=0.0) -> tuple:
        """The interval of the gear's holding force along ``ratio * output`` (minus the
        loss moment) at rest: ``[-L(tau), L(-tau)]``."""
        return -self.loss(tau, tolerance), self.loss(-tau, tolerance)

"""The results and the error of the linkage analyses (:class:`~mechdyn.analyse.linkage.Linkage`
and its helper modules): a crank sweep, a special position, Grashof's classification.

>>> str(grashof(3, 1, 3, 2.5))
'crank-rocker (ground 3, crank 1, coupler 3, rocker 2.5; shortest: crank)'
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mechdyn.errors import MechdynError
from mechdyn.symbols import is_coordinate

__all__ = ["LinkageError", "CrankSweep", "Singularity", "Grashof", "grashof"]


class LinkageError(MechdynError, ValueError):
    """A linkage that cannot be analysed as asked: not assembled at a crank angle, no
    loops, a four-bar question to another linkage. ``at``: the crank angle, if any.

    Examples
    --------
    >>> import numpy as np, mechdyn as md
    >>> phi, th2, th3 = md.coordinates("phi theta_2 theta_3")
    >>> rocker = md.Mechanism("triple rocker", [phi, th2, th3])
    >>> _ = rocker.link("crank", J=1, angle=phi)
    >>> _ = rocker.link("coupler", J=1, angle=th2)
    >>> _ = rocker.link("rocker", J=1, angle=th3)
    >>> _ = rocker.loop("ABCD", (3, phi), (3.5, th2), (-5, th3), (-2, 0))
    >>> linkage = md.Linkage(rocker, guess={th2: 0.5, th3: 1}, guess_at=1.0)
    >>> try:
    ...     linkage.position(0.0)                     # beyond the toggle at 0.46 rad
    ... except md.LinkageError as error:
    ...     print(type(error).__name__, error.at)
    LinkageError 0.0
    """

    def __init__(self, message, at=None):
        super().__init__(message)
        self.at = at


@dataclass(frozen=True)
class CrankSweep:
    """Kinematics along the independent coordinate (one-DOF linkages): ``phi`` (N),
    ``q``, ``ratio`` (``dq/dphi``), ``second`` (``d2q/dphi2``), one row per coordinate
    (``names``); ``inertia`` (``I_red``) and ``inertia_slope`` (``dI_red/dphi``).

    Examples
    --------
    >>> import mechdyn as md
    >>> phi, th2, th3 = md.coordinates("phi theta_2 theta_3")
    >>> four = md.Mechanism("four-bar", [phi, th2, th3])
    >>> _ = four.link("crank", J=1, angle=phi)
    >>> _ = four.link("coupler", J=1, angle=th2)
    >>> _ = four.link("rocker", J=1, angle=th3)
    >>> _ = four.loop("ABCD", (1, phi), (3, th2), (-2.5, th3), (-3, 0))
    >>> linkage = md.Linkage(four, guess={th2: 1, th3: 2})
    >>> import numpy as np
    >>> along = linkage.sweep(np.array([0.0, np.pi]))
    >>> along.names, along.ratio[:, 0].round(6)      # dq/dphi at phi = 0
    (('phi', 'theta_2', 'theta_3'), array([ 1. , -0.5, -0.5]))
    >>> along.inertia.round(6)                       # 1 + 0.5^2 + 0.5^2 at phi = 0
    array([1.5  , 1.125])
    """
    phi: np.ndarray
    q: np.ndarray
    ratio: np.ndarray
    second: np.ndarray
    inertia: np.ndarray
    inertia_slope: np.ndarray
    names: tuple

    def __getitem__(self, name):
        """Positions of a coordinate by name or coordinate: ``sweep["theta_2"]``."""
        return self.q[self._row(name)]

    def _row(self, name):
        key = name.func.__name__ if is_coordinate(name) else str(name)
        if key not in self.names:
            raise KeyError(f"{name!r}: not a coordinate ({', '.join(self.names)})")
        return self.names.index(key)


@dataclass(frozen=True)
class Singularity:
    """A special position of a linkage: ``kind`` ("toggle": the loop locks the
    dependent coordinates, the crank cannot pass; "change point": the constraints
    themselves lose rank), the ``loop`` that locks, the crank angle ``at``.

    Examples
    --------
    A triple rocker (ground 2, crank 3, coupler 3.5, rocker 5): its crank stops where
    coupler and rocker fold, ``|B - D| = 5 - 3.5``, at ``cos(phi) = (9 + 4 - 1.5^2) / 12``:

    >>> import numpy as np, mechdyn as md
    >>> phi, th2, th3 = md.coordinates("phi theta_2 theta_3")
    >>> rocker = md.Mechanism("triple rocker", [phi, th2, th3])
    >>> _ = rocker.link("crank", J=1, angle=phi)
    >>> _ = rocker.link("coupler", J=1, angle=th2)
    >>> _ = rocker.link("rocker", J=1, angle=th3)
    >>> _ = rocker.loop("ABCD", (3, phi), (3.5, th2), (-5, th3), (-2, 0))
    >>> linkage = md.Linkage(rocker, guess={th2: 0.5, th3: 1}, guess_at=1.0)
    >>> toggles = linkage.singularities()
    >>> [(s.kind, s.loop) for s in toggles]
    [('toggle', 'ABCD'), ('toggle', 'ABCD')]
    >>> round(toggles[0].at, 6), round(float(np.arccos(43 / 48)), 6)
    (0.460493, 0.460493)
    """
    kind: str
    loop: str
    at: float
    coordinate: str

    def __str__(self):
        return (f"{self.kind} of loop {self.loop} at {self.coordinate} = {self.at:.9g} rad "
                f"({np.degrees(self.at):.4f} deg)")


@dataclass(frozen=True)
class Grashof:
    """Grashof's classification of a four-bar: ``kind`` in words ("crank-rocker",
    "double-crank (drag link)", "double-rocker (Grashof)", "rocker-crank",
    "triple-rocker (non-Grashof)"; at s + l = p + q: "parallelogram",
    "anti-parallelogram" (the branch, from a linkage), "deltoid (kite)" or e.g.
    "crank-rocker with change points"), ``grashof`` (s + l
    <= p + q: some link turns fully), ``change_point`` (s + l = p + q), the link lengths
    ``shortest``, ``longest`` and which link is shortest, ``crank_turns`` (the input link
    makes full turns).

    Examples
    --------
    >>> import mechdyn as md
    >>> four = md.grashof(ground=3, crank=1, coupler=3, rocker=2.5)   # s + l = 4 < p + q = 5.5
    >>> four.kind, four.grashof, four.crank_turns, four.shortest
    ('crank-rocker', True, True, 'crank')
    """
    kind: str
    grashof: bool
    change_point: bool
    shortest: str
    lengths: dict
    crank_turns: bool

    def __str__(self):
        values = ", ".join(f"{k} {v:.6g}" for k, v in self.lengths.items())
        return f"{self.kind} ({values}; shortest: {self.shortest})"


def grashof(ground, crank, coupler, rocker, tolerance=1e-12) -> Grashof:
    """Classify a four-bar by its link lengths (Grashof's criterion).

    Examples
    --------
    >>> str(grashof(3, 1, 3, 2.5))
    'crank-rocker (ground 3, crank 1, coupler 3, rocker 2.5; shortest: crank)'
    >>> grashof(2, 3, 3.5, 5).kind
    'triple-rocker (non-Grashof)'
    >>> grashof(3, 1, 3, 1).kind, grashof(3, 3, 1, 1).kind    # s + l = p + q
    ('parallelogram or anti-parallelogram', 'deltoid (kite)')
    """
    lengths = {"ground": abs(float(ground)), "crank": abs(float(crank)),
               "coupler": abs(float(coupler)), "rocker": abs(float(rocker))}
    if min(lengths.values()) <= 0:
        raise LinkageError(f"four-bar link lengths must be positive, got {lengths}")
    ordered = sorted(lengths.values())
    excess = ordered[0] + ordered[3] - ordered[1] - ordered[2]
    shortest = min(lengths, key=lengths.get)
    change = abs(excess) <= tolerance * ordered[3]
    if excess > 0 and not change:
        return Grashof("triple-rocker (non-Grashof)", False, False, shortest, lengths, False)
    kind = {"ground": "double-crank (drag link)", "crank": "crank-rocker",
            "coupler": "double-rocker (Grashof)", "rocker": "rocker-crank"}[shortest]
    if change:
        near = lambda x, y: abs(lengths[x] - lengths[y]) <= tolerance * ordered[3]  # noqa
        kind = ("parallelogram or anti-parallelogram" if near("crank", "rocker") and
                near("coupler", "ground") else "deltoid (kite)" if
                (near("crank", "coupler") and near("rocker", "ground")) or
                (near("crank", "ground") and near("coupler", "rocker")) else
                f"{kind} with change points")
    return Grashof(kind, True, change, shortest, lengths, shortest in ("ground", "crank"))

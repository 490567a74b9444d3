"""A chain of discs on stiff, lightly damped shafts (issue 39's model) at the defaults.

Its fast modes are oscillations (k = 1e6 N m/rad, c = 5 N m s/rad: damping ratio about
4 %), which the explicit method must resolve at rtol 1e-8 and the stiff method steps over
no faster: the default run must end where a tight reference does, to the tolerance asked
(``|y - y_ref| <= atol + rtol |y_ref|`` per state). The reference: the same equations
written by hand (``J_i phi_i'' = the shafts' moments``), integrated by scipy's DOP853 at
rtol 1e-13. Before the kernel weighed what a stiff step buys (issue 39), the run switched
to Rodas5P and ended 18 tolerances off in speed.
"""
import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp

import mechdyn as md

K, C, DRIVE, LOAD = 1e6, 5.0, 5.0, 0.02
RTOL, ATOL = 1e-8, 1e-10


def inertias(n):
    return np.array([0.01 * (1 + i % 3) for i in range(n)])


def chain(n):
    phi = md.coordinates(" ".join(f"phi{i}" for i in range(n)))
    k, c, drive, load = sp.symbols("k c M b", positive=True)
    mech = md.Mechanism(f"{n} discs", phi)
    for i, inertia in enumerate(inertias(n)):
        mech.link(f"disc {i}", J=float(inertia), angle=phi[i])
    for i in range(1, n):
        mech.spring(f"shaft {i}", k, stretch=phi[i] - phi[i - 1])
        mech.damper(f"damper {i}", c, stretch=phi[i] - phi[i - 1])
    mech.load("drive", drive, along=phi[0])
    mech.load("load", -load * md.speed(phi[-1]), along=phi[-1])
    scene = md.Scene("start", initial={**{q: 0 for q in phi},
                                       **{md.speed(q): 0 for q in phi}},
                     t_end=1.0, rtol=RTOL, atol=ATOL)
    return mech, scene, {"k": K, "c": C, "M": DRIVE, "b": LOAD}, phi


def by_hand(n):
    inertia = inertias(n)

    def rhs(t, y):
        q, u = y[:n], y[n:]
        shaft = K * np.diff(q) + C * np.diff(u)           # shaft i joins discs i-1 and i
        moment = np.zeros(n)
        moment[:-1] += shaft
        moment[1:] -= shaft
        moment[0] += DRIVE
        moment[-1] -= LOAD * u[-1]
        return np.concatenate([u, moment / inertia])
    return rhs


@pytest.mark.slow
def test_the_stiff_chain_ends_where_a_tight_reference_does_at_the_defaults():
    n = 40
    mech, scene, values, _ = chain(n)
    result = mech.simulate(scene, values)
    reference = solve_ivp(by_hand(n), (0.0, 1.0), np.zeros(2 * n), method="DOP853",
                          rtol=1e-13, atol=1e-14).y[:, -1]
    end = np.array([result[name][-1] for name in result.state_names])   # q, then q'
    allowed = ATOL + RTOL * np.abs(reference)
    worst = np.argmax(np.abs(end - reference) / allowed)
    assert abs(end[worst] - reference[worst]) <= allowed[worst], (
        f"state {worst}: {end[worst]!r} against {reference[worst]!r}; "
        f"methods {result.stats['methods']}")

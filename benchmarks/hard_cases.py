"""The hard cases of simulation, each with a reference computed independently.

Each case is a function returning a :class:`Case`: the mechanism, the scene (default
tolerances unless the case is about tolerances), the parameters, and ``error(result)``,
the largest deviation from a reference that does not come from mechdyn's integrator
(a closed form, a matrix exponential, an energy balance, or a published reference).

Used by ``hard_case_matrix.py`` (each case x each method x a few tolerances).
"""
from __future__ import annotations

import csv
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np
import sympy as sp
from scipy.integrate import quad
from scipy.linalg import expm
from scipy.optimize import brentq

import mechdyn as md

ROOT = Path(__file__).resolve().parent.parent


@dataclass
class Case:
    name: str
    mechanism: md.Mechanism
    scene: md.Scene
    params: dict
    error: Callable            # result -> float (deviation from the reference)
    what: str                  # what the error measures
    bound: float               # the acceptance bound of the error
    expect_failure: bool = False
    notes: list = field(default_factory=list)


# ----------------------------------------------------------------- linear references
def _linear_solution(A, b, x0, times):
    """x(t) of x' = A x + b from x0, exactly, by the matrix exponential of the
    augmented system [[A, b], [0, 0]]."""
    n = len(x0)
    augmented = np.zeros((n + 1, n + 1))
    augmented[:n, :n], augmented[:n, n] = A, b
    start = np.append(x0, 1.0)
    return np.array([(expm(augmented * t) @ start)[:n] for t in times]).T


def _two_mass(J1, J2, k, c, M, name):
    phi1, phi2 = md.coordinates("phi_1 phi_2")
    mech = md.Mechanism(name, [phi1, phi2])
    mech.link("motor", J=J1, angle=phi1)
    mech.link("load", J=J2, angle=phi2)
    mech.spring("shaft", k, stretch=phi1 - phi2)
    if c:
        mech.damper("shaft damping", c, stretch=phi1 - phi2)
    mech.load("motor moment", M, along=phi1)
    return mech, phi1, phi2


def _two_mass_matrix(J1, J2, k, c, M):
    A = np.array([[0, 0, 1, 0], [0, 0, 0, 1],
                  [-k / J1, k / J1, -c / J1, c / J1], [k / J2, -k / J2, c / J2, -c / J2]])
    return A, np.array([0, 0, M / J1, 0])


def stiff_damped_pair(rtol=None):
    """k = 1e6 N m/rad between J1 = 1 and J2 = 1e-4 kg m^2, damping ratio 0.1, a sudden
    moment 20 N m: reference the exact linear solution (matrix exponential)."""
    J1, J2, k, M = 1.0, 1e-4, 1e6, 20.0
    c = 2 * 0.1 * math.sqrt(k * J1 * J2 / (J1 + J2))
    mech, phi1, phi2 = _two_mass(J1, J2, k, c, M, "stiff damped pair")
    scene = _scene("start", [phi1, phi2], 1.0, rtol)
    A, b = _two_mass_matrix(J1, J2, k, c, M)
    times = np.linspace(0, 1, 101)
    exact = _linear_solution(A, b, np.zeros(4), times)

    def error(res):
        return float(np.max(np.abs(res.at(times)["phi_1"] - exact[0])))
    return Case("stiff damped pair", mech, scene, {}, error, "max |phi_1 - exact| (rad)",
                1e-6)


def stiff_undamped_pair(rtol=None):
    """The same pair without damping: T + V must equal the work of the motor moment."""
    J1, J2, k, M = 1.0, 1e-4, 1e6, 20.0
    mech, phi1, phi2 = _two_mass(J1, J2, k, 0.0, M, "stiff undamped pair")
    scene = _scene("start", [phi1, phi2], 1.0, rtol)

    def error(res):
        T, V = res.energy()
        work = M * res["phi_1"]
        return float(np.max(np.abs(T + V - work)) / np.max(np.abs(work)))
    return Case("stiff undamped pair", mech, scene, {}, error, "|T + V - W| / W", 1e-6)


def late_coupling(rtol=None):
    """A stiff damped coupling (k = 1e6, c = 50) between a motor (1 kg m^2, 10 N m) and a
    load (1e-3 kg m^2) engages at t = 0.5 s (a Piecewise in time), relaxed at engagement:
    momentum balance gives both speeds M t / (J1 + J2) once the coupling has settled."""
    J1, J2, k, c, M, t_on = 1.0, 1e-3, 1e6, 50.0, 10.0, 0.5
    phi1, phi2 = md.coordinates("phi_1 phi_2")
    mech = md.Mechanism("late coupling", [phi1, phi2])
    mech.link("motor", J=J1, angle=phi1)
    mech.link("load", J=J2, angle=phi2)
    mech.load("motor moment", M, along=phi1)
    twist = phi1 - phi2 - M * t_on**2 / (2 * J1)          # relaxed when it engages
    engaged = sp.Piecewise((0, md.t < t_on), (1, True))
    coupling = -engaged * (k * twist + c * (md.speed(phi1) - md.speed(phi2)))
    mech.load("coupling", coupling, along=phi1 - phi2)
    scene = _scene("start", [phi1, phi2], 1.0, rtol)

    def error(res):
        final = M * 1.0 / (J1 + J2)
        return max(abs(res.final(md.speed(phi1)) - final),
                   abs(res.final(md.speed(phi2)) - final))
    return Case("late coupling", mech, scene, {}, error, "|omega - M t/(J1+J2)| (rad/s)",
                1e-5)


def preload_spool(rtol=None):
    """MSL Translational.Examples.PreLoad: a spool held between two spring plates by four
    elasto-gap contacts (c = 1e6 N/m, d = 250 N s/m), a preload spring, a viscous
    damper, a slow sine force; 100 s. Reference: the MSL result (Dymola, DASSL 1e-6)."""
    s, a, b = md.coordinates("s_spool s_A s_B")
    mech = md.Mechanism("preload spool", [s, a, b], units={s: "m", a: "m", b: "m"})
    mech.link("spool", m=0.150, x=s)
    mech.link("spring plate A", m=10e-3, x=a)
    mech.link("spring plate B", m=10e-3, x=b)
    mech.spring("spring", 20e3, stretch=b - a - 0.002 - 0.025)
    mech.damper("friction", 2500, stretch=s)
    mech.load("force", 150 * sp.sin(2 * sp.pi * 0.01 * md.t), along=s)
    gaps = {"innerContactA": (a + 0.008) - (s - 0.10075),
            "innerContactB": (s - 0.08925) - (b - 0.008),
            "outerContactA": a - 0.001 + 0.0955,
            "outerContactB": -0.066 - b}
    opening = {"innerContactA": 0.001, "innerContactB": 0.001,
               "outerContactA": 0.0015, "outerContactB": 0.0015}
    for name, gap in gaps.items():
        mech.load(name, _elasto_gap(gap, opening[name], 1e6, 250.0), along=gap)
    initial = {s: 0.01475, a: -0.093, b: -0.06925}
    initial.update({md.speed(q): 0 for q in (s, a, b)})
    scene = md.Scene("sine force", initial=initial, t_end=100.0,
                     **({"rtol": rtol, "atol": rtol * 1e-2} if rtol else {}))
    reference = _msl("Translational.PreLoad")
    signals = {"friction.v_rel": md.speed(s), "innerContactA.s_rel": gaps["innerContactA"],
               "innerContactB.s_rel": gaps["innerContactB"],
               "outerContactA.v_rel": sp.diff(gaps["outerContactA"], md.t),
               "outerContactB.s_rel": gaps["outerContactB"],
               "outerContactB.v_rel": sp.diff(gaps["outerContactB"], md.t)}

    def error(res):
        return _msl_error(res, reference, signals, mech)
    return Case("preload spool", mech, scene, {}, error,
                "max error / signal range vs MSL", 2e-3)


def _elasto_gap(gap, opening, c, d):
    """MSL ElastoGap's force on the flange that opens the gap (positive pushes it open):
    spring c (opening - gap) while in contact, damping d gap' limited to the spring force
    so the contact never pulls."""
    spring = c * (opening - gap)
    damping = sp.Max(-spring, sp.Min(spring, d * sp.diff(gap, md.t)))
    return sp.Piecewise((spring - damping, gap < opening), (0, True))


def _msl(name):
    path = ROOT / "validation" / "msl" / "reference" / f"{name}.csv"
    if not path.exists():
        path = ROOT.parent / "shared" / "msl-reference" / f"{name}.csv"
    with open(path) as handle:
        rows = list(csv.reader(handle))
    header, data = rows[0], np.array(rows[1:], dtype=float)
    return {column: data[:, i] for i, column in enumerate(header)}


def _msl_error(res, reference, signals, mech):
    """Largest deviation of each signal from the MSL result, over the signal's range."""
    times = reference["time"]
    states = res.at(times)
    worst = 0.0
    for label, expr in signals.items():
        values = _evaluate(expr, states, mech)
        span = np.ptp(reference[label]) or max(1e-3 * np.max(np.abs(reference[label])),
                                                1e-12)
        worst = max(worst, float(np.max(np.abs(values - reference[label])) / span))
    return worst


def _evaluate(expr, states, mech):
    speeds = {md.speed(q): md.plain(md.speed(q)) for q in mech.coordinates}
    plain = expr.subs(speeds).subs({q: md.plain(q) for q in mech.coordinates})
    symbols = sorted(plain.free_symbols, key=str)
    function = sp.lambdify(symbols, plain, "numpy")
    return np.broadcast_to(function(*(states[str(s)] for s in symbols)),
                           states[next(iter(states))].shape)


def free_crank(rtol=None, revolutions=1000):
    """A crank with a slider's mass (I_red = J + m r^2 sin^2 phi), free, for a whole
    number of revolutions: energy must stay constant, and the crank must end where the
    energy integral puts it (the period of a revolution, t = integral of dphi / omega(phi)
    with omega = sqrt(2 E / I_red), by quadrature): 2 pi N at N periods."""
    phi = md.coordinate("phi")
    J, m, r, omega0 = 0.01, 1.0, 0.1, 20.0
    mech = md.Mechanism("free crank", [phi])
    mech.link("crank", J=J, angle=phi)
    mech.link("slider", m=m, x=r * sp.cos(phi))
    energy = J * omega0**2 / 2                             # sin(0) = 0: I_red(0) = J
    period = quad(lambda a: math.sqrt((J + m * r**2 * math.sin(a) ** 2) / (2 * energy)),
                  0, 2 * math.pi, epsabs=1e-14, epsrel=1e-14)[0]
    scene = _scene("coast", [phi], revolutions * period, rtol, speeds={phi: omega0})
    turned = 2 * math.pi * revolutions

    def error(res):
        T, V = res.energy()
        drift = float(np.max(np.abs(T + V - energy)) / energy)
        return max(drift, abs(res.final(phi) - turned) / turned)
    return Case(f"free crank, {revolutions:,} rev", mech, scene, {}, error,
                "max(|E - E0| / E0, |phi_end / (2 pi N) - 1|)", 1e-6)


def free_crank_long(rtol=None):
    """The free crank over 10,000 revolutions (about 3,800 s, ~600,000 DOP853 steps)."""
    return free_crank(rtol, revolutions=10_000)


def near_resonance(rtol=None):
    """A lightly damped oscillator (f0 = 1 Hz, damping ratio 0.005) forced at 0.98 f0
    from rest over 200 periods: the transient beats against the steady response (24.5x
    the static deflection) while it decays. Reference: the closed-form solution,
    particular plus homogeneous part."""
    x = md.coordinate("x")
    m, w0, zeta, ratio, F = 1.0, 2 * math.pi, 0.005, 0.98, 1.0
    k, c, w = m * w0**2, 2 * zeta * w0 * m, ratio * w0
    mech = md.Mechanism("forced oscillator", [x], units={x: "m"})
    mech.link("mass", m=m, x=x)
    mech.spring("spring", k, stretch=x)
    mech.damper("damper", c, stretch=x)
    mech.load("force", F * sp.cos(w * md.t), along=x)
    t_end = 200 * 2 * math.pi / w
    scene = _scene("from rest", [x], t_end, rtol)
    # x = a cos wt + b sin wt + exp(-zeta w0 t) (A cos wd t + B sin wd t), x(0) = x'(0) = 0
    D = (k - m * w**2) ** 2 + (c * w) ** 2
    a, b = F * (k - m * w**2) / D, F * c * w / D
    wd = w0 * math.sqrt(1 - zeta**2)
    A = -a
    B = (zeta * w0 * A - b * w) / wd
    times = np.linspace(0, t_end, 20_001)
    exact = (a * np.cos(w * times) + b * np.sin(w * times)
             + np.exp(-zeta * w0 * times) * (A * np.cos(wd * times) + B * np.sin(wd * times)))

    def error(res):
        return float(np.max(np.abs(res.at(times, "x") - exact)) / np.max(np.abs(exact)))
    return Case("near resonance, 200 periods", mech, scene, {}, error,
                "max |x - exact| / max |exact|", 1e-6)


def stiff_stick_slip(rtol=None):
    """A brake (80 N m) on a drum (0.5 kg m^2) holding a light load (1e-3 kg m^2) on a
    stiff shaft (k = 1e6 N m/rad, damping ratio 0.05: modes at 2.2e4 and 3.2e4 rad/s)
    against a load moment growing as 20 + 40 t N m: it slides from 6 rad/s to rest,
    sticks, and slips backward once the shaft moment exceeds the brake's (t near 1.5 s).
    Reference: the piecewise-linear motion by matrix exponentials, phase by phase, the
    stop and the release located by root finding on the exact solution."""
    J1, J2, k, Mb, w0 = 0.5, 1e-3, 1e6, 80.0, 6.0
    c = 2 * 0.05 * math.sqrt(k * J1 * J2 / (J1 + J2))
    phi1, phi2 = md.coordinates("phi_1 phi_2")
    mech = md.Mechanism("braked elastic drive", [phi1, phi2])
    mech.link("drum", J=J1, angle=phi1)
    mech.link("load", J=J2, angle=phi2)
    mech.spring("shaft", k, stretch=phi1 - phi2)
    mech.damper("shaft damping", c, stretch=phi1 - phi2)
    mech.load("load moment", -(20 + 40 * md.t), along=phi2)
    mech.friction("brake", Mb, along=phi1)
    scene = _scene("brake and release", [phi1, phi2], 2.0, rtol, speeds={phi1: w0, phi2: w0})
    reference = _stick_slip_reference(J1, J2, k, c, Mb, w0, 2.0)
    times = np.linspace(0, 2.0, 2001)
    exact = reference(times)

    def error(res):
        states = res.at(times)
        return float(max(np.max(np.abs(states["phidot_1"] - exact[2])),
                         np.max(np.abs(states["phidot_2"] - exact[3]))))
    return Case("stiff stick-slip", mech, scene, {}, error, "max speed error (rad/s)", 1e-6)


def _stick_slip_reference(J1, J2, k, c, Mb, w0, t_end):
    """times -> [phi1, phi2, u1, u2] of :func:`stiff_stick_slip`, exactly: the state
    augmented with t and 1 makes each phase x' = A x (load moment linear in t)."""
    def sliding(sign):           # brake -sign Mb on the drum
        A = np.zeros((6, 6))
        A[0, 2] = A[1, 3] = A[4, 5] = 1.0
        A[2, :4] = np.array([-k, k, -c, c]) / J1
        A[2, 5] = -sign * Mb / J1
        A[3, :4] = np.array([k, -k, c, -c]) / J2
        A[3, 4], A[3, 5] = -40 / J2, -20 / J2
        return A

    stuck = np.zeros((6, 6))      # drum held: phi1' = u1' = 0
    stuck[1, 3] = stuck[4, 5] = 1.0
    stuck[3, :4] = np.array([k, -k, 0, -c]) / J2
    stuck[3, 4], stuck[3, 5] = -40 / J2, -20 / J2

    def along(A, x0, t0):
        return lambda t: expm(A * (t - t0)) @ x0

    def first_root(g, t0, t1, dt):
        grid = np.arange(t0 + dt, t1 + dt, dt)
        previous = t0
        for t in grid:
            if g(t) > 0:
                return brentq(g, previous, t, xtol=1e-15, rtol=1e-15)
            previous = t
        return None

    x0 = np.array([0, 0, w0, w0, 0, 1.0])
    slide = along(sliding(+1), x0, 0.0)
    t_stick = first_root(lambda t: -slide(t)[2], 0.0, t_end, 1e-4)
    x1 = slide(t_stick)
    x1[2] = 0.0
    hold = along(stuck, x1, t_stick)
    holding = lambda t: abs(k * (hold(t)[0] - hold(t)[1]) - c * hold(t)[3]) - Mb  # noqa: E731
    t_release = first_root(holding, t_stick, t_end, 1e-3)
    back = along(sliding(-1), hold(t_release), t_release)
    assert back(t_end)[2] < 0, "the reference expects the drum to keep slipping backward"

    def solution(times):
        return np.array([slide(t) if t < t_stick else hold(t) if t < t_release else back(t)
                         for t in times])[:, :4].T
    solution.events = (t_stick, t_release)
    return solution


def dead_centre_start(rtol=None):
    """A slider-crank started from rest at its dead centre under a constant moment: the
    energy integral gives omega(phi) = sqrt(2 M phi / I_red(phi))."""
    phi = md.coordinate("phi")
    J, m, r, M = 0.02, 2.0, 0.1, 5.0
    mech = md.Mechanism("dead centre start", [phi])
    mech.link("crank", J=J, angle=phi)
    mech.link("slider", m=m, x=r * sp.cos(phi))
    mech.load("drive", M, along=phi)
    scene = _scene("start", [phi], 3.0, rtol)

    def error(res):
        angle, speed = res["phi"], res["phidot"]
        inertia = J + m * r**2 * np.sin(angle) ** 2
        exact = np.sqrt(2 * M * angle / inertia)
        return float(np.max(np.abs(speed - exact)))
    return Case("dead centre start", mech, scene, {}, error, "max |omega - omega(phi)|",
                1e-6)


def vanishing_inertia(rtol=None):
    """A yoke whose crank has no inertia (I_red = m l^2 sin^2 phi): the reduced inertia
    vanishes at phi = pi; the run must fail with a named error, never a NaN trajectory."""
    phi = md.coordinate("phi")
    mech = md.Mechanism("yoke without crank inertia", [phi])
    mech.link("yoke", m=1.0, x=0.1 * sp.cos(phi))
    mech.load("drive", 1.0, along=phi)
    scene = _scene("start", [phi], 5.0, rtol, positions={phi: 1.0})

    def error(res):
        return float("nan")
    return Case("vanishing inertia", mech, scene, {}, error, "fails with a named error",
                0.0, expect_failure=True)


def brake_hold(rtol=None):
    """A hanging load lowered on a drum, braked to rest and held (brake 80 N m against a
    load moment 49.05 N m): stop time omega0 I / (M_b - M_L), then held exactly."""
    phi = md.coordinate("phi")
    J, r, m, g, Mb = 0.5, 0.1, 50.0, 9.81, 80.0
    I = J + m * r**2
    mech = md.Mechanism("brake hold", [phi])
    mech.link("drum", J=J, angle=phi)
    mech.link("load", m=m, y=-r * phi)       # lowered while the drum turns backward
    mech.gravity(g)
    mech.friction("brake", Mb, along=phi)
    scene = _scene("brake", [phi], 4.0, rtol, speeds={phi: 6.0})
    stop = 6.0 * I / (Mb - m * g * r)

    def error(res):
        moving = res.at(np.linspace(0, stop * 0.999, 50), "phidot")
        exact = 6.0 - (Mb - m * g * r) / I * np.linspace(0, stop * 0.999, 50)
        held = res.at(np.linspace(stop * 1.001, 4.0, 50), "phidot")
        return float(max(np.max(np.abs(moving - exact)), np.max(np.abs(held))))
    return Case("brake stop and hold", mech, scene, {}, error, "speed error (rad/s)", 1e-8)


def _scene(name, coords, t_end, rtol, speeds=None, positions=None, **extra):
    initial = {q: (positions or {}).get(q, 0) for q in coords}
    initial.update({md.speed(q): (speeds or {}).get(q, 0) for q in coords})
    if rtol is not None:
        extra.update(rtol=rtol, atol=rtol * 1e-2)
    return md.Scene(name, initial=initial, t_end=t_end, **extra)


CASES = [stiff_damped_pair, stiff_undamped_pair, late_coupling, preload_spool,
         dead_centre_start, brake_hold, stiff_stick_slip, near_resonance, free_crank,
         free_crank_long, vanishing_inertia]

"""Impacts: the velocity jumps where a stop's limit is reached (or a one-way clutch is
driven backward at the start of a run).

At an impact the speeds jump by the impulse of least kinetic energy change (through
the mass matrix, like the friction projection) that gives each impacting limit the rate
``-e`` times its rate before (Newton's law of restitution), keeps the closed loops'
speeds closed, and lets no limit already in contact, and no locked one-way clutch, move
into its stop: those take impulses only in the way they push, found by an active set
(a limit whose impulse would pull is left out; one driven into its stop is added,
plastically). Friction carries no impulse (its force is finite): a stuck brake slips
through an impact and sticks again if the new speeds allow.

A bouncing contact (``e > 0``) under a load that pushes it back would bounce
infinitely often before it comes to rest, in the finite time ``2 e v / ((1 - e) a)``
(``v`` its speed into the stop, ``a`` the acceleration towards it): once that time is
below ``1e-9`` of the run, or the next bounce would rise less than ``1e-12`` of the
coordinates' size (``(e v)^2 / (2 a)``: below what positions resolve), the impact is
taken as plastic and the contact rests, so a run has a finite number of events.

>>> import mechdyn as md
>>> x = md.coordinate("x")
>>> ball = md.Mechanism("ball", [x], units={x: "m"})
>>> _ = ball.link("ball", m=1, y=x)
>>> _ = ball.gravity(10)
>>> _ = ball.stop("floor", along=x, lower=0, restitution=0.5)
>>> res = ball.simulate(md.Scene("drop", initial={x: 5, md.speed(x): 0}, t_end=5), {})
>>> first = [e for e in res.events if e.kind == "impact"][0]
>>> round(first.time, 9), round(first.value, 9)        # t = 1 s, impulse 1.5 * 10
(1.0, 15.0)
>>> rest = res.events[-1]                 # bounces of 5, 2.5, ... m/s end at t = 3 s
>>> rest.kind, abs(rest.time - 3.0) < 1e-5, abs(res.final(x)) < 1e-12
('contact', True, True)
"""
from __future__ import annotations

import math

import numpy as np

from mechdyn.errors import SceneError
from mechdyn.simulate.events import Event

__all__ = ["jump", "ZENO"]

ZENO = 1e-9              # bounces ending within this fraction of the run: plastic
_HEIGHT = 1e-12          # ... or rising less than this x (1 + largest coordinate)
_AT_REST = 1e-12         # as in friction.py: speeds below this x (1 + largest) are rest
_START = 1e-10           # a limit this close (x (1 + largest coordinate)) at the start


def jump(modes, t, y, mode, arrived, events):
    """The speeds after the impacts at ``(t, y)``: returns ``(y, touching, arrived)``,
    the stop limits now touching (element indices of ``modes``) and those at rest on
    them (for :meth:`~mechdyn.simulate.friction.FrictionModes.decide`). ``mode``: the mode
    before (None at the start of a run, where limits touched are found and limits
    already passed are refused); ``arrived``: the limits whose gap event fired."""
    from mechdyn.simulate.friction import Mode, largest_magnitude
    k, n = modes.k, modes.n
    if not modes.contacts and (mode is not None or "one_way" not in modes.kinds):
        return y, set(), set()
    view = modes.view(t, y, mode or Mode())
    resting = {e for e in (mode.stuck if mode else ()) if e >= k}     # in contact before
    arriving = set(arrived) | (_touching_at_start(modes, view, y) if mode is None else set())
    touching = resting | arriving
    rest = _AT_REST * (1.0 + largest_magnitude(y[n:]))
    hitting = [e for e in sorted(arriving) if view.rates[e] < -rest]
    if mode is None:
        hitting += [j for j in range(k) if modes.kinds[j] == "one_way"
                    and view.rates[j] < -rest]
    if not hitting:
        return y, touching, {e for e in arrived if view.rates[e] <= rest}
    targets = _targets(modes, t, y, view, mode, hitting, rest)
    one_way = [j for j in range(k) if modes.kinds[j] == "one_way"]
    others = [e for e in sorted(touching) + one_way if e not in hitting]
    u = y[n:]
    active = dict(targets)
    for _ in range(2 * len(hitting) + 2 * len(others) + 2):
        rows = list(active)
        change, impulses = _impulse(view, u, rows, [active[e] for e in rows])
        after = view.rates + view.gradients @ change
        pulling = [e for e, impulse in zip(rows, impulses) if impulse < 0]
        driven = [e for e in others if e not in active and after[e] < -rest]
        if not pulling and not driven:
            break
        for e in pulling:
            del active[e]
        for e in driven:
            active[e] = 0.0
    mass, after_speeds = view.mass, u + change
    lost = 0.5 * (u @ mass @ u - after_speeds @ mass @ after_speeds)
    y = np.array(y, dtype=float)
    y[n:] = after_speeds
    impulses = dict(zip(rows, impulses))
    for count, e in enumerate(hitting):
        name = modes.contact_elements[e - k] if e >= k else modes.names[e]
        label = modes.contact_names[e - k] if e >= k else f"{name} (locks)"
        events.append(Event(t, "impact", name,
                            f"{label}: speed {view.rates[e]:.6g} -> {after[e]:.6g}, "
                            f"impulse {impulses.get(e, 0.0):.6g}, kinetic energy lost "
                            f"{lost:.6g}", value=float(impulses.get(e, 0.0)),
                            energy=float(lost) if count == 0 else 0.0))
    resting = {e for e in touching if after[e] <= rest}
    return y, touching, resting


def _touching_at_start(modes, view, y) -> set:
    """The limits touched at the start of a run; a limit passed is an error."""
    tolerance = _START * (1.0 + float(np.abs(y[:modes.n]).max(initial=0.0)))
    out = set()
    for j, gap in enumerate(view.gaps):
        if gap < -tolerance:
            raise SceneError(f"stop {modes.contact_elements[j]!r}: the run starts beyond "
                             f"its {modes.contact_names[j].rsplit('.', 1)[1]} limit (by "
                             f"{-gap:.6g}); start within the limits")
        if gap <= tolerance:
            out.add(modes.k + j)
    return out


def _targets(modes, t, y, view, mode, hitting, rest) -> dict:
    """The rate each impacting element leaves with: ``-e`` times its rate, or 0 where
    the remaining bounces would end within ``ZENO`` of the run (and for one-way
    clutches, which lock)."""
    from mechdyn.simulate.friction import Mode, largest_magnitude
    restitution = view.terms["contact_restitution"]
    accelerations = modes.solve(view, mode or Mode()).a
    height_floor = _HEIGHT * (1.0 + largest_magnitude(y[:modes.n]))
    out = {}
    for e in hitting:
        e_value = float(restitution[e - modes.k]) if e >= modes.k else 0.0
        speed = -float(view.rates[e])
        toward = -(float(view.gradients[e] @ accelerations) + float(view.biases[e]))
        if 0 < e_value < 1 and toward > 0:
            remaining = 2 * e_value * speed / ((1 - e_value) * toward)
            height = (e_value * speed) ** 2 / (2 * toward)
            if remaining < ZENO * modes.span or height < height_floor:
                e_value = 0.0
        if e_value * speed <= rest:
            e_value = 0.0
        out[e] = e_value * speed
    return out


def _impulse(view, u, rows, targets):
    """The least-kinetic-energy speed change that gives the ``rows`` the ``targets``
    rates and keeps the loops' speeds closed; returns it and the rows' impulses."""
    n = view.n
    loops = view.terms["constraint_gradient"].reshape(-1, n)
    if not len(loops) and len(rows) == 1:
        single = _single_impulse(view, rows[0], float(targets[0]))
        if single is not None:
            return single
    g = np.concatenate([loops, view.gradients[rows].reshape(-1, n)])
    wanted = np.concatenate([-(loops @ u + view.terms["constraint_rate"]),
                             np.asarray(targets, dtype=float) - view.rates[rows]])
    m = len(g)
    system = np.zeros((n + m, n + m))
    system[:n, :n] = view.mass
    system[:n, n:] = -g.T
    system[n:, :n] = g
    solution = np.linalg.lstsq(system, np.concatenate([np.zeros(n), wanted]), rcond=None)[0]
    return solution[:n], solution[n + len(loops):]


def _single_impulse(view, row, target):
    """:func:`_impulse` for one row and no loops, in closed form: the change
    ``M^-1 g' lambda`` with ``lambda = (target - rate) / (g M^-1 g')``; None where
    ``g M^-1 g'`` is not positive (left to the least-squares solution)."""
    mass, gradient = view.mass, view.gradients[row]
    direction = gradient / mass[0, 0] if view.n == 1 else np.linalg.solve(mass, gradient)
    weight = float(gradient @ direction)
    if not (weight > 0 and math.isfinite(weight)):
        return None
    impulse = (target - float(view.rates[row])) / weight
    return direction * impulse, np.array([impulse])

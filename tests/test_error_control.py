"""simulate/error_control.py: a revolving coordinate is weighed on the scale of one
revolution, ``atol + rtol min(|y|, 2 pi)`` (docs/hard-cases.md, "What the tolerance
means"). The references are runs that differ only where the rule says they must not:
a load of time alone, ``y' = 0.1 cos(10 t)``, gives every run the same stages, so the
steps differ only through the scale the error is weighed on."""
import math

import numpy as np

from mechdyn.simulate.error_control import guarded


def step_times(y0, revolving, rtol, atol):
    solver = guarded("RK23")(lambda t, y: [0.1 * math.cos(10 * t)], 0.0, [y0], 10.0,
                             rtol=rtol, atol=atol, revolving=revolving, first_step=1e-3)
    times = []
    while solver.status == "running":
        solver.step()
        times.append(solver.t)
    return np.array(times)


def test_a_revolving_angle_is_allowed_the_same_error_after_a_turn_or_five_hundred():
    # y stays within 0.01 of its start: 2.9 pi and 1000 pi are both past one revolution
    near = step_times(2.9 * math.pi, [0], 1e-6, 1e-9)
    far = step_times(1000 * math.pi, [0], 1e-6, 1e-9)
    assert near.tolist() == far.tolist()


def test_a_revolving_angle_is_weighed_as_an_absolute_error_of_rtol_times_two_pi():
    # the same steps as a coordinate near 0 (where rtol |y| is nothing) given
    # atol + rtol 2 pi as its absolute tolerance; the smallest rtol scipy takes keeps its
    # relative part negligible. The runs' rounding differs (y near 2.9 pi or near 0), so
    # the step counts may differ by a step or two; weighing on 3 pi would save ~11 %.
    revolving = step_times(2.9 * math.pi, [0], 1e-6, 1e-9)
    absolute = step_times(0.0, [], 100 * np.finfo(float).eps, 1e-9 + 1e-6 * 2 * math.pi)
    assert len(absolute) > 250
    assert abs(len(revolving) - len(absolute)) <= 2


def test_the_blind_estimate_guard_lets_the_step_grow_on_a_smooth_solution():
    # y' = -y from a first step of 1 us: only an estimate 100 times below the last trusted
    # one keeps the step, so the steps grow as scipy's own RK23 grows them (a guard that
    # kept every step would need ten million steps to reach 10 s).
    from scipy.integrate import RK23

    def count(solver, limit=10_000):
        steps = 0
        while solver.status == "running" and steps < limit:
            solver.step()
            steps += 1
        return steps, solver.t

    options = dict(rtol=1e-6, atol=1e-9, first_step=1e-6)
    plain, _ = count(RK23(lambda t, y: -y, 0.0, [1.0], 10.0, **options))
    steps, t = count(guarded("RK23")(lambda t, y: -y, 0.0, [1.0], 10.0, **options))
    assert t == 10.0
    assert steps <= 2 * plain

"""simulate/events.py: an event function that crosses zero and back within one step is
caught by the ``interior`` samples of :class:`EventWatch` (the step's ends alone show no
change of sign). Reference: the roots of the step's polynomial, by the quadratic formula."""
import math

import numpy as np

from mechdyn.simulate.events import EventWatch


def test_an_interior_sample_catches_a_crossing_and_recrossing_within_one_step():
    # g = y = 1 - 5 x + 5 x^2 on the step x = t in [0, 1]: positive at both ends, negative
    # between its roots (5 -+ sqrt 5) / 10; the first is where it fires.
    coefficients = np.array([[1.0], [-5.0], [5.0]])
    for interior, expected in ((0, None), (1, (5 - math.sqrt(5)) / 10)):
        watch = EventWatch(lambda t, y: np.array([y[0]]), [0], [False], interior=interior)
        watch.start(0.0, np.array([1.0]))
        found = watch.check(0.0, 1.0, np.array([1.0]), coefficients)
        if expected is None:
            assert found is None                # the ends alone see no crossing
        else:
            t, y, fired = found
            assert fired == [0]
            assert abs(t - expected) <= 1e-12
            assert abs(y[0]) <= 1e-12

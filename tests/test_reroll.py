"""compile/reroll.py: loops made of straight-line generated code compute what the code
computed, to the last bit, across the lines that are fences (calls, loops): nothing
moves across them. The reference is the original function itself, run by Python."""
import numpy as np

from mechdyn.compile.reroll import rerolled

SOURCE = "\n".join([
    "def f(t, y, p, out):",
    "    q0 = y[0]", "    q1 = y[1]", "    q2 = y[2]", "    p0 = p[0]",
    "    _c0 = p0*q0", "    _c1 = p0*q1", "    _c2 = p0*q2",
    "    out[0] = _c0", "    out[1] = _c1", "    out[2] = _c2",
    "    scale(out, 2.0)",                       # a fence: a call that changes out
    "    _c3 = out[0] + q0", "    _c4 = out[1] + q1", "    _c5 = out[2] + q2",
    "    out[3] = _c3", "    out[4] = _c4", "    out[5] = _c5",
    "    for _i in range(3):",                   # a fence: a loop
    "        out[6 + _i] = out[3 + _i] * t",
])


def scale(out, factor):
    for i in range(out.shape[0]):
        out[i] *= factor


def run(text, tables):
    namespace = {"np": np, "scale": scale, **tables}
    exec(text, namespace)
    out = np.zeros(9)
    namespace["f"](1.5, np.array([0.3, -1.7, 2.9]), np.array([1.1]), out)
    return out


def test_rerolled_code_with_fences_computes_the_same_bits():
    text, tables = rerolled(SOURCE, "f", minimum=2)
    assert "for _k in range(3):" in text and tables          # rerolled at all
    expected = run(SOURCE, {})
    assert run(text, tables).tolist() == expected.tolist()
    assert expected[3] == 2.0 * 1.1 * 0.3 + 0.3                # the fence ran in between

"""Friction mode decisions that the suite did not pin before mutation testing
(docs/mutation.md): whether a stuck element can hold does not depend on the size of the
machine. Expected values: the impulse balance integrated by hand."""
import numpy as np
import pytest

import mechdyn as md

x = md.coordinate("x")
CAPACITY_PER_KG = 0.3 * 9.81              # mu g
RELEASE = CAPACITY_PER_KG                 # push m t reaches mu m g at t = mu g


@pytest.mark.parametrize("sign, way", [(+1, "forward"), (-1, "backward")])
@pytest.mark.parametrize("mass", [1.0, 1e7], ids=["1 kg", "10,000 t"])
def test_a_block_pushed_harder_and_harder_holds_then_slides_whatever_its_mass(
        mass, sign, way):
    # Push m t against a friction capacity mu m g: held until t1 = mu g = 2.943 s, then
    # a = t - t1: v(4) = (4 - t1)^2 / 2, x(4) = (4 - t1)^3 / 6; the same for any mass,
    # mirrored for a pull.
    block = md.Mechanism("pushed block", [x])
    block.link("block", m=mass, x=x)
    block.load("push", sign * mass * md.t, along=x)
    block.friction("floor", CAPACITY_PER_KG * mass, along=x)
    res = block.simulate(md.Scene("push", initial={x: 0, md.speed(x): 0}, t_end=4), {})
    assert [e.kind for e in res.events] == ["slip"]
    assert res.events[0].detail.split()[-1] == way              # the way, as a word
    assert res.events[0].time == pytest.approx(RELEASE, abs=1e-9)
    assert np.all(res[x][res.t < RELEASE] == 0.0)
    assert res.final(md.speed(x)) == pytest.approx(sign * (4 - RELEASE) ** 2 / 2, rel=1e-9)
    assert res.final(x) == pytest.approx(sign * (4 - RELEASE) ** 3 / 6, rel=1e-9)

"""Friction and stop mode decisions that the suite did not pin before mutation testing
(docs/mutation.md): whether a stuck element can hold does not depend on the size of the
machine; a release names the element and the way it slides; a block resting on a stop
stays there through later events without new contact events. Expected values: the
impulse balance and free fall integrated by hand."""
import math

import numpy as np
import pytest
import sympy as sp

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
    assert [(e.kind, e.name) for e in res.events] == [("slip", "floor")]
    assert res.events[0].detail.split()[-1] == way              # the way, as a word
    assert res.events[0].time == pytest.approx(RELEASE, abs=1e-9)
    assert np.all(res[x][res.t < RELEASE] == 0.0)
    assert res.final(md.speed(x)) == pytest.approx(sign * (4 - RELEASE) ** 2 / 2, rel=1e-9)
    assert res.final(x) == pytest.approx(sign * (4 - RELEASE) ** 3 / 6, rel=1e-9)


def test_a_block_dropped_on_a_stop_rests_there_through_a_later_change_of_the_load():
    # 1 kg dropped from 1 m onto a plastic stop x >= 0: impact at t0 = sqrt(2 h / g) with
    # the impulse m sqrt(2 g h) taking the kinetic energy m g h; it then rests on the stop.
    # At t = 1.5 s the load changes (-9.81 -> -4.81 N, still pressing): an event, but
    # not a new contact.
    g = 9.81
    block = md.Mechanism("dropped block", [x])
    block.link("block", m=1, x=x)
    block.load("weight", -g + sp.Piecewise((0, md.t < 1.5), (5, True)), along=x)
    block.stop("floor", along=x, lower=0)
    res = block.simulate(md.Scene("drop", initial={x: 1, md.speed(x): 0}, t_end=2), {})
    t0 = math.sqrt(2 / g)
    assert [(e.kind, e.name) for e in res.events] == [("impact", "floor"), ("contact", "floor")]
    assert "lower" in res.events[1].detail                    # which limit it rests on
    assert [e.time for e in res.events] == pytest.approx([t0, t0], abs=1e-9)
    assert res.events[0].value == pytest.approx(math.sqrt(2 * g), rel=1e-9)
    assert res.events[0].energy == pytest.approx(g, rel=1e-9)
    after = res.t > t0 + 1e-9
    assert np.all(np.abs(res[x][after]) <= 1e-12) and np.all(res[md.speed(x)][after] == 0.0)


def test_a_block_resting_on_a_stop_lifts_off_when_the_load_pulls_it_away():
    # Resting on x >= 0 under its weight until t = 1, then pulled up with a net 5 N:
    # it lifts off at t = 1 (an event naming the stop and its limit) and rises as
    # x = 5/2 (t - 1)^2, x(2) = 2.5.
    g = 9.81
    block = md.Mechanism("lifted block", [x])
    block.link("block", m=1, x=x)
    block.load("weight", -g + sp.Piecewise((0, md.t < 1), (g + 5, True)), along=x)
    block.stop("floor", along=x, lower=0)
    res = block.simulate(md.Scene("lift", initial={x: 0, md.speed(x): 0}, t_end=2), {})
    lifts = [e for e in res.events if e.kind == "lift"]
    assert [(e.name, e.time) for e in lifts] == [("floor", pytest.approx(1.0, abs=1e-9))]
    assert "lower" in lifts[0].detail
    assert np.all(res[x][res.t < 1.0] == 0.0)
    assert res.final(x) == pytest.approx(2.5, rel=1e-9)
    assert res.final(md.speed(x)) == pytest.approx(5.0, rel=1e-9)


def test_a_brake_that_engages_late_stops_a_spinning_shaft():
    # J = 1 spinning at 5 rad/s; the brake's capacity 10 max(0, t - 1) is zero (free)
    # until t = 1, when it engages; then omega = 5 - 5 (t - 1)^2 reaches zero at t = 2,
    # where the brake holds: phi = 5 + (5 - 5/3) = 25/3 from then on.
    phi = md.coordinate("phi")
    shaft = md.Mechanism("braked shaft", [phi])
    shaft.link("shaft", J=1, angle=phi)
    shaft.friction("brake", 10 * sp.Max(0, md.t - 1), along=phi)
    res = shaft.simulate(md.Scene("brake", initial={phi: 0, md.speed(phi): 5}, t_end=3), {})
    assert [(e.kind, e.name) for e in res.events] == [("engage", "brake"), ("stick", "brake")]
    assert [e.time for e in res.events] == pytest.approx([1.0, 2.0], abs=1e-9)
    assert res.at(1.5, md.speed(phi)) == pytest.approx(5 - 5 * 0.5 ** 2, rel=1e-9)
    assert res.final(phi) == pytest.approx(25 / 3, rel=1e-9)
    assert res.final(md.speed(phi)) == 0.0

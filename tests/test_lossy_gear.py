"""Lossy gears: mesh loss by the direction of power flow, self-locking, against closed
forms of the rigid reduction (the MSL LossyGearDemo1-3 references run in
test_msl_validation.py)."""
import dataclasses

import numpy as np
import pytest
import sympy as sp

import mechdyn as md

J_M, J_D, I, ETA, R, MASS, G, M, T_M, M_LOW = 0.01, 0.5, 40, 0.4, 0.1, 200, 9.81, 15, 1, 0.2
INERTIA = J_D + MASS * R**2 + ETA * I**2 * J_M      # the drum's, the motor's through eta


def hoist():
    return md.load_model("models/worm_hoist.py")


def test_lifting_the_worm_drives_and_loses_one_minus_eta_of_its_moment():
    model = hoist()
    phi_m, phi_d = model.mechanism.coordinates
    res = model.mechanism.simulate(model.scenes["lift"], model.params)
    lift = (I * ETA * M - MASS * G * R) / INERTIA           # the drum's acceleration
    assert res.at(T_M, md.speed(phi_d)) == pytest.approx(lift * T_M, rel=1e-9)
    assert res.at(T_M, md.speed(phi_m)) == pytest.approx(I * lift * T_M, rel=1e-9)
    # the mesh moment tau = M - J_m i a and the loss (1 - eta) tau
    tau = M - J_M * I * lift
    values = res.outputs_at([0.5])
    assert values["worm gear"][0] == pytest.approx(tau, rel=1e-9)
    assert values["worm gear.loss"][0] == pytest.approx((1 - ETA) * tau, rel=1e-9)
    assert values["worm gear.mode"][0] == 1.0


def test_with_the_motor_off_the_hoist_coasts_up_stops_and_self_locks():
    model = hoist()
    phi_m, phi_d = model.mechanism.coordinates
    res = model.mechanism.simulate(model.scenes["lift"], model.params)
    lift = (I * ETA * M - MASS * G * R) / INERTIA
    coast = -MASS * G * R / INERTIA                # the worm's inertia still drives
    t_stop = T_M - lift * T_M / coast
    stick = [e for e in res.events if e.kind == "stick"]
    assert [e.time for e in stick] == [pytest.approx(t_stop, rel=1e-9)]
    height = lift * T_M**2 / 2 + (lift * T_M) ** 2 / (-2 * coast)
    assert res.final(phi_d) == pytest.approx(height, rel=1e-9)
    after = res.t > t_stop * (1 + 1e-9)
    assert np.all(res[md.speed(phi_d)][after] == 0.0)
    # held by the gear: the loss moment carries the load's m g r / i
    assert res.final("worm gear.loss") == pytest.approx(-MASS * G * R / I, rel=1e-9)


def test_lowering_turns_at_the_motors_pace_whatever_the_load():
    model = hoist()
    phi_m, phi_d = model.mechanism.coordinates
    res = model.mechanism.simulate(model.scenes["lower"], model.params)
    # the load would overhaul the gear but cannot drive the worm: mesh moment 0 and
    # phi_m'' = -M_low / J_m
    assert res.final(md.speed(phi_m)) == pytest.approx(-M_LOW / J_M, rel=1e-9)
    assert res.final(md.speed(phi_d)) == pytest.approx(-M_LOW / J_M / I, rel=1e-9)
    assert np.allclose(res["worm gear"], 0.0, atol=1e-9)
    # ... and for any load: double it, the motion is the same
    heavy = model.params | {model.param_symbol("m"): 2 * MASS}
    assert model.mechanism.simulate(model.scenes["lower"], heavy).final(phi_m) == \
        pytest.approx(res.final(phi_m), rel=1e-9)


def test_the_load_alone_cannot_drive_a_self_locking_gear():
    model = hoist()
    res = model.mechanism.simulate(model.scenes["hold"], model.params)
    assert not res.events
    assert np.all(res.y == 0.0)


def test_the_work_of_the_motor_becomes_potential_energy_and_mesh_loss():
    model = hoist()
    scene = dataclasses.replace(model.scenes["lift"], outputs=["power:lift",
                                                               "power:worm gear"])
    res = model.mechanism.simulate(scene, model.params)
    kinetic, potential = res.energy()
    nodes, weights = np.polynomial.legendre.leggauss(8)
    work = {"power:lift": 0.0, "power:worm gear": 0.0}
    for a, b in zip(res.t[:-1], res.t[1:]):
        times = (a + b) / 2 + (b - a) / 2 * nodes
        powers = res.outputs_at(times)
        for label in work:
            work[label] += (b - a) / 2 * weights @ powers[label]
    change = kinetic[-1] + potential[-1] - kinetic[0] - potential[0]
    assert change == pytest.approx(work["power:lift"] + work["power:worm gear"], rel=1e-8)
    assert work["power:worm gear"] < 0                         # a loss, never a gain


def two_shafts(**law):
    phi_a, phi_b = md.coordinates("phi_a phi_b")
    mech = md.Mechanism("gear", [phi_a, phi_b])
    mech.link("input", J=1, angle=phi_a)
    mech.link("output", J=1.5, angle=phi_b)
    mech.load("drive", 10, along=phi_a)
    mech.load("brake", -4, along=phi_b)
    mech.lossy_gear("gear", input=phi_a, output=phi_b, ratio=2, **law)
    scene = md.Scene("s", initial={phi_a: 0, phi_b: 0, md.speed(phi_a): 0,
                                   md.speed(phi_b): 0}, t_end=1, outputs=["gear"])
    return mech, scene, phi_a, phi_b


def test_an_ideal_gear_is_the_rigid_reduction():
    mech, scene, phi_a, phi_b = two_shafts()
    res = mech.simulate(scene, {})
    # (J_b + 4 J_a) phi_b'' = 2 * 10 - 4: 16 / 5.5
    assert res.final(md.speed(phi_b)) == pytest.approx(16 / 5.5, rel=1e-10)
    assert res.final(md.speed(phi_a)) == pytest.approx(32 / 5.5, rel=1e-10)
    assert res.final("gear") == pytest.approx(10 - 32 / 5.5, rel=1e-10)   # M - J_a a_a


def test_speed_dependent_efficiency_from_a_table_of_the_speed():
    # eta_forward = 0.9 - 0.01 |w_a| (a table of |w_a|): phi_b'' = (2 eta 10 - 4) /
    # (1.5 + 4 eta) with eta falling as the input speeds up; at the start 14 / 5.1.
    phi_a = md.coordinate("phi_a")
    eta = md.table([0, 10], [0.9, 0.8])(sp.Abs(md.speed(phi_a)))
    mech, scene, phi_a, phi_b = two_shafts(eta_forward=eta)
    res = mech.simulate(dataclasses.replace(scene, t_end=1e-4), {})
    assert res.accelerations[1][0] == pytest.approx(14 / 5.1, rel=1e-9)
    res = mech.simulate(scene, {})
    w = res.final(md.speed(phi_a))
    eta_end = 0.9 - 0.01 * w
    assert res.accelerations[1][-1] == pytest.approx((20 * eta_end - 4) / (1.5 + 4 * eta_end),
                                                     rel=1e-8)


@pytest.mark.parametrize("kwargs, match", [
    (dict(ratio=0), "ratio must not be zero"),
    (dict(ratio=2, eta_forward=0), r"eta_forward = 0 must lie in \(0, 1\]"),
    (dict(ratio=2, eta_backward=1.2), "must not exceed 1"),
    (dict(ratio=2, bearing_forward=-1), "must not be negative"),
])
def test_bad_gears_are_refused_naming_the_gear(kwargs, match):
    phi_a, phi_b = md.coordinates("phi_a phi_b")
    mech = md.Mechanism("gear", [phi_a, phi_b])
    with pytest.raises(md.DeclarationError, match=f"lossy gear 'gear'.*{match}"):
        mech.lossy_gear("gear", input=phi_a, output=phi_b, **kwargs)


def test_a_two_stage_gearbox_loses_eta_squared_of_the_drive():
    # Input J_a = 0.1 driven by 10, intermediate J_m = 0.2, output J_b = 1, two stages of
    # ratio 2 and eta 0.8: tau_2 = J_b a_b / (r eta), J_m r a_b = r eta (10 - J_a r^2 a_b)
    # - tau_2, so a_b = r eta 10 / (J_m r + r^3 eta J_a + J_b / (r eta)).
    a, m, b = md.coordinates("phi_a phi_m phi_b")
    box = md.Mechanism("two stages", [a, m, b])
    box.link("in", J=0.1, angle=a)
    box.link("mid", J=0.2, angle=m)
    box.link("out", J=1.0, angle=b)
    box.load("drive", 10, along=a)
    box.lossy_gear("stage 1", input=a, output=m, ratio=2, eta_forward=0.8, eta_backward=0.7)
    box.lossy_gear("stage 2", input=m, output=b, ratio=2, eta_forward=0.8, eta_backward=0.7)
    res = box.simulate(md.Scene("s", initial={a: 0, m: 0, b: 0, md.speed(a): 0},
                                t_end=1), {})
    a_b = 2 * 0.8 * 10 / (0.2 * 2 + 8 * 0.8 * 0.1 + 1.0 / (2 * 0.8))
    assert res.final(md.speed(b)) == pytest.approx(a_b, rel=1e-10)


def test_the_printed_mesh_loss_has_both_directions_of_power_flow():
    """MSL LossyGear's loss as a function of the mesh moment tau: (1 - eta_f) tau forward,
    (1 - 1/eta_b) tau backward, the larger of the two; a self-locking gear (eta_b <= 0)
    has the forward law alone."""
    def loss_line(**law):
        latex = two_shafts(**law)[0].latex()
        return next(line for line in latex.splitlines() if line.startswith("\\tau_{\\mathrm{loss}"))
    both = loss_line(eta_forward=0.9, eta_backward=0.8)
    assert "\\max" in both and "0.1 \\tau_{gear}" in both and "- 0.25 \\tau_{gear}" in both
    locking = loss_line(eta_forward=0.9, eta_backward=-0.5)
    assert "\\max" not in locking and "0.1 \\tau_{gear}" in locking

"""Sizing by optimisation (md.optimize, mechdyn optimize): known optima, KKT conditions
with closed-form gradients, the flywheel md.flywheel sizes, refusals."""
import numpy as np
import pytest
import sympy as sp

import mechdyn as md
from mechdyn.cli.command import main


def _brake_problem():
    brake = md.load_model("models/shoe_brake.py")
    return brake, dict(vary={"P": (1, 100), "R": (0.05, 0.5)}, minimize="P + 100*R",
                       subject_to=["t_end <= 20 s", "P <= 15 N"])


def test_a_two_constraint_optimum_satisfies_its_kkt_conditions():
    brake, problem = _brake_problem()
    best = md.optimize(brake.mechanism, brake.scenes["braking"], brake.params, **problem)
    # t = I w0 / (2 f P R) = 100 / (P R) <= 20 s: P R >= 5; P + 100 R on P R = 5 is least
    # at P = sqrt(500) > 15, so P = 15 (its bound) and R = 5 / 15
    P, R = best.values["P"], best.values["R"]
    assert best.success
    assert (P, R) == pytest.approx((15, 1 / 3), rel=1e-6)
    assert best.objective == pytest.approx(15 + 100 / 3, rel=1e-6)
    lam_t, lam_p = (c["multiplier"] for c in best.constraints)
    assert all(c["active"] for c in best.constraints)
    # KKT with the closed form's gradient of t: grad F + lam_t grad t + lam_p grad P = 0
    t_end = 100 / (P * R)
    grad_f, grad_t, grad_p = np.array([1, 100]), np.array([-t_end / P, -t_end / R]), \
        np.array([1, 0])
    assert np.linalg.norm(grad_f + lam_t * grad_t + lam_p * grad_p) < 1e-6 * 100
    assert (lam_t, lam_p) == pytest.approx((5 / 3, 11 / 9), rel=1e-6)
    assert best.simulations >= 1 and "multiplier" in str(best)


def _machine():
    phi = md.coordinate("phi")
    J = sp.Symbol("J", positive=True)
    machine = md.Mechanism("machine", [phi])
    machine.link("crank and flywheel", J=J, angle=phi)
    machine.load("motor", md.motors.dc_shunt(400, 110)(md.speed(phi)), along=phi)
    machine.load("process", 20 * sp.cos(phi), along=phi)
    return machine, md.Scene("run", initial={phi: 0, md.speed(phi): 100}, t_end=1), J


def test_the_least_flywheel_for_a_fluctuation_is_the_one_md_flywheel_sizes():
    machine, scene, J = _machine()
    sized = md.flywheel(machine, scene, {J: 2}, delta=0.01, inertia=J)
    best = md.optimize(machine, scene, {J: 2}, vary={J: (0.01, 10)}, minimize="J",
                       subject_to="fluctuation <= 0.01")
    assert best.values["J"] == pytest.approx(sized.inertia, rel=1e-6)
    assert best.constraints[0]["active"] and best.constraints[0]["multiplier"] > 0


@pytest.mark.slow
def test_the_press_flywheel_for_delta_five_percent_against_md_flywheel():
    press = md.load_model("models/press_flywheel.py")
    scene = press.scenes["steady"]
    sized = md.flywheel(press.mechanism, scene, press.params, delta=0.05,
                        inertia=press.param_symbol("J_f"))
    best = md.optimize(press.mechanism, scene, press.params, vary={"J_f": (0.05, 5)},
                       minimize="J_f", subject_to=["fluctuation <= 0.05"])
    assert best.values["J_f"] == pytest.approx(sized.inertia, rel=1e-6)


def test_maximize_and_an_inactive_constraint():
    brake = md.load_model("models/shoe_brake.py")
    # the longest stop angle with P in [10, 40] N: the lowest force, at its bound
    best = md.optimize(brake.mechanism, brake.scenes["braking"], brake.params,
                       vary={"P": (10, 40)}, maximize="stop_angle",
                       subject_to=["t_end <= 200 s"])
    assert best.values["P"] == pytest.approx(10, rel=1e-9)
    assert best.objective == pytest.approx(0.4 * 100 ** 2 / (4 * 0.2 * 10 * 0.1), rel=1e-8)
    assert best.bounds["P"][0] == "lower"
    assert not best.constraints[0]["active"] and best.constraints[0]["multiplier"] == 0


@pytest.mark.parametrize("constraint, words", [
    ("fluctuation < 0.05", "expected GOAL <= LIMIT"),
    ("__import__('os').system('x') <= 1", "only numbers, parameter names"),
    ("t_end <= 20 m", "m is a length but s"),
    ("Q <= 3", "'Q' is not a parameter or measure"),
])
def test_constraints_that_cannot_be_read_are_named(constraint, words):
    brake = md.load_model("models/shoe_brake.py")
    with pytest.raises(md.MechdynError, match=words.replace("(", r"\(")):
        md.optimize(brake.mechanism, brake.scenes["braking"], brake.params,
                    vary={"P": (1, 100)}, minimize="P", subject_to=[constraint])


def test_bad_bounds_are_refused():
    brake = md.load_model("models/shoe_brake.py")
    with pytest.raises(md.OptimizeError, match="low < high"):
        md.optimize(brake.mechanism, brake.scenes["braking"], brake.params,
                    vary={"P": (100, 1)}, minimize="P")


def test_the_command_prints_the_optimum(capsys):
    status = main(["optimize", "models/shoe_brake.py", "--scene", "braking", "--vary",
                   "P=1:100", "R=50 mm:0.5", "--minimize", "P + 100*R", "--subject-to",
                   "t_end <= 20 s", "P <= 15 N"])
    out = capsys.readouterr().out
    assert status == 0
    assert "P = 15 N, R = 0.33333333 m" in out and "1.22222" in out


def test_the_sensitivities_command(capsys):
    status = main(["sensitivities", "models/shoe_brake.py", "--scene", "braking", "--wrt",
                   "P", "--measure", "t_end"])
    assert status == 0
    assert "s/N" in capsys.readouterr().out


def test_a_failing_run_names_the_point():
    machine, scene, J = _machine()
    machine.load("overload", -500, along=machine.coordinates[0])   # the motor gives <= 400
    with pytest.raises(md.OptimizeError, match=r"the run at J = 2 failed after 0 points"):
        md.optimize(machine, scene, {J: 2}, vary={J: (0.01, 10)}, minimize="fluctuation")

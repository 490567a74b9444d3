"""Duty cycles: phases run one after another from the previous end state.

Expected values come from closed forms and hand formulas, not from mechdyn: the motor
and flywheel of models/motor_startup.py (J = 5 kg m^2, constant load M_L = 60 N m, brake
M_b = 150 N m) coasts and brakes at constant deceleration; its start-up time is the
quadrature of J d omega / (M_Kloss(omega) - M_L). The press of models/press_cycle.py is
checked with its reduced inertia written by hand: kinetic energy across phase
boundaries, the workpiece's work as the integral of its force over the crank angle, the
braking stop angle from the energy balance and the stop time by quadrature, and the
brake's holding moment against the ram's weight.
"""
import csv
import math
import re
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq

import mechdyn as md
from mechdyn import cli

ROOT = Path(__file__).resolve().parents[1]
MOTOR = ROOT / "models" / "motor_startup.py"
PRESS = ROOT / "models" / "press_cycle.py"

# models/motor_startup.py
J, M_K, S_K, OMEGA_S, M_L, M_B = 5.0, 200.0, 0.2, 157.08, 60.0, 150.0


def kloss(omega):
    slip = (OMEGA_S - omega) / OMEGA_S
    return 2 * M_K * slip * S_K / (slip ** 2 + S_K ** 2)


@pytest.fixture(scope="module")
def motor_cycle():
    model = md.load_model(MOTOR)
    phi = model.mechanism.coordinates[0]
    coast = md.Scene("coast", effects=["load"], t_end=2, outputs=["load"])
    brake = md.Scene("brake", effects=["brake", "load"], until=md.stopped(phi),
                     outputs=["brake"])
    hold = md.Scene("hold", effects=["brake", "load"], t_end="1.5 s",
                    initial={md.speed(phi): 0}, outputs=["brake"])   # restates: at rest
    return phi, md.duty_cycle(model, ["startup", coast, brake, hold])


def test_motor_cycle_against_closed_forms(motor_cycle):
    phi, cycle = motor_cycle
    omega = md.speed(phi)
    startup, coast, brake, hold = cycle.phases
    # Start-up to 95 % of the steady speed: t = int J d omega / (M(omega) - M_L).
    slip = S_K * (M_K - math.sqrt(M_K ** 2 - M_L ** 2)) / M_L
    target = 0.95 * OMEGA_S * (1 - slip)
    t_startup = quad(lambda w: J / (kloss(w) - M_L), 0, target, epsabs=0, epsrel=1e-12)[0]
    assert startup.end == pytest.approx(t_startup, rel=1e-8)
    # Time and state run on: each phase starts where the one before ended.
    for before, after in zip(cycle.phases, cycle.phases[1:]):
        assert after.start == before.end
        assert after.result.y[0][0] == before.result.y[0][-1]
        # the speed too; a brake that sticks at the start makes it exactly zero
        assert after.result.y[1][0] == pytest.approx(before.result.y[1][-1], abs=1e-12)
        assert after.energy.kinetic[0] == pytest.approx(before.energy.kinetic[1], abs=1e-12)
    assert startup.energy.kinetic[1] == pytest.approx(J * target ** 2 / 2, rel=1e-9)
    # Coasting 2 s against M_L alone: omega drops by M_L t / J = 24 rad/s.
    w0 = coast.result.y[1][0]
    assert cycle.at(coast.start + 2.0, omega) == pytest.approx(w0 - 24.0, rel=1e-10)
    travel = w0 * 2.0 - M_L / J * 2.0 ** 2 / 2
    assert coast.energy.work["load"] == pytest.approx(-M_L * travel, rel=1e-9)
    # Braking with M_b + M_L: stops after J omega_0 / (M_b + M_L).
    w1 = brake.result.y[1][0]
    assert brake.end - brake.start == pytest.approx(J * w1 / (M_B + M_L), rel=1e-9)
    assert brake.reason == "stopped(phi)"
    # Holding: the brake holds the load moment, the speed stays exactly zero.
    assert np.all(hold.result[omega] == 0.0)
    assert np.all(cycle.at(np.linspace(hold.start, hold.end, 50), omega) == 0.0)
    assert np.allclose(hold.result["brake"], M_L, rtol=1e-12)
    assert cycle.t_end == pytest.approx(hold.start + 1.5, rel=1e-14)
    # Energy balance per phase: dT + dV = work of the loads, brake and dampers.
    for p in cycle.phases:
        scale = max([abs(w) for w in p.energy.work.values()] + [1.0])
        assert abs(p.energy.residual) < 1e-8 * scale, p.name


def test_cycle_arrays_csv_and_summary(motor_cycle, tmp_path):
    phi, cycle = motor_cycle
    # Step points: a boundary appears as the end of one phase and the start of the next.
    assert len(cycle.t) == sum(len(p.result.t) for p in cycle.phases)
    assert np.all(np.diff(cycle.t) >= 0)
    assert np.isnan(cycle["load"][:len(cycle.phases[0].result.t)]).all()   # not recorded
    path = cycle.to_csv(tmp_path / "cycle.csv", sample=0.5, units={"speed": "rpm"})
    with open(path) as handle:
        rows = list(csv.DictReader(handle))
    assert list(rows[0])[:4] == ["t [s]", "phase", "phi [rad]", "phidot [rpm]"]
    phases = [row["phase"] for row in rows]
    assert phases == sorted(phases, key=["startup", "coast", "brake", "hold"].index)
    for row in rows:
        t = float(row["t [s]"])
        assert row["phase"] == cycle.phase_at(t)[0]
        assert float(row["phidot [rpm]"]) == pytest.approx(
            cycle.at(t, md.speed(phi)) * 30 / math.pi, rel=1e-12, abs=1e-12)
    text = cycle.summary()
    for p in cycle.phases:
        assert f"phase {p.number} {p.name!r}" in text
    assert text.count("energy: T") == 4
    assert re.search(r"phase 3 'brake'.*\n.*\n.*\n    energy: T [\d.]+ kJ -> [-+e\d.]+ J, "
                     r"V 0 J -> 0 J; work: load -[\d.]+ kJ, brake -[\d.]+ kJ", text)
    figure = cycle.plot(units={"speed": "rpm"})
    strip = figure.axes[0]
    names = [t.get_text() for t in strip.texts if t.get_fontweight() == "bold"]
    assert names == ["startup", "coast", "brake", "hold"]


# ------------------------------------------------------------------- the press
R, L, M_R, J_C, J_M, J_F, I, G, MB_FAST = 0.05, 0.25, 150.0, 2.0, 0.02, 1.5, 15, 9.81, 80.0
F_P, PHI_W, BETA = 60e3, 5 * math.pi / 6, math.pi / 6
LAM = R / L


def stroke(phi):
    return R * (1 - math.cos(phi)) + L * (1 - math.sqrt(1 - LAM ** 2 * math.sin(phi) ** 2))


def stroke_rate(phi):          # ds/dphi
    return R * math.sin(phi) * (1 + LAM * math.cos(phi) / math.sqrt(1 - LAM ** 2
                                                                    * math.sin(phi) ** 2))


def inertia(phi):              # reduced to the crank, by hand
    return J_C + (J_M + J_F) * I ** 2 + M_R * stroke_rate(phi) ** 2


def process_force(phi):
    pulse = (math.cos(phi - PHI_W) - math.cos(BETA)) / (1 - math.cos(BETA))
    return F_P * max(pulse, 0.0)


@pytest.fixture(scope="module")
def press():
    model = md.load_model(PRESS)
    return model, md.duty_cycle(model, "startup+steady+braking+hold")


def test_press_cycle_summary_shows_values_at_rest_as_zero(press):
    # The braking phase ends at stopped(phi): the flywheel is at rest, its speed and
    # kinetic energy are 0, not rounding residue (-7.8e-16 rad/s, 1e-28 J); the ram's
    # potential energy at the start and the workpiece's force after the stroke are 0,
    # not "-0".
    _, cycle = press
    text = re.sub(r"\(balance [^)]*\)", "", cycle.summary())   # the balance is a residue
    braking = text.split("phase 3")[1].split("phase 4")[0]
    assert re.search(r"speed [1-9][\d.]* -> 0, peak", braking)
    assert re.search(r"T [1-9][\d.]* kJ -> 0 J", braking)
    assert not re.search(r"(?<![\w.])-0(?![.\d])", text), text
    assert not re.search(r"e-(1[3-9]|[2-9]\d)\b", text), text


def test_press_cycle_by_hand(press):
    model, cycle = press
    phi = model.mechanism.coordinates[0]
    omega = md.speed(phi)
    startup, steady, braking, hold = cycle.phases
    # Start-up ends at 95 rpm (a stop value with a unit), exactly continued.
    assert startup.result.y[1][-1] == pytest.approx(95 * math.pi / 30, rel=1e-10)
    phi_1, w_1 = startup.result.y[:, -1]
    kinetic = inertia(phi_1) * w_1 ** 2 / 2
    assert startup.energy.kinetic[1] == pytest.approx(kinetic, rel=1e-12)
    assert steady.energy.kinetic[0] == pytest.approx(kinetic, rel=1e-12)
    assert steady.end - steady.start == pytest.approx(10.0, rel=1e-14)
    # The workpiece's work depends on the crank angle alone: -int F s' dphi.
    phi_a, phi_b = steady.result.y[0][[0, -1]]
    edges = [PHI_W - BETA + 2 * math.pi * k for k in range(-1, 30)]
    windows = [(max(e, phi_a), min(e + 2 * BETA, phi_b)) for e in edges]
    work = -sum(quad(lambda x: process_force(x) * stroke_rate(x), a, b, epsabs=0,
                     epsrel=1e-12)[0] for a, b in windows if b > a)
    assert work < -10e3                                 # about 16 strokes of 852 J
    assert steady.energy.work["workpiece"] == pytest.approx(work, rel=1e-7)
    # Braking: the energy balance gives the stop angle, quadrature the stop time.
    phi_0, w_0 = braking.result.y[:, 0]
    brake_moment = I * MB_FAST                         # at the crank

    def energy_left(x):       # T at angle x: T0 + m g (s(x) - s(phi_0)) - i M_b (x - phi_0)
        return (inertia(phi_0) * w_0 ** 2 / 2 + M_R * G * (stroke(x) - stroke(phi_0))
                - brake_moment * (x - phi_0))
    reach = inertia(phi_0) * w_0 ** 2 / (brake_moment - M_R * G * R * (1 + LAM))  # bound
    phi_stop = brentq(energy_left, phi_0, phi_0 + reach, xtol=1e-14)
    assert braking.result.y[0][-1] == pytest.approx(phi_stop, abs=1e-8)

    def dt_du(u):             # phi = phi_stop - u^2: smooth at the stop
        x = phi_stop - u * u
        left = brake_moment * u * u - M_R * G * (stroke(phi_stop) - stroke(x))
        return 2 * u / math.sqrt(2 * left / inertia(x))
    t_stop = quad(dt_du, 0, math.sqrt(phi_stop - phi_0), epsabs=0, epsrel=1e-12, limit=200)[0]
    assert braking.end - braking.start == pytest.approx(t_stop, rel=1e-7)
    assert braking.energy.work["brake"] == pytest.approx(-brake_moment * (phi_stop - phi_0),
                                                         rel=1e-9)
    # Holding: exactly at rest; the brake (on the fast shaft) holds the ram's weight.
    assert np.all(hold.result[omega] == 0.0)
    assert np.all(hold.result[phi] == hold.result[phi][0])
    holding = -M_R * G * stroke_rate(hold.result.y[0][0]) / I
    assert np.allclose(hold.result["brake"], holding, rtol=1e-9)
    for p in cycle.phases:
        scale = max([abs(w) for w in p.energy.work.values()] + [1.0])
        assert abs(p.energy.residual) < 1e-7 * scale, p.name


def test_press_cycle_on_the_command_line(capsys, tmp_path):
    out = tmp_path / "cycle.csv"
    status = cli.main(["simulate", str(PRESS), "--scene", "startup+steady+braking+hold",
                       "--csv", str(out), "--plot", str(tmp_path / "cycle.png"),
                       "--units", "speed=rpm,power=kW"])
    text, err = capsys.readouterr()
    assert status == 0, err
    assert "duty cycle startup+steady+braking+hold: 4 phases" in text
    assert text.count("    energy: T") == 4
    with open(out) as handle:
        rows = list(csv.DictReader(handle))
    assert {row["phase"] for row in rows} == {"startup", "steady", "braking", "hold"}
    assert (tmp_path / "cycle.png").stat().st_size > 10_000


# ------------------------------------------------------------ continuity rules
def test_a_later_phase_may_not_change_the_speed(capsys):
    status = cli.main(["simulate", str(MOTOR), "--scene", "startup+braking"])
    _, err = capsys.readouterr()
    assert status == 2
    slip = S_K * (M_K - math.sqrt(M_K ** 2 - M_L ** 2)) / M_L
    steady = OMEGA_S * (1 - slip)          # the braking scene's own start; startup: 95 %
    assert f"phase 'braking' gives phidot = {steady:.6g} rad/s" in err
    assert f"starts where phase 'startup' ended, at phidot = {0.95 * steady:.6g}" in err
    assert "state continuity: its speed is continuous" in err


def test_a_free_coordinate_may_be_reset_a_bound_one_not():
    model = md.load_model(MOTOR)
    phi = model.mechanism.coordinates[0]           # the equations do not contain phi
    coast = md.Scene("coast", effects=["load"], t_end=1, initial={phi: 0})
    cycle = md.duty_cycle(model, ["startup", coast])
    second = cycle.phases[1].result
    assert second.y[0][0] == 0.0 and cycle.phases[0].result.y[0][-1] > 600
    assert second.y[1][0] == cycle.phases[0].result.y[1][-1]      # speed continues
    press = md.load_model(PRESS)
    angle = press.mechanism.coordinates[0]
    steady = md.Scene("steady", effects=["motor", "gravity"], t_end=1, initial={angle: 0})
    with pytest.raises(md.DutyCycleError, match="equations contain this coordinate"):
        md.duty_cycle(press, ["startup", steady])


def test_phases_with_different_coordinates_are_refused():
    hoist = md.load_model(ROOT / "models" / "hoist_drive.py")
    with pytest.raises(md.DutyCycleError, match="has the coordinates phi \\(rigid: rope\\) "
                       "but phase 'lift_start' has phi, h: the phases of a duty cycle keep"):
        md.duty_cycle(hoist, "lift_start+lift_start_rigid")


@pytest.mark.parametrize("phases, params, message", [
    ("startup+nothing", None, "no scene 'nothing'"),
    ([], None, "no phases"),
    ("startup+braking", {"M_Q": 3}, "unknown parameter 'M_Q'"),
])
def test_bad_cycles_are_named(phases, params, message):
    model = md.load_model(MOTOR)
    with pytest.raises(md.MechdynError, match=message):
        md.duty_cycle(model, phases, params)


def test_a_phase_scene_alone_says_how_to_run_it():
    press = md.load_model(PRESS)
    with pytest.raises(md.SceneError, match="later phase of a duty cycle"):
        press.mechanism.simulate(press.scenes["steady"], press.params)

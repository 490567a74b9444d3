"""Exact sensitivities (md.sensitivities): closed forms where they exist, central finite
differences of an independent high-precision integration elsewhere."""
import math

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

import mechdyn as md


@pytest.mark.parametrize("backend", ["auto", "scipy"])
def test_shoe_brake_stop_time_and_angle_against_the_closed_forms(backend):
    brake = md.load_model("models/shoe_brake.py")
    I, f, P, R = (brake.param_symbol(n) for n in "IfPR")
    omega0 = 100
    time = I * omega0 / (2 * f * P * R)             # constant deceleration 2 f P R / I
    angle = I * omega0 ** 2 / (4 * f * P * R)
    s = md.sensitivities(brake.mechanism, brake.scenes["braking"], brake.params,
                         wrt=["I", "f", "P", "R"], measures=["t_end", "stop_angle", "final:phi"],
                         backend=backend)
    values = {sym: brake.params[sym] for sym in (I, f, P, R)}
    assert s.results["t_end"] == pytest.approx(float(time.subs(values)), rel=1e-10)
    for sym in (I, f, P, R):
        for measure, form in (("t_end", time), ("stop_angle", angle), ("final:phi", angle)):
            exact = float(sp.diff(form, sym).subs(values))
            assert s[measure, sym.name] == pytest.approx(exact, rel=1e-8), (measure, sym)
        assert s.relative("t_end", sym.name) == pytest.approx(1 if sym is I else -1, rel=1e-8)


def _startup():
    phi = md.coordinate("phi")
    J, M_0, omega_0, M_L, w_s, w_1 = sp.symbols("J M_0 omega_0 M_L w_s w_1", positive=True)
    drive = md.Mechanism("linear motor", [phi], units={
        J: "kg*m^2", M_0: "N*m", omega_0: "rad/s", M_L: "N*m", w_s: "rad/s", w_1: "rad/s"})
    drive.link("rotor", J=J, angle=phi)
    drive.load("motor", md.motors.dc_shunt(M_0, omega_0)(md.speed(phi)), along=phi)
    drive.load("load", -M_L, along=phi)
    scene = md.Scene("startup", initial={phi: 0, md.speed(phi): w_s},
                     until=md.reaches(md.speed(phi), w_1))
    values = {J: 2.0, M_0: 100.0, omega_0: 150.0, M_L: 30.0, w_s: 10.0, w_1: 90.0}
    # J w' = M_0 (1 - w/omega_0) - M_L: w -> w_inf with time constant tau
    tau, w_inf = J * omega_0 / M_0, omega_0 * (1 - M_L / M_0)
    return drive, scene, values, tau * sp.log((w_inf - w_s) / (w_inf - w_1))


@pytest.mark.parametrize("backend", ["auto", "scipy"])
def test_start_up_time_of_a_linear_motor_characteristic_against_its_closed_form(backend):
    drive, scene, values, time = _startup()
    names = [s.name for s in values]
    s = drive.sensitivities(scene, values, wrt=names, measures=["t_end", "final:phidot"],
                            backend=backend)
    assert s.results["t_end"] == pytest.approx(float(time.subs(values)), rel=1e-9)
    for sym in values:
        assert s["t_end", sym.name] == pytest.approx(float(sp.diff(time, sym).subs(values)),
                                                     rel=1e-8), sym
        # the end speed is the condition's value: d w(t*)/dp = d w_1/dp
        assert s["final:phidot", sym.name] == pytest.approx(
            1.0 if sym.name == "w_1" else 0.0, abs=1e-8)


def test_a_final_state_at_the_time_limit():
    phi = md.coordinate("phi")
    J, M = sp.symbols("J M", positive=True)
    disc = md.Mechanism("disc", [phi])
    disc.link("disc", J=J, angle=phi)
    disc.load("drive", M, along=phi)
    scene = md.Scene("run", initial={phi: 0, md.speed(phi): 1}, t_end=3)
    s = md.sensitivities(disc, scene, {J: 2, M: 6}, wrt=[J, M],
                         measures=["final:phi", "final:phidot", "t_end"])
    # phi(T) = T + M T^2 / (2 J): d/dJ = -M T^2 / (2 J^2), d/dM = T^2 / (2 J)
    assert s["final:phi", "J"] == pytest.approx(-6 * 9 / 8, rel=1e-9)
    assert s["final:phi", "M"] == pytest.approx(9 / 4, rel=1e-9)
    assert s["final:phidot", "J"] == pytest.approx(-6 * 3 / 4, rel=1e-9)
    assert s["t_end", "J"] == 0.0


# ------------------------------------------------------------ steady running
def _slider_crank():
    phi = md.coordinate("phi")
    r, L, J_f, m_2, m_3, M_0, omega_0, F_p = sp.symbols(
        "r L J_f m_2 m_3 M_0 omega_0 F_p", positive=True)
    rod_run = sp.sqrt(L ** 2 - r ** 2 * sp.sin(phi) ** 2)
    x = r * sp.cos(phi) + rod_run
    mech = md.Mechanism("slider-crank with flywheel", [phi], units={
        r: "m", L: "m", J_f: "kg*m^2", m_2: "kg", m_3: "kg", M_0: "N*m",
        omega_0: "rad/s", F_p: "N"})
    mech.link("flywheel", J=J_f, angle=phi)
    mech.link("rod", m=m_2, x=r * sp.cos(phi) + rod_run / 2, y=r * sp.sin(phi) / 2)
    mech.link("slider", m=m_3, x=x)
    mech.load("motor", md.motors.dc_shunt(M_0, omega_0)(md.speed(phi)), along=phi)
    mech.load("process", F_p * sp.sin(phi), along=x)           # takes work every turn
    params = {r: 0.1, L: 0.4, J_f: 0.5, m_2: 0.5, m_3: 2.0, M_0: 50.0, omega_0: 100.0,
              F_p: 300.0}
    scene = md.Scene("run", initial={phi: 0, md.speed(phi): 70}, t_end=1)
    return mech, scene, params


def _precise_steady(mech, scene, params):
    """Mean speed and delta of steady running, integrated here at rtol 1e-13 (brentq on
    the cycle map, the extremes polished on the dense output)."""
    eqs = mech.equations(scene)
    a = (eqs.smooth_forcing[0] / eqs.mass_matrix[0, 0]).xreplace(
        {k: sp.Float(v) for k, v in params.items()})
    accel = sp.lambdify((eqs.q[0], eqs.u[0]), a)

    def cycle(w, dense=False):
        return solve_ivp(lambda x, z: [accel(x, z[0]) / z[0], 1 / z[0]], (0, 2 * math.pi),
                         [w, 0], method="DOP853", rtol=1e-13, atol=1e-13, dense_output=dense)
    w0 = brentq(lambda w: cycle(w).y[0, -1] - w, 20, 99, xtol=1e-13, rtol=1e-15)
    sol = cycle(w0, dense=True)
    grid = np.linspace(0, 2 * math.pi, 20001)
    speeds = sol.sol(grid)[0]
    extremes = []
    for sign in (-1, 1):
        from scipy.optimize import minimize_scalar
        k = int(np.argmin(sign * speeds))
        found = minimize_scalar(lambda x: sign * sol.sol(x)[0], method="bounded",
                                bounds=(grid[max(k - 1, 0)], grid[min(k + 1, 20000)]),
                                options={"xatol": 1e-12})
        extremes.append(sign * found.fun)
    mean = 2 * math.pi / sol.y[1, -1]
    return np.array([mean, (extremes[0] - extremes[1]) / mean, sol.y[1, -1]])


@pytest.mark.slow
def test_mean_speed_and_fluctuation_against_central_differences():
    mech, scene, params = _slider_crank()
    s = md.sensitivities(mech, scene, params, wrt=["J_f", "M_0", "r"],
                         measures=["mean_speed", "fluctuation", "cycle_time"])
    assert [s.results["mean_speed"], s.results["fluctuation"], s.results["cycle_time"]] == \
        pytest.approx(_precise_steady(mech, scene, params), rel=1e-8)
    for name in ("J_f", "M_0", "r"):
        sym = next(k for k in params if k.name == name)
        h = 1e-2 * params[sym]
        values = [_precise_steady(mech, scene, {**params, sym: params[sym] + k * h})
                  for k in (-2, -1, 1, 2)]
        central = (values[0] - 8 * values[1] + 8 * values[2] - values[3]) / (12 * h)
        assert s["mean_speed", name] == pytest.approx(central[0], rel=1e-5), name
        assert s["fluctuation", name] == pytest.approx(central[1], rel=1e-5), name
        assert s["cycle_time", name] == pytest.approx(central[2], rel=1e-5), name


def test_steady_measures_agree_with_steady_running_and_print_as_a_table():
    mech, scene, params = _slider_crank()
    s = md.sensitivities(mech, scene, params, wrt=["J_f"], measures=["fluctuation", "mean_speed"])
    running = md.steady_running(mech, scene, params)
    # steady_running stops Newton at a residual of 1e-8 omega0 (this omega0 is polished)
    assert s.results["fluctuation"] == pytest.approx(running.delta, rel=1e-6)
    assert s.results["mean_speed"] == pytest.approx(running.omega_mean, rel=1e-7)
    text = str(s)
    assert "1/(kg*m^2)" in text and "rad/s/(kg*m^2)" in text
    assert "1 % more J_f changes fluctuation by -" in text
    assert s.relative("fluctuation", "J_f") == pytest.approx(
        s["fluctuation", "J_f"] * 0.5 / running.delta, rel=1e-6)


def test_the_bar_chart_is_written(tmp_path):
    brake = md.load_model("models/shoe_brake.py")
    s = md.sensitivities(brake.mechanism, brake.scenes["braking"], brake.params, ["I", "P"],
                         ["t_end", "stop_angle"], backend="scipy")
    s.plot(tmp_path / "bars.png")
    assert (tmp_path / "bars.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


# ------------------------------------------------------------------- refusals
def test_unknown_measures_and_parameters_are_named():
    brake = md.load_model("models/shoe_brake.py")
    scene = brake.scenes["braking"]
    with pytest.raises(md.SensitivityError, match="no measure 't_ned'.*did you mean t_end"):
        md.sensitivities(brake.mechanism, scene, brake.params, ["P"], ["t_ned"])
    with pytest.raises(md.SensitivityError, match="'Q' is not a parameter"):
        md.sensitivities(brake.mechanism, scene, brake.params, ["Q"], ["t_end"])


@pytest.mark.parametrize("backend", ["auto", "scipy"])
def test_friction_that_sticks_before_the_end_is_refused(backend):
    brake = md.load_model("models/shoe_brake.py")
    phi = brake.mechanism.coordinates[0]
    scene = md.Scene("long", effects=["shoe"], initial={phi: 0, md.speed(phi): 100},
                     t_end=80)
    with pytest.raises(md.SensitivityError, match="friction .shoe. sticks at t = 50"):
        md.sensitivities(brake.mechanism, scene, brake.params, ["P"], ["final:phi"],
                         backend=backend)


def _double_pendulum():
    a, b = md.coordinates("a b")
    m_1, m_2, l_1, l_2 = sp.symbols("m_1 m_2 l_1 l_2", positive=True)
    pendulum = md.Mechanism("double pendulum", [a, b])
    x_1, y_1 = l_1 * sp.sin(a), -l_1 * sp.cos(a)
    pendulum.link("upper", m=m_1, x=x_1, y=y_1)
    pendulum.link("lower", m=m_2, x=x_1 + l_2 * sp.sin(b), y=y_1 - l_2 * sp.cos(b))
    pendulum.gravity()
    initial = {a: 0.8, b: -0.3, md.speed(a): 0, md.speed(b): 0}
    return pendulum, {m_1: 1.0, m_2: 0.6, l_1: 0.5, l_2: 0.4}, initial, a


@pytest.mark.parametrize("backend", [pytest.param("auto", marks=pytest.mark.slow), "scipy"])
def test_two_coupled_coordinates_against_central_differences_of_simulate(backend):
    pendulum, params, initial, a = _double_pendulum()
    scene = md.Scene("swing", initial=initial, until=md.reaches(a, 0), t_end=5)
    names = [s.name for s in params]
    measures = ["t_end", "final:b", "final:adot", "final:bdot"]
    s = md.sensitivities(pendulum, scene, params, names, measures, backend=backend)

    def run(values):
        result = pendulum.simulate(scene, values)
        assert result.reason != "t_end"
        return np.array([result.t_end] + [result.final(m[6:]) for m in measures[1:]])
    assert s.results["t_end"] == pytest.approx(run(params)[0], rel=1e-9)
    for sym in params:
        h = 1e-4 * params[sym]
        central = (run({**params, sym: params[sym] + h}) -
                   run({**params, sym: params[sym] - h})) / (2 * h)
        exact = np.array([s[m, sym.name] for m in measures])
        assert exact == pytest.approx(central, rel=1e-5, abs=1e-6 * np.abs(central).max()), sym


def test_stop_angles_of_several_coordinates():
    pendulum, params, initial, a = _double_pendulum()
    scene = md.Scene("swing", initial=initial, until=md.reaches(a, 0), t_end=5)
    s = md.sensitivities(pendulum, scene, params, ["l_2"], ["stop_angle:b", "final:b"],
                         backend="scipy")
    assert s.results["stop_angle:b"] == pytest.approx(s.results["final:b"] + 0.3, rel=1e-12)
    assert s["stop_angle:b", "l_2"] == s["final:b", "l_2"]      # b starts at -0.3 whatever l_2
    with pytest.raises(md.SensitivityError, match="name one: stop_angle:a"):
        md.sensitivities(pendulum, scene, params, ["l_2"], ["stop_angle"], backend="scipy")
    timed = md.Scene("timed", initial=initial, t_end=0.1)
    with pytest.raises(md.SensitivityError, match="did not stop at a stop condition"):
        md.sensitivities(pendulum, timed, params, ["l_2"], ["stop_angle:a"], backend="scipy")


def test_guide_friction_reversing_at_every_dead_centre_against_central_differences():
    model = md.load_model("tests/data/slider_crank_flywheel.py")
    mech = model.mechanism
    phi = mech.coordinates[0]
    scene = md.Scene("run", effects=["motor", "guide"], initial={phi: 0.3, md.speed(phi): 50},
                     t_end=0.5, backend="scipy")
    params = {str(k): float(v) for k, v in model.params.items()}
    reference = mech.simulate(scene, params)
    assert sum(e.kind == "slip" for e in reference.events) >= 8     # it reverses, never sticks
    names = ["J_f", "F_r", "r"]
    s = md.sensitivities(mech, scene, params, names, ["final:phi", "final:phidot"],
                         backend="scipy")
    assert s.results["final:phidot"] == pytest.approx(reference.final("phidot"), rel=1e-9)
    for name in names:
        h = 1e-5 * params[name]
        up = mech.simulate(scene, {**params, name: params[name] + h})
        down = mech.simulate(scene, {**params, name: params[name] - h})
        for key in ("phi", "phidot"):
            central = (up.final(key) - down.final(key)) / (2 * h)
            assert s[f"final:{key}", name] == pytest.approx(central, rel=1e-6), (name, key)


@pytest.mark.parametrize("backend", ["auto", "scipy"])
def test_a_reversing_friction_moment_jumps_the_sensitivities(backend):
    # a disc shaken harder than its bearing holds: the friction moment reverses six times
    # and jumps by 2 F each time, so the sensitivities jump by (f- - f+) dt*/dp
    phi = md.coordinate("phi")
    J, A, w, F = sp.symbols("J A w F", positive=True)
    disc = md.Mechanism("shaken disc", [phi])
    disc.link("disc", J=J, angle=phi)
    disc.load("shaker", A * sp.sin(w * md.t), along=phi)
    disc.friction("bearing", F, along=phi)
    scene = md.Scene("run", initial={phi: 0, md.speed(phi): 0.5}, t_end=3, backend="scipy")
    params = {"J": 0.2, "A": 10.0, "w": 7.0, "F": 2.0}
    reference = disc.simulate(scene, params)
    assert [e.kind for e in reference.events].count("slip") == 6
    s = md.sensitivities(disc, scene, params, list(params), ["final:phi", "final:phidot"],
                         backend=backend)
    for name in params:
        h = 1e-6 * params[name]
        up = disc.simulate(scene, {**params, name: params[name] + h})
        down = disc.simulate(scene, {**params, name: params[name] - h})
        for key in ("phi", "phidot"):
            central = (up.final(key) - down.final(key)) / (2 * h)
            assert s[f"final:{key}", name] == pytest.approx(central, rel=1e-6), (name, key)

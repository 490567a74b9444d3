"""Closed kinematic loops: declaration, position/velocity/acceleration analysis, reduced
inertia, simulation with the loop constraints, kinetostatics and balancing.

Expected values come from independent derivations written out here: Freudenstein's
closed form of the four-bar, its velocity and acceleration loop equations solved by
hand, the textbook reduced inertia, Newton's laws per link, the law of cosines.
"""
import math
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

import mechdyn as md

ROOT = Path(__file__).resolve().parents[1]

A, B, C, D = 0.1, 0.35, 0.3, 0.4          # crank, coupler, rocker, ground (crank-rocker)
J1, M2, M3 = 0.002, 1.5, 1.2
J2, J3 = M2 * B**2 / 12, M3 * C**2 / 12   # about the centres (bars)
G = 9.81


def four_bar(gravity=True, loads=False):
    phi, th2, th3 = md.coordinates("phi theta_2 theta_3")
    mech = md.Mechanism("four-bar", [phi, th2, th3], independent=[phi])
    pin = (A * sp.cos(phi), A * sp.sin(phi))
    mech.link("crank", J=J1, angle=phi)
    mech.link("coupler", m=M2, J=J2, x=pin[0] + B / 2 * sp.cos(th2),
              y=pin[1] + B / 2 * sp.sin(th2), angle=th2)
    mech.link("rocker", m=M3, J=J3, x=D + C / 2 * sp.cos(th3), y=C / 2 * sp.sin(th3),
              angle=th3)
    mech.loop("ABCD", (A, phi), (B, th2), (-C, th3), (-D, 0))
    mech.joint("O", ("frame", "crank"), at=(0, 0))
    mech.joint("A", ("crank", "coupler"), at=pin)
    mech.joint("B", ("coupler", "rocker"), at=(D + C * sp.cos(th3), C * sp.sin(th3)))
    mech.joint("D", ("frame", "rocker"), at=(D, 0))
    if gravity:
        mech.gravity(G)
    if loads:
        mech.load("motor", 5 - 0.1 * md.speed(phi), along=phi, on="crank")
        mech.load("work", -3 * sp.cos(th3), along=th3)
    return mech, (phi, th2, th3)


# ------------------------------------------------------------ independent closed forms
def freudenstein(phi, branch=+1):
    """theta_2, theta_3 of the loop A e^(i phi) + B e^(i th2) - C e^(i th3) - D = 0:
    |D + C e^(i th3) - A e^(i phi)| = B gives P cos th3 + Q sin th3 = R."""
    p = 2 * C * (D - A * np.cos(phi))
    q = -2 * A * C * np.sin(phi)
    r = B**2 - A**2 - C**2 - D**2 + 2 * A * D * np.cos(phi)
    th3 = np.arctan2(q, p) + branch * np.arccos(r / np.hypot(p, q))
    bx = D + C * np.cos(th3) - A * np.cos(phi)
    by = C * np.sin(th3) - A * np.sin(phi)
    return np.arctan2(by, bx), th3


def ratios_by_hand(phi, th2, th3):
    """First and second order transmission functions from the velocity loop
    A e^(i phi) + B w2 e^(i th2) = C w3 e^(i th3) and its derivative."""
    w2 = -A * np.sin(phi - th3) / (B * np.sin(th2 - th3))
    w3 = A * np.sin(phi - th2) / (C * np.sin(th3 - th2))
    # i A e^(i phi) (phi'' = 0, phi' = 1) differentiated:
    # -A e^(i phi) + B (i a2 - w2^2) e^(i th2) - C (i a3 - w3^2) e^(i th3) = 0
    rhs = A * np.exp(1j * phi) + B * w2**2 * np.exp(1j * th2) - C * w3**2 * np.exp(1j * th3)
    u, v = 1j * B * np.exp(1j * th2), -1j * C * np.exp(1j * th3)   # a2 u + a3 v = rhs
    det = u.real * v.imag - v.real * u.imag
    a2 = (rhs.real * v.imag - v.real * rhs.imag) / det
    a3 = (u.real * rhs.imag - rhs.real * u.imag) / det
    return w2, w3, a2, a3


def inertia_by_hand(phi, th2, th3):
    """I_red = J1 + m2 (v_S2/w)^2 + J2 w2^2 + (J3 + m3 (C/2)^2) w3^2."""
    w2, w3, _, _ = ratios_by_hand(phi, th2, th3)
    v2 = A**2 + (B / 2 * w2) ** 2 + A * B * w2 * np.cos(phi - th2)
    return J1 + M2 * v2 + J2 * w2**2 + (J3 + M3 * (C / 2) ** 2) * w3**2


GUESS = {"theta_2": 1.2, "theta_3": 1.9}


def linkage(mech, coords, **kw):
    phi, th2, th3 = coords
    return md.Linkage(mech, guess={th2: GUESS["theta_2"], th3: GUESS["theta_3"]}, **kw)


# ------------------------------------------------------------------------ kinematics
def test_position_analysis_matches_freudenstein_to_1e_12():
    mech, coords = four_bar()
    sweep = linkage(mech, coords).sweep(np.linspace(0, 2 * np.pi, 73))
    th2, th3 = freudenstein(sweep.phi)
    for mine, exact in ((sweep["theta_2"], th2), (sweep["theta_3"], th3)):
        difference = np.angle(np.exp(1j * (mine - exact)))      # modulo 2 pi
        assert np.max(np.abs(difference)) < 1e-12


def test_transmission_functions_match_finite_differences_and_the_loop_equations():
    mech, coords = four_bar()
    phi = np.linspace(0.05, 2 * np.pi, 40)
    sweep = linkage(mech, coords).sweep(phi)
    h = 1e-3          # fourth-order central differences of the closed-form positions

    def derivative(f, order):
        values = [np.unwrap(np.array(f(phi + k * h))) for k in (-2, -1, 0, 1, 2)]
        if order == 1:
            return (values[0] - 8 * values[1] + 8 * values[3] - values[4]) / (12 * h)
        return (-values[0] + 16 * values[1] - 30 * values[2] + 16 * values[3]
                - values[4]) / (12 * h * h)
    for k, row in ((0, "theta_2"), (1, "theta_3")):
        index = sweep.names.index(row)
        first = derivative(lambda x: freudenstein(x)[k], 1)
        second = derivative(lambda x: freudenstein(x)[k], 2)
        assert np.max(np.abs(sweep.ratio[index] - first)) < 1e-9
        assert np.max(np.abs(sweep.second[index] - second)) < 1e-6
    th2, th3 = freudenstein(phi)
    w2, w3, a2, a3 = ratios_by_hand(phi, th2, th3)
    assert np.allclose(sweep.ratio[1:], [w2, w3], rtol=1e-12, atol=1e-13)
    assert np.allclose(sweep.second[1:], [a2, a3], rtol=1e-10, atol=1e-12)


def test_reduced_inertia_matches_the_closed_form_numerically_and_symbolically():
    mech, coords = four_bar()
    phi = np.linspace(0, 2 * np.pi, 25)
    lk = linkage(mech, coords)
    sweep = lk.sweep(phi)
    th2, th3 = freudenstein(phi)
    expected = inertia_by_hand(phi, th2, th3)
    assert np.allclose(sweep.inertia, expected, rtol=1e-12)
    h = 1e-4
    slope = (inertia_by_hand(phi + h, *freudenstein(phi + h))
             - inertia_by_hand(phi - h, *freudenstein(phi - h))) / (2 * h)
    assert np.allclose(sweep.inertia_slope, slope, rtol=1e-6, atol=1e-9)
    symbolic = sp.lambdify(sp.symbols("phi theta_2 theta_3"), mech.reduced_inertia())
    assert np.allclose(symbolic(phi, th2, th3), expected, rtol=1e-12)


def test_grashof_crank_range_and_rocker_swing_match_the_law_of_cosines():
    mech, coords = four_bar()
    lk = linkage(mech, coords)
    assert lk.grashof().kind == "crank-rocker" and lk.crank_range() is None
    assert lk.singularities() == []
    # rocker extremes: crank and coupler in line, |DB| = C, |OB| = B +- A
    swing = sorted(value for _, value in lk.extremes("theta_3"))
    for reach, found in zip((B - A, B + A), swing[::-1]):
        angle_at_d = math.acos((D**2 + C**2 - reach**2) / (2 * D * C))
        assert abs(found - (math.pi - angle_at_d)) < 1e-10
    assert md.grashof(2, 3, 3.5, 5).kind == "triple-rocker (non-Grashof)"
    assert md.grashof(1, 2, 1, 2).change_point


def test_non_grashof_crank_range_and_toggle_are_named_with_the_crank_angle():
    phi, th2, th3 = md.coordinates("phi theta_2 theta_3")
    rocker = md.Mechanism("triple rocker", [phi, th2, th3])
    for name, angle in (("input", phi), ("coupler", th2), ("output", th3)):
        rocker.link(name, J=1, angle=angle)
    rocker.loop("loop", (3, phi), (3.5, th2), (-5, th3), (-2, 0))
    lk = md.Linkage(rocker, guess={phi: np.pi, th2: 1.2, th3: 2.2})
    limit = math.acos((13 - 1.5**2) / 12)     # |A - D|^2 = 13 - 12 cos phi = (5 - 3.5)^2
    low, high = lk.crank_range()
    assert abs(low - limit) < 1e-10 and abs(high - (2 * np.pi - limit)) < 1e-10
    toggles = lk.singularities()
    assert [s.kind for s in toggles] == ["toggle", "toggle"]
    assert toggles[0].loop == "loop" and abs(toggles[0].at - limit) < 1e-10
    with pytest.raises(md.LinkageError, match="phi = 0.2") as error:
        lk.position(0.2)
    assert error.value.at == 0.2


# ------------------------------------------------------------------------ simulation
def test_energy_of_a_conservative_four_bar_over_100_revolutions():
    mech, (phi, th2, th3) = four_bar()
    omega = 30.0
    scene = md.Scene("free", initial={phi: 0, md.speed(phi): omega, th2: 1.2, th3: 1.9},
                     t_end=100 * 2 * np.pi / 25)
    result = mech.simulate(scene, {})
    assert result.final(phi) > 100 * 2 * np.pi
    kinetic, potential = result.energy()
    total = kinetic + potential
    assert np.max(np.abs(total - total[0])) < 1e-7 * kinetic[0]
    th2_end, th3_end = freudenstein(result.final(phi))     # still on the loop
    assert abs(np.angle(np.exp(1j * (result.final(th3) - th3_end)))) < 1e-8


def test_dependent_speeds_are_assembled_from_the_loop():
    mech, (phi, th2, th3) = four_bar()
    scene = md.Scene("s", initial={phi: 0.3, md.speed(phi): 2, th2: 1.2, th3: 1.9}, t_end=0.1)
    result = mech.simulate(scene, {})
    exact2, exact3 = freudenstein(0.3)
    w2, w3, _, _ = ratios_by_hand(0.3, exact2, exact3)
    state = result.y[:, 0]
    assert np.allclose(state, [0.3, exact2, exact3, 2, 2 * w2, 2 * w3], rtol=1e-12)


def test_loop_multipliers_are_the_joint_force_at_the_cut():
    """lambda of loop ABCD acts on the links of its positive terms (crank, coupler) at
    the closing joint B: it is the force of the rocker on the coupler, -R_B."""
    mech, (phi, th2, th3) = four_bar(loads=True)
    scene = md.Scene("run", initial={phi: 0, md.speed(phi): 10, th2: 1.2, th3: 1.9},
                     t_end=0.3, outputs=["ABCD"])
    result = mech.simulate(scene, {})
    j = len(result.t) // 2
    state = result.y[:, j]
    eps = result.accelerations[0, j]
    statics = md.kinetostatics(mech, {}, [state[0]], omega=state[3], eps=eps,
                               drive="motor", guess={th2: state[1], th3: state[2]})
    assert abs(statics.driving[0] - (5 - 0.1 * state[3])) < 1e-8
    reaction = statics.reactions["B"]
    assert abs(result["ABCD.x"][j] + reaction.x[0]) < 1e-8
    assert abs(result["ABCD.y"][j] + reaction.y[0]) < 1e-8


# --------------------------------------------------------------------- kinetostatics
def test_joint_reactions_balance_every_link():
    mech, coords = four_bar(loads=True)
    phi = np.linspace(0, 2 * np.pi, 13)
    omega, eps = 20.0, 35.0
    statics = md.kinetostatics(mech, {}, phi, omega=omega, eps=eps, drive="motor",
                               guess={coords[1]: 1.2, coords[2]: 1.9})
    th2, th3 = freudenstein(phi)
    w2, w3, a2, a3 = ratios_by_hand(phi, th2, th3)
    # angular speeds and accelerations of coupler and rocker, by hand
    om2, om3 = w2 * omega, w3 * omega
    al2, al3 = w2 * eps + a2 * omega**2, w3 * eps + a3 * omega**2
    e = lambda angle: np.array([np.cos(angle), np.sin(angle)])        # noqa: E731
    n = lambda angle: np.array([-np.sin(angle), np.cos(angle)])       # noqa: E731
    pin = A * e(phi)
    pin_acc = A * (eps * n(phi) - omega**2 * e(phi))
    s2 = pin + B / 2 * e(th2)
    a_s2 = pin_acc + B / 2 * (al2 * n(th2) - om2**2 * e(th2))
    s3 = np.array([D, 0])[:, None] + C / 2 * e(th3)
    a_s3 = C / 2 * (al3 * n(th3) - om3**2 * e(th3))
    joint_b = np.array([D, 0])[:, None] + C * e(th3)
    r = {k: np.array([v.x, v.y]) for k, v in statics.reactions.items()}
    cross = lambda arm, force: arm[0] * force[1] - arm[1] * force[0]  # noqa: E731
    scale = np.max(np.abs(np.concatenate(list(r.values()))))
    drive = statics.driving
    # crank: R_O - R_A = 0 (massless), moments about O: motor - pin x R_A = J1 eps
    assert np.max(np.abs(r["O"] - r["A"])) < 1e-9 * scale
    assert np.max(np.abs(drive - cross(pin, r["A"]) - J1 * eps)) < 1e-9 * scale
    # coupler: R_A - R_B + weight = m2 a_S2; moments about its centre
    weight2 = np.array([0, -M2 * G])[:, None]
    assert np.max(np.abs(r["A"] - r["B"] + weight2 - M2 * a_s2)) < 1e-9 * scale
    moment2 = cross(pin - s2, r["A"]) - cross(joint_b - s2, r["B"])
    assert np.max(np.abs(moment2 - J2 * al2)) < 1e-9 * scale
    # rocker: R_B + R_D + weight = m3 a_S3; moments about its centre with the work
    weight3 = np.array([0, -M3 * G])[:, None]
    assert np.max(np.abs(r["B"] + r["D"] + weight3 - M3 * a_s3)) < 1e-9 * scale
    moment3 = (cross(joint_b - s3, r["B"]) + cross(np.array([D, 0])[:, None] - s3, r["D"])
               - 3 * np.cos(th3))
    assert np.max(np.abs(moment3 - J3 * al3)) < 1e-9 * scale
    # the shaking force is the sum of the inertia forces
    assert np.allclose(statics.shaking_force, -(M2 * a_s2 + M3 * a_s3), atol=1e-9 * scale)


def test_driving_moment_equals_the_energy_method():
    """Kinetostatics and I_red eps + I_red' omega^2 / 2 - M_red,other give one moment."""
    mech, coords = four_bar(loads=True)
    lk = linkage(mech, coords)
    phi = np.linspace(0, 2 * np.pi, 9)
    statics = md.kinetostatics(mech, {}, phi, omega=15.0, eps=-4.0, drive="motor",
                               guess={coords[1]: 1.2, coords[2]: 1.9})
    th2, th3 = freudenstein(phi)
    h = 1e-5
    slope = (inertia_by_hand(phi + h, *freudenstein(phi + h))
             - inertia_by_hand(phi - h, *freudenstein(phi - h))) / (2 * h)
    other = lk.reduced_moment(phi, omega=15.0, exclude=("motor",))
    energy = inertia_by_hand(phi, th2, th3) * -4.0 + slope / 2 * 15.0**2 - other
    assert np.allclose(statics.driving, energy, rtol=1e-7, atol=1e-8)


def slider_crank(r=0.05, length=0.2, m1=0.8, r1=0.01, m2=0.6, m3=1.0, weights=()):
    phi, th, s = md.coordinates("phi theta s")
    mech = md.Mechanism("slider-crank", [phi, th, s], units={s: "m"})
    mech.link("crank", m=m1, J=0.001, x=r1 * sp.cos(phi), y=r1 * sp.sin(phi), angle=phi)
    mech.link("rod", m=m2, J=m2 * length**2 / 12, x=r * sp.cos(phi) + length / 2 * sp.cos(th),
              y=r * sp.sin(phi) + length / 2 * sp.sin(th), angle=th)
    mech.link("slider", m=m3, x=s)
    for name, (mass_radius, angle, sense) in weights:
        mech.link(name, m=mass_radius, x=sp.cos(sense * phi + angle),
                  y=sp.sin(sense * phi + angle))
    mech.loop("loop", (r, phi), (length, th), (-s, 0))
    return mech, {th: -0.1, s: 0.25}


def test_balanced_slider_crank_has_no_first_harmonic_of_shaking_force():
    r, m1, r1, m2, m3 = 0.05, 0.8, 0.01, 0.6, 1.0
    mech, guess = slider_crank(r, 0.2, m1, r1, m2, m3)
    plan = md.balance(mech, {}, guess=guess)
    # textbook: rod split half to pin, half to piston; forward m1 r1 + (m2/2 + rec/2) r
    # with rec = m3 + m2/2, backward rec r / 2
    assert abs(plan.crank.mass_radius - (m1 * r1 + 0.75 * m2 * r + 0.5 * m3 * r)) < 1e-12
    assert abs(plan.counter_rotating.mass_radius - (0.25 * m2 * r + 0.5 * m3 * r)) < 1e-12
    assert abs(plan.crank.angle - np.pi) < 1e-9
    assert abs(plan.counter_rotating.angle - np.pi) < 1e-9
    weights = [("counterweight", (plan.crank.mass_radius, plan.crank.angle, 1)),
               ("balancer", (plan.counter_rotating.mass_radius, plan.counter_rotating.angle,
                             -1))]
    balanced, guess = slider_crank(r, 0.2, m1, r1, m2, m3, weights)
    phi = 2 * np.pi * np.arange(64) / 64
    before, _ = md.shaking(mech, {}, phi, omega=30, guess=guess)
    after, _ = md.shaking(balanced, {}, phi, omega=30, guess=guess)
    first = lambda f: np.abs(np.fft.fft(f[0] + 1j * f[1])[[1, -1]]) / 64   # noqa: E731
    assert np.min(first(before)) > 10                            # N, unbalanced
    assert np.max(first(after)) < 1e-10 * np.max(first(before))
    second = lambda f: np.abs(np.fft.fft(f[0] + 1j * f[1])[[2, -2]]) / 64  # noqa: E731
    assert np.allclose(second(after), second(before), rtol=1e-9)    # untouched


# -------------------------------------------------------------------------- errors
def test_declaration_errors_name_the_culprit():
    phi, th = md.coordinates("phi theta")
    mech = md.Mechanism("m", [phi, th])
    mech.link("crank", J=1, angle=phi)
    mech.link("rod", J=1, angle=th)
    with pytest.raises(md.DeclarationError, match="does not involve the coordinates"):
        mech.constraint("nothing", sp.Symbol("L") - 1)
    mech.loop("loop", (1, phi), (2, th), (-2.5, 0))
    with pytest.raises(md.DeclarationError, match="leave no degree of freedom"):
        mech.equations()
    with pytest.raises(md.DeclarationError, match="not one of its coordinates"):
        md.Mechanism("m", [phi], independent=[th])
    three = md.Mechanism("m", md.coordinates("a b c"), independent=md.coordinates("a b"))
    three.link("l", J=1, angle=md.coordinate("a") + md.coordinate("b") + md.coordinate("c"))
    three.loop("loop", (1, md.coordinate("a")), (1, md.coordinate("c")), (-1.5, 0))
    with pytest.raises(md.DeclarationError, match="leave 1 degrees of freedom"):
        three.equations()
    with pytest.raises(md.DeclarationError, match="'frame' names the fixed frame"):
        mech.link("frame", m=1)
    with pytest.raises(md.DeclarationError, match="'wheel' is not a link"):
        mech.joint("J", ("frame", "wheel"), at=(0, 0))
    with pytest.raises(md.DeclarationError, match="prismatic joint needs direction"):
        mech.joint("P", ("frame", "rod"), at=(0, 0), kind="prismatic")


def test_scene_errors_for_loops():
    mech, (phi, th2, th3) = four_bar()
    missing = md.Scene("s", initial={phi: 0, md.speed(phi): 1, th2: 1.2}, t_end=1)
    with pytest.raises(md.SceneError, match="theta_3.*guess"):
        mech.simulate(missing, {})
    wrong = md.Scene("s", initial={phi: 0, md.speed(phi): 1, th2: 1.2, th3: 1.9,
                                   md.speed(th3): 5}, t_end=1)
    with pytest.raises(md.SceneError, match="disagrees with the loops"):
        mech.simulate(wrong, {})


def test_unassemblable_start_is_named_with_the_crank_angle():
    phi, th2, th3 = md.coordinates("phi theta_2 theta_3")
    rocker = md.Mechanism("triple rocker", [phi, th2, th3])
    for name, angle in (("input", phi), ("coupler", th2), ("output", th3)):
        rocker.link(name, J=1, angle=angle)
    rocker.loop("loop", (3, phi), (3.5, th2), (-5, th3), (-2, 0))
    scene = md.Scene("s", initial={phi: 0.1, md.speed(phi): 1, th2: 1.2, th3: 2.2}, t_end=1)
    with pytest.raises(md.SceneError, match=r"cannot be closed at phi = 0\.1 ") as error:
        rocker.simulate(scene, {})
    assert error.value.independent == {"phi": 0.1}


def test_a_non_grashof_crank_swings_back_at_its_toggle_positions():
    """Coupler and rocker in line lock the crank, not the full coordinates: the crank
    stops exactly at the toggle angle (law of cosines) and swings back, energy kept."""
    phi, th2, th3 = md.coordinates("phi theta_2 theta_3")
    rocker = md.Mechanism("triple rocker", [phi, th2, th3])
    for name, angle in (("input", phi), ("coupler", th2), ("output", th3)):
        rocker.link(name, J=1, angle=angle)
    rocker.loop("loop", (3, phi), (3.5, th2), (-5, th3), (-2, 0))
    scene = md.Scene("swing", initial={phi: np.pi, md.speed(phi): 3, th2: 1.2, th3: 2.2},
                     t_end=10)
    result = rocker.simulate(scene, {})
    limit = math.acos((13 - 1.5**2) / 12)
    assert abs(result[phi].min() - limit) < 1e-6
    assert abs(result[phi].max() - (2 * np.pi - limit)) < 1e-6
    kinetic, potential = result.energy()
    assert np.ptp(kinetic + potential) < 1e-8 * kinetic[0]


@pytest.mark.parametrize("backend", ["auto", "scipy"])
def test_a_change_point_stops_the_simulation_with_a_named_error_and_partial_result(backend):
    phi, th2, th3 = md.coordinates("phi theta_2 theta_3")
    parallelogram = md.Mechanism("parallelogram", [phi, th2, th3])
    parallelogram.link("crank", J=1, angle=phi)
    parallelogram.link("coupler", m=1, J=0.5, x=sp.cos(phi) + sp.cos(th2),
                       y=sp.sin(phi) + sp.sin(th2), angle=th2)
    parallelogram.link("rocker", J=1, angle=th3)
    parallelogram.loop("ABCD", (1, phi), (2, th2), (-1, th3), (-2, 0))
    scene = md.Scene("run", initial={phi: np.pi / 2, md.speed(phi): 10, th2: 0.1,
                                     th3: np.pi / 2}, t_end=3, backend=backend)
    with pytest.raises(md.SimulationError, match=r"loop ABCD is singular.*short of "
                       r"3\.1415926\d, the singular position") as error:
        parallelogram.simulate(scene, {})
    partial = error.value.partial                         # all links in line at phi = pi
    assert set(partial.stats["backends"]) <= {"compiled" if backend == "auto" else "scipy"}
    assert backend == "scipy" or partial.stats["backends"]["compiled"] > 0
    assert np.all(np.isfinite(partial.y)) and partial.final(phi) < np.pi
    assert isinstance(error.value, md.LoopSingularError) and error.value.loop == "ABCD"


def test_driving_moment_of_a_linkage_along_a_prescribed_motion():
    mech, (phi, th2, th3) = four_bar(loads=True)
    needed = md.driving_moment(mech, md.uniform_rotation(15), {}, drive="motor",
                               guess={th2: 1.2, th3: 1.9})
    times = np.linspace(0, 2 * np.pi / 15, 7)
    statics = md.kinetostatics(mech, {}, 15 * times, omega=15.0, drive="motor",
                               guess={th2: 1.2, th3: 1.9})
    assert np.allclose(needed.at(times), statics.driving, rtol=1e-9, atol=1e-9)
    # over a revolution at constant speed the inertia terms and every moment of the
    # position alone (gravity, the work moment -3 cos(theta_3)) do no net work
    assert abs(needed.mean) < 1e-9 * needed.peak
    assert phi in mech.coordinates and "phiddot" in str(needed.expression)


def test_prismatic_guide_reaction_of_a_slider_crank_with_a_massless_rod():
    """The rod is a two-force member: its force on the slider lies along BA; the slider
    (mass m3, no gravity) gives its x part m3 s'', the guide takes its y part."""
    r, length, m3, omega = 0.05, 0.2, 2.0, 40.0
    phi, th, s = md.coordinates("phi theta s")
    mech = md.Mechanism("slider-crank", [phi, th, s], units={s: "m"})
    mech.link("crank", J=0.01, angle=phi)
    mech.link("rod", angle=th)                                  # massless
    mech.link("slider", m=m3, x=s)
    mech.loop("loop", (r, phi), (length, th), (-s, 0))
    mech.joint("O", ("frame", "crank"), at=(0, 0))
    mech.joint("A", ("crank", "rod"), at=(r * sp.cos(phi), r * sp.sin(phi)))
    mech.joint("B", ("rod", "slider"), at=(s, 0))
    mech.joint("guide", ("frame", "slider"), at=(s, 0), kind="prismatic", direction=0)
    angles = np.linspace(0.1, 2 * np.pi, 12)
    statics = md.kinetostatics(mech, {}, angles, omega=omega, guess={th: -0.1, s: 0.25})

    def stroke(x):
        return r * np.cos(x) + np.sqrt(length**2 - (r * np.sin(x)) ** 2)
    h = 1e-3
    s_dd = omega**2 * (-stroke(angles + 2 * h) + 16 * stroke(angles + h) - 30 * stroke(angles)
                       + 16 * stroke(angles - h) - stroke(angles - 2 * h)) / (12 * h * h)
    along = np.array([r * np.cos(angles) - stroke(angles), r * np.sin(angles)])   # B -> A
    force_x = m3 * s_dd
    force_y = force_x * along[1] / along[0]
    scale = np.max(np.abs(force_x))
    assert np.allclose(statics.reactions["B"].x, force_x, atol=1e-6 * scale)
    assert np.allclose(statics.reactions["B"].y, force_y, atol=1e-6 * scale)
    guide = statics.reactions["guide"]
    assert np.allclose(guide.normal, -force_y, atol=1e-6 * scale)
    assert np.allclose(guide.y, -force_y, atol=1e-6 * scale) and np.allclose(guide.x, 0)
    assert np.allclose(guide.moment, 0, atol=1e-9 * scale)
    # the rod's mass matrix is singular (no inertia in theta): the loop still moves it
    free = md.Scene("free", initial={phi: 0.1, md.speed(phi): omega, th: -0.1, s: 0.25},
                    t_end=1.0)
    result = mech.simulate(free, {})
    kinetic, potential = result.energy()
    assert np.max(np.abs(kinetic + potential - kinetic[0])) < 1e-8 * kinetic[0]


def test_the_printed_loop_derivation_names_first_then_second_order_transmission_functions():
    """The four-bar's derivation states theta_2', theta_3' (first order) and then
    theta_2'', theta_3'' (second order: two primes, d2/dphi2), before I_red and M_red."""
    model = md.load_model(ROOT / "models" / "fourbar_flywheel.py")
    names = [line.split("&=")[0].strip() for line in model.mechanism.latex().splitlines()
             if "&=" in line]
    ratios = [n for n in names if n.startswith("\\theta_{") and n.endswith("'")]
    assert ratios == ["\\theta_{2}'", "\\theta_{3}'", "\\theta_{2}''", "\\theta_{3}''"]
    assert names[names.index("\\theta_{3}''") + 1:] == ["I_{\\mathrm{red}}", "M_{\\mathrm{red}}"]


def test_a_stiff_closed_loop_starts_on_the_stiff_method_and_decays_as_by_hand():
    """A slider (1 kg) geared to a wheel (2 kg m^2, x = 2 y: m_red = 1.5 kg) on a stiff
    spring (1e6 N/m) and damper (1e5 N s/m): 1.5 s^2 + 1e5 s + 1e6 = 0 has a fast root
    near -66,657 1/s beside the slow one near -10, so the run starts on the stiff method
    (judged on the motion the loop allows); x(t) = A e^(s1 t) + B e^(s2 t) from x = 0.2,
    x' = 0."""
    x, y = md.coordinate("x"), md.coordinate("y")
    mech = md.Mechanism("stiff geared pair", [x, y], independent=x)
    mech.link("slider", m=1, x=x)
    mech.link("wheel", J=2, angle=y)
    mech.constraint("rack", x - 2 * y)
    mech.spring("spring", 1e6, stretch=x)
    mech.damper("damper", 1e5, stretch=x)
    res = mech.simulate(md.Scene("settle", initial={x: 0.2, y: 0.1, md.speed(x): 0},
                                 t_end=1), {})
    assert res.stats["method"].split("+")[0] == "Rodas5P"
    s1, s2 = np.roots([1.5, 1e5, 1e6])
    a = 0.2 * s2 / (s2 - s1)                       # x(0) = a + b, x'(0) = a s1 + b s2 = 0
    assert res.final(x) == pytest.approx(a * np.exp(s1) + (0.2 - a) * np.exp(s2), rel=1e-5)

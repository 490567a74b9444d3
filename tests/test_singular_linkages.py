"""Closed loops at their singular positions: change points (Grashof's equality) and
toggles (non-Grashof), as a designer meets them (issue 30).

Every expected value is worked out here: the parallelogram's constant reduced inertia,
its coupler translating and its rocker turning with the crank; the anti-parallelogram's
positions by intersecting two circles; toggles and ranges by the law of cosines; an
offset slider's dead centres by Pythagoras.
"""
import ast
import math
import pathlib
import re

import numpy as np
import pytest
import sympy as sp

import mechdyn as md

ROOT = pathlib.Path(__file__).resolve().parents[1]
M_CRANK, M_COUPLER, M_ROCKER, J_CRANK = 0.5, 0.8, 0.6, 0.002
TORQUE = 1.0


def four_bar(a, b, c, d, name="four-bar"):
    """Crank a, coupler b, rocker c, frame d; point masses at the link centres, the
    crank's inertia J_CRANK, the others' m l^2 / 12; a constant moment on the crank."""
    phi, th, psi = md.coordinates("phi theta psi")
    mech = md.Mechanism(name, [phi, th, psi], independent=[phi])
    mech.link("crank", m=M_CRANK, J=J_CRANK, x=a / 2 * sp.cos(phi), y=a / 2 * sp.sin(phi),
              angle=phi)
    mech.link("coupler", m=M_COUPLER, J=M_COUPLER * b**2 / 12,
              x=a * sp.cos(phi) + b / 2 * sp.cos(th), y=a * sp.sin(phi) + b / 2 * sp.sin(th),
              angle=th)
    mech.link("rocker", m=M_ROCKER, J=M_ROCKER * c**2 / 12, x=d + c / 2 * sp.cos(psi),
              y=c / 2 * sp.sin(psi), angle=psi)
    mech.loop("ABCD", (a, phi), (b, th), (-c, psi), (-d, 0))
    mech.load("drive", TORQUE, along=phi, on="crank")
    return mech, (phi, th, psi)


def parallelogram_inertia(a=0.1, c=0.1):
    """theta' = 0, psi' = 1: the coupler translates with the crank pin (speed a w)."""
    return (M_CRANK * (a / 2) ** 2 + J_CRANK + M_COUPLER * a**2
            + M_ROCKER * (c / 2) ** 2 + M_ROCKER * c**2 / 12)


def circle_branches(phi, a=0.1, b=0.3, c=0.1, d=0.3):
    """Both assemblies (theta, psi) at the crank angle phi: B on the circle of radius
    b about the crank pin A and of radius c about D = (d, 0)."""
    pin = a * np.exp(1j * phi)
    span = d - pin
    length = abs(span)
    along = (b**2 - c**2 + length**2) / (2 * length)
    across = math.sqrt(max(b**2 - along**2, 0.0))
    out = []
    for side in (1, -1):
        joint = pin + span / length * (along + 1j * side * across)
        out.append((np.angle(joint - pin), np.angle(joint - d)))
    return out


def crossed(phi):
    """The anti-parallelogram's (theta, psi): the branch that is not theta = 0."""
    return max(circle_branches(phi), key=lambda branch: abs(branch[0]))


def same_angle(x, y, tolerance):
    return abs(math.remainder(x - y, 2 * math.pi)) < tolerance


TRIPLE = (0.14, 0.09, 0.13, 0.21)
TOGGLE = math.acos((TRIPLE[0]**2 + TRIPLE[3]**2 - (TRIPLE[1] + TRIPLE[2])**2)
                   / (2 * TRIPLE[0] * TRIPLE[3]))      # |AD| = coupler + rocker


# ------------------------------------------------------------------ simulation
def test_partial_result_before_a_change_point_is_the_true_motion():
    mech, (phi, th, psi) = four_bar(0.1, 0.3, 0.1, 0.3, "parallelogram")
    inertia = parallelogram_inertia()
    assert abs(inertia - 0.01325) < 1e-15                   # the value
    scene = md.Scene("run", initial={phi: 0.5, md.speed(phi): 0, th: 0, psi: 0.5},
                     t_end=1)
    with pytest.raises(md.LoopSingularError, match="loop ABCD is singular") as caught:
        mech.simulate(scene, {})
    error = caught.value
    t_singular = math.sqrt(2 * inertia * (math.pi - 0.5) / TORQUE)   # phi = pi there
    assert error.time < t_singular and error.loop == "ABCD"
    partial = error.partial
    t = partial.t
    omega = TORQUE * t / inertia
    assert len(t) > 5 and t[-1] < t_singular
    assert np.all(np.abs(partial[md.speed(phi)] - omega) <= 1e-6 * np.maximum(omega, 1e-3))
    assert np.all(np.abs(partial[md.speed(psi)] - omega) <= 1e-6 * np.maximum(omega, 1e-3))
    assert np.max(np.abs(partial[th])) < 1e-8 and np.max(np.abs(partial[md.speed(th)])) < 1e-6
    assert np.allclose(partial[phi], 0.5 + TORQUE * t**2 / (2 * inertia), rtol=0, atol=1e-9)
    gap = float(re.search(r"phi ([0-9.e+-]+) short of 3\.1415926\d, the singular position",
                          str(error)).group(1))
    assert abs(gap - (math.pi - partial.final(phi))) < 1e-6 and error.kept_until == t[-1]


def test_a_triple_rocker_driven_from_rest_stops_at_its_toggle_and_swings_back():
    mech, (phi, th, psi) = four_bar(*TRIPLE, "triple-rocker")
    scene = md.Scene("run", initial={phi: 0, md.speed(phi): 0, th: 1.8, psi: 2.2}, t_end=1)
    result = mech.simulate(scene, {})
    t_peak, peak = result.peak(phi)
    assert abs(peak - TOGGLE) < 1e-8
    assert result.at([t_peak + 0.1], phi)[0] < peak - 0.1     # swings back
    beyond = md.Scene("beyond", initial={phi: 1.5, md.speed(phi): 0, th: 1.8, psi: 2.2},
                      t_end=1)
    with pytest.raises(md.SceneError, match=r"cannot be closed at phi = 1\.5 "):
        mech.simulate(beyond, {})


# ------------------------------------------------------------------ kinematics
def test_singularities_name_the_change_points_of_both_parallelogram_branches():
    mech, (phi, th, psi) = four_bar(0.1, 0.3, 0.1, 0.3, "parallelogram")
    for guess in ({phi: 0.5, th: 0, psi: 0.5}, {phi: 0.7, th: -0.5, psi: -1.2}):
        found = md.Linkage(mech, guess=guess).singularities()
        assert [(s.kind, s.loop) for s in found] == [("change point", "ABCD")] * 2
        for item, expected in zip(found, (math.pi, 0.0)):
            assert same_angle(item.at, expected, 1e-9)


def test_triple_rocker_toggles_are_the_law_of_cosines_positions():
    mech, (phi, th, psi) = four_bar(*TRIPLE, "triple-rocker")
    linkage = md.Linkage(mech, guess={th: 1.8, psi: 2.2})
    low, high = linkage.crank_range()
    assert abs(low + TOGGLE) < 1e-10 and abs(high - TOGGLE) < 1e-10
    found = linkage.singularities()
    assert [s.kind for s in found] == ["toggle", "toggle"]
    assert abs(found[0].at + TOGGLE) < 1e-10 and abs(found[1].at - TOGGLE) < 1e-10


def test_a_guess_is_honoured_at_the_crank_angle_it_belongs_to():
    mech, (phi, th, psi) = four_bar(0.1, 0.3, 0.1, 0.3, "anti-parallelogram")
    theta, psi_value = crossed(0.7)
    for linkage in (md.Linkage(mech, guess={th: theta + 0.1, psi: psi_value - 0.1},
                               guess_at=0.7),
                    md.Linkage(mech, guess={phi: 0.7, th: theta, psi: psi_value}),
                    md.Linkage(mech, scene=md.Scene("s", initial={
                        phi: 0.7, md.speed(phi): 0, th: theta, psi: psi_value}, t_end=1))):
        q = linkage.position(0.7)
        assert abs(q[1] - theta) < 1e-12 and abs(q[2] - psi_value) < 1e-12
        for angle in (math.pi + 0.3, 2 * math.pi + 0.3, 0.2, -0.4):   # through phi = 0, pi
            q = linkage.position(angle)
            expected = crossed(angle)
            assert same_angle(q[1], expected[0], 1e-10)
            assert same_angle(q[2], expected[1], 1e-10)
    at_change_point = md.Linkage(mech, guess={th: theta, psi: psi_value})   # at phi = 0
    with pytest.raises(md.LinkageError, match=r"phi = 0 .*change point of loop ABCD"):
        at_change_point.position(0.7)


def test_transmission_functions_at_a_change_point_are_the_branch_limits():
    mech, (phi, th, psi) = four_bar(0.1, 0.3, 0.1, 0.3, "anti-parallelogram")
    linkage = md.Linkage(mech, guess={phi: 0.7, th: -0.5, psi: -1.2})
    sweep = linkage.sweep([3.0, math.pi])
    # the crossed branch's slopes at phi = pi (B at (0.2, 0)) by central differences of
    # the circle intersection, Richardson-extrapolated (error ~ h^4)

    def central(h, k):
        step = math.remainder(crossed(math.pi + h)[k] - crossed(math.pi - h)[k], 2 * math.pi)
        return step / (2 * h)
    slope = [(4 * central(4e-3, k) - central(8e-3, k)) / 3 for k in (0, 1)]
    assert np.allclose(sweep.ratio[1:, 1], slope, rtol=0, atol=1e-8)


# ------------------------------------------------------------------ describe()
def slider_crank(r=0.05, rod=0.2, offset=0.02):
    phi, th, x = md.coordinates("phi theta x")
    mech = md.Mechanism("offset slider-crank", [phi, th, x], independent=[phi],
                        units={x: "m"})
    mech.link("crank", J=0.01, angle=phi)
    mech.link("rod", m=0.5, J=0.002, x=r * sp.cos(phi) + rod / 2 * sp.cos(th),
              y=r * sp.sin(phi) + rod / 2 * sp.sin(th), angle=th)
    mech.link("slider", m=1.0, x=x)
    mech.loop("ABC", (r, phi), (rod, th), (-x, 0), (-offset, sp.pi / 2))
    return mech, (phi, th, x)


def _deg(value):
    return f"{math.degrees(value):.4f} deg"


def _table():
    """(mechanism, Linkage keywords, lines the description must hold)."""
    a, b, c, d = 0.1, 0.35, 0.3, 0.4
    mech, (phi, th, psi) = four_bar(a, b, c, d, "crank-rocker")
    swing = [math.pi - math.acos((d**2 + c**2 - reach**2) / (2 * d * c))
             for reach in (b - a, b + a)]       # crank and coupler in line
    yield mech, {"guess": {th: 1.2, psi: 1.9}}, [
        "class: crank-rocker", "the crank turns fully", "no toggle position or change point",
        *(_deg(v) for v in swing)]
    mech, (phi, th, psi) = four_bar(0.3, 0.35, 0.3, 0.1, "drag link")
    yield mech, {"guess": {th: 0.5, psi: 1.5}}, [
        "class: double-crank", "the crank turns fully", "no toggle position or change point",
        "theta extremes: none (turns fully)", "psi extremes: none (turns fully)"]
    mech, (phi, th, psi) = four_bar(0.1, 0.3, 0.1, 0.3, "parallelogram")
    change_points = ["change point of loop ABCD at phi = 3.14159265 rad (180.0000 deg)",
                     "change point of loop ABCD at phi = 6.28318531 rad (360.0000 deg)"]
    yield mech, {"guess": {th: 0, psi: 0.5}, "guess_at": 0.5}, [
        "class: parallelogram", "the crank turns fully", *change_points,
        "theta constant: 0.0000 deg", f"I_red constant: {parallelogram_inertia():.6g} kg m^2"]
    yield mech, {"guess": {phi: 0.7, th: -0.5, psi: -1.2}}, [
        "class: anti-parallelogram", "the crank turns fully", *change_points]
    mech, (phi, th, psi) = four_bar(*TRIPLE, "triple-rocker")
    yield mech, {"guess": {th: 1.8, psi: 2.2}}, [
        "class: triple-rocker", f"crank range {-math.degrees(TOGGLE):.4f} .. "
        f"{math.degrees(TOGGLE):.4f} deg", f"toggle of loop ABCD at phi = {-TOGGLE:.9g} rad",
        f"toggle of loop ABCD at phi = {TOGGLE:.9g} rad"]
    mech, (phi, th, psi) = four_bar(0.1, 0.3, 0.3, 0.1, "kite")    # crank = frame
    yield mech, {"guess": {phi: 0.5, th: 1.0, psi: 1.8}}, [     # A on D at phi = 0
        "class: deltoid (kite)", "the crank turns fully",
        "change point of loop ABCD at phi = 6.28318531 rad (360.0000 deg)"]
    mech, (phi, th, x) = slider_crank()
    ends = [math.sqrt((0.2 + 0.05) ** 2 - 0.02**2), math.sqrt((0.2 - 0.05) ** 2 - 0.02**2)]
    yield mech, {"guess": {th: 0, x: 0.25}}, [
        "class: slider-crank (crank 0.05, rod 0.2, offset 0.02)", "the crank turns fully",
        "no toggle position or change point",
        f"{ends[0]:.6g} m at phi = {math.degrees(math.asin(0.02 / 0.25)):.4f} deg",
        f"{ends[1]:.6g} m at phi = {180 + math.degrees(math.asin(0.02 / 0.15)):.4f} deg"]


@pytest.mark.parametrize("case", range(7), ids=["crank-rocker", "double-crank",
                                               "parallelogram", "anti-parallelogram",
                                               "triple-rocker", "deltoid",
                                               "offset slider-crank"])
def test_describe_states_class_singular_positions_and_range(case):
    mech, keywords, expected = list(_table())[case]
    text = md.Linkage(mech, **keywords).describe(points=91)
    for line in expected:
        assert line in text, (line, text)
    assert len(text.splitlines()) < 15


def test_anti_parallelogram_coupler_swing_is_the_circle_intersection_one():
    from scipy.optimize import minimize_scalar
    mech, (phi, th, psi) = four_bar(0.1, 0.3, 0.1, 0.3, "anti-parallelogram")
    linkage = md.Linkage(mech, guess={phi: 0.7, th: -0.5, psi: -1.2})
    found = sorted(linkage.extremes("theta"), key=lambda e: e[1])
    lowest = minimize_scalar(lambda v: crossed(v)[0], bounds=(0.2, 2.0), method="bounded",
                             options={"xatol": 1e-12})
    assert abs(found[0][1] - lowest.fun) < 1e-12 and abs(found[0][0] - lowest.x) < 1e-5
    assert abs(found[1][1] + lowest.fun) < 1e-12          # mirror image


# ------------------------------------------------------------------ errors
def test_every_error_a_user_can_meet_is_top_level_and_in_the_guides_table():
    names = set()           # every ...Error class mechdyn defines
    for path in (ROOT / "mechdyn").rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ClassDef) and node.name.endswith("Error") \
                    and not node.name.startswith("_"):
                names.add(node.name)
    guide = (ROOT / "docs" / "guide" / "derive.md").read_text()     # the errors table
    table = guide[guide.index("| error (base) |"):]
    table = table.split("\n\n")[0]               # the table ends the page
    internal = {"MechdynError",            # the base: named above the table
                "FmuExpressionError"}      # export_fmu turns it into an FmuError
    for name in sorted(names - internal):
        error = getattr(md, name)
        assert issubclass(error, md.MechdynError), name
        assert f"`{name}`" in table, name
    assert issubclass(md.LoopSingularError, md.SimulationError)

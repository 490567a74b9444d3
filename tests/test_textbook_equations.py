"""The derivation as a textbook prints it (issue 29): positions, transmission functions
named once, each element's law as it writes it, I_red, I_red', M_red and the equation of
motion in them; deterministic output; the hand-worked formulas of the worked examples
(restated from the project's worked examples, sections 2-4: gear pair, cam, Scotch yoke)."""
import os
import re
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

import mechdyn as md

ROOT = Path(__file__).resolve().parents[1]
USER_MODEL = ROOT / "tests" / "data" / "slider_crank_flywheel.py"
MODELS = ROOT / "models"


def _equations(model, *options, seed="0"):
    env = dict(os.environ, PYTHONHASHSEED=seed, PYTHONPATH=str(ROOT))
    done = subprocess.run([sys.executable, "-m", "mechdyn.cli", "equations",
                           str(model), *options], capture_output=True, text=True, env=env,
                          timeout=120)
    assert done.returncode == 0, done.stderr
    return done.stdout


def _lines(latex):
    return {line.split("&=")[0].strip(): line.rstrip(" \\") for line in latex.splitlines()
            if "&=" in line}


def _close(a, b, symbols, points=5):
    """``a == b`` at random values of ``symbols`` (positive, and angles in (0, 2 pi))."""
    rng = np.random.default_rng(7)
    for _ in range(points):
        values = {s: rng.uniform(0.3, 2.0) for s in symbols}
        assert complex(a.subs(values)) == pytest.approx(complex(b.subs(values)), rel=1e-10,
                                                         abs=1e-12)


@pytest.mark.parametrize("model, seeds", [
    (USER_MODEL, ("0", "1", "4242")),
    pytest.param(MODELS / "slider_crank.py", ("2", "77"), marks=pytest.mark.slow)])
def test_equations_are_the_same_for_any_hash_seed_and_name_each_function_once(model, seeds):
    outputs = {_equations(model, seed=seed) for seed in seeds}
    assert len(outputs) == 1
    (latex,) = outputs
    lines = _lines(latex)
    slider = "x_{\\text{slider}}"
    defined = [key for key in lines if key.startswith(slider)]
    assert defined == [slider, slider + "^{\\prime}", slider + "^{\\prime\\prime}"]
    inertia = lines["I_{\\mathrm{red}}"]
    assert "\\left(x_{\\text{slider}}^{\\prime}\\right)^{2}" in inertia
    slope = next(line for key, line in lines.items() if key.startswith("\\frac{d I_"))
    moment = lines["M_{\\mathrm{red}}"]
    (motion,) = [line for key, line in lines.items() if "\\ddot{\\phi}" in key
                 and not key.startswith("I_{")]
    assert len(motion) <= len(inertia) + len(slope) + len(moment)
    for line in (lines["T"], inertia, slope, moment, motion):   # in the named quantities
        assert "\\sqrt" not in line and "\\sin" not in line


def test_user_slider_crank_matches_the_hand_worked_reduction():
    model = md.load_model(USER_MODEL)
    book = model.mechanism.derivation()
    phi, w = md.plain(md.coordinate("phi")), md.plain(md.speed(md.coordinate("phi")))
    r, L, J_f, m_s, F_r, M_b, M_k, s_k, w_s = sp.symbols(
        "r L J_f m_s F_r M_b M_k s_k omega_s", positive=True)
    x_s = r * sp.cos(phi) + sp.sqrt(L**2 - r**2 * sp.sin(phi)**2)     # by hand
    ratio = -r * sp.sin(phi) - r**2 * sp.sin(phi) * sp.cos(phi) / sp.sqrt(
        L**2 - r**2 * sp.sin(phi)**2)
    slip = (w_s - w) / w_s
    kloss = 2 * M_k / (slip / s_k + s_k / slip)
    printed = {str(k): v for k, v in book.quantities.items()}
    assert set(printed) == {"x_slider", "x_slider'", "x_slider''", "M_motor"}
    assert str(book.reduced_inertia) == "J_f + m_s*x_slider'**2"
    assert str(book.reduced_inertia_slope) == "2*m_s*x_slider'*x_slider''"
    assert str(book.reduced_moment) == \
        "-F_r*x_slider'*sign(phidot*x_slider') - M_b*sign(phidot) + M_motor"
    symbols = [phi, w, r, J_f, m_s, F_r, M_b, M_k, s_k, w_s]
    at = {L: 4}                                    # L > r: the rod reaches
    _close(book.expand(book.reduced_inertia).subs(at), (J_f + m_s * ratio**2).subs(at), symbols)
    _close(book.expand(book.reduced_inertia_slope).subs(at),
           sp.diff(J_f + m_s * ratio**2, phi).subs(at), symbols)
    hand_moment = kloss - F_r * ratio * sp.sign(w * ratio) - M_b * sp.sign(w)
    _close(book.expand(book.reduced_moment).subs(at), hand_moment.subs(at), symbols)
    assert printed["x_slider"] == x_s


@pytest.mark.parametrize("name, inertia, moment", [
    # 2. gear pair: I_red = J1 + J2 (z1/z2)^2, M_red = M1 - M2 z1/z2
    ("gear_pair", "J_1 + J_2*(z_1/z_2)**2", "M_1 - M_2*z_1/z_2"),
    # 3. cam, uniform rise: I_red = J1A + m2 (h/Phi)^2, M_red = M1 - F2 h/Phi
    ("cam_follower", "J_1A + m_2*(h/Phi)**2", "M_1 - F_2*h/Phi"),
    # 4. Scotch yoke: I_red = J1A + m3 (l sin phi)^2, M_red = M1 - F3 l sin(phi)
    ("scotch_yoke", "J_1A + m_3*(l*sin(phi))**2", "M_1 - F_3*l*sin(phi)"),
])
def test_worked_examples_reduced_quantities_in_the_named_derivation(name, inertia, moment):
    model = md.load_model(MODELS / f"{name}.py")
    book = model.mechanism.derivation()
    assert not book.budget_spent                # a small machine is simplified in full
    names = {s.name: s for s in model.mechanism.equations().parameters}
    names["phi"] = model.mechanism.equations().q[0]
    hand_inertia = sp.parse_expr(inertia, local_dict=names)
    hand_moment = sp.parse_expr(moment, local_dict=names)
    assert sp.simplify(book.expand(book.reduced_inertia) - hand_inertia) == 0
    assert sp.simplify(book.expand(book.reduced_moment) - hand_moment) == 0
    # I_red eps + 1/2 I_red' omega^2 = M_red: 1/2 I_red' by hand, and the velocity term
    # 1/2 I_red' omega^2 the equation prints
    assert sp.simplify(book.expand(book.reduced_inertia_slope) / 2
                       - sp.diff(hand_inertia, names["phi"]) / 2) == 0
    omega = model.mechanism.equations().u[0]
    assert sp.simplify(book.expand(book.velocity_terms[0])
                       - sp.diff(hand_inertia, names["phi"]) / 2 * omega**2) == 0
    if name == "scotch_yoke":                  # m3 l^2 sin(phi) cos(phi), the source's form
        l, m3, phi = names["l"], names["m_3"], names["phi"]
        assert sp.simplify(book.expand(book.reduced_inertia_slope) / 2
                           - m3 * l**2 * sp.sin(phi) * sp.cos(phi)) == 0


def test_two_dof_jacobian_entries_are_named_and_agree_with_lagrange():
    x, th = md.coordinates("x theta")
    m, M, l, k, F = sp.symbols("m M l k F", positive=True)
    cart = md.Mechanism("cart pendulum", [x, th], units={x: "m"})
    cart.link("cart", m=M, x=x)
    cart.link("bob", m=m, x=x + l * sp.sin(th), y=-l * sp.cos(th))
    cart.spring("tether", k, stretch=x)
    cart.gravity(9.81)
    cart.load("push", F, along=x + l * sp.sin(th))
    book = cart.derivation()
    eqs = cart.equations()
    assert "dx_bob/dtheta" in map(str, book.quantities)
    latex = cart.latex()
    assert "\\frac{\\partial x_{\\text{bob}}}{\\partial \\theta}" in latex
    assert "I_{\\mathrm{red}}" not in latex
    symbols = sorted(eqs.mass_matrix.free_symbols | eqs.forcing.free_symbols, key=str)
    for i in range(2):
        _close(book.expand(book.forces[i]), eqs.smooth_forcing[i] - eqs.inertial_forcing[i],
               symbols)
        _close(book.expand(book.velocity_terms[i]), -eqs.inertial_forcing[i], symbols)
        for j in range(2):
            _close(book.expand(book.mass_matrix[i, j]), eqs.mass_matrix[i, j], symbols)


def _in_process(capsys, *argv):
    from mechdyn.cli import main
    assert main(["equations", *map(str, argv)]) == 0
    return capsys.readouterr().out


def test_expanded_form_writes_every_term_in_the_coordinates(capsys):
    latex = _in_process(capsys, MODELS / "scotch_yoke.py", "--expanded")
    inertia = _lines(latex)["I_{\\mathrm{red}}"]
    assert "\\sin" in inertia and "prime" not in latex


def test_the_expanded_equation_of_motion_has_half_the_inertia_slope(capsys):
    """I_red phi'' + 1/2 dI_red/dphi phi'^2 = M_red of the Scotch yoke, written out:
    I_red = J_1A + m_3 l^2 sin^2 phi, so the velocity term is m_3 l^2 sin cos phi'^2."""
    text = _in_process(capsys, MODELS / "scotch_yoke.py", "--expanded", "--format", "text")
    line = next(line for line in text.splitlines() if "equation of motion:" in line)
    lhs = line.split("equation of motion:")[1].split("=")[0]
    names = {n: sp.Symbol(n) for n in ("l", "m_3", "J_1A", "phi", "phidot", "phiddot")}
    names.update(sin=sp.sin, cos=sp.cos)
    l, m3, J1A, phi, w, a = (names[n] for n in ("l", "m_3", "J_1A", "phi", "phidot", "phiddot"))
    by_hand = (J1A + m3 * l**2 * sp.sin(phi)**2) * a + m3 * l**2 * sp.sin(phi) * sp.cos(phi) * w**2
    assert sp.simplify(sp.parse_expr(lhs, local_dict=names) - by_hand) == 0


def test_a_spent_budget_is_said_and_the_expressions_print_as_derived(capsys):
    text = _in_process(capsys, USER_MODEL, "--format", "text", "--budget", "0")
    assert "simplification stopped after the budget of 0 s" in text
    assert re.search(r"reduced inertia: +I_red = J_f \+ m_s\*x_slider'\*\*2", text)
    derivative = next(line for line in text.splitlines() if "x_slider' =" in line)
    assert derivative.endswith("= -r**2*sin(phi)*cos(phi)/sqrt(L**2 - r**2*sin(phi)**2) - r*sin(phi)")


def test_a_long_derivation_is_announced_on_stderr(capsys):
    from mechdyn.cli.scene_commands import announced
    with announced("deriving", after=0.0):
        for _ in range(500):                 # wait for the timer thread, at most 5 s
            if "deriving" in capsys.readouterr().err:
                break
            time.sleep(0.01)
        else:
            pytest.fail("no announcement")
    with announced("quick", after=60.0):
        pass
    assert capsys.readouterr().err == ""


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(p.stem for p in MODELS.glob("*.py")))
def test_every_bundled_model_named_derivation_agrees_with_lagrange(name):
    """Written back in the coordinates, the named mass matrix, velocity terms and forces
    are the derived ones (at random points); a law is named by what it acts along."""
    model = md.load_model(MODELS / f"{name}.py")
    eqs = model.mechanism.equations()
    from mechdyn.derive.textbook import applies
    if not applies(eqs):
        pytest.skip("closed loops or imposed motion: printed expanded")
    book = model.mechanism.derivation()
    symbols = sorted(eqs.mass_matrix.free_symbols | eqs.forcing.free_symbols
                     | set(eqs.q) | set(eqs.u), key=str)
    for i in range(eqs.dof):
        _close(book.expand(book.forces[i]), sum((c[i] for c in eqs.generalized_forces.values()),
                                                sp.S.Zero), symbols, points=3)
        _close(book.expand(book.velocity_terms[i]), -eqs.inertial_forcing[i], symbols, points=3)
        for j in range(eqs.dof):
            _close(book.expand(book.mass_matrix[i, j]), eqs.mass_matrix[i, j], symbols, points=3)
    latex = model.mechanism.latex()
    if name == "press_cycle":                  # a force along the ram's (negated) height
        assert "F_{\\text{workpiece}}\\left(\\phi\\right) &=" in latex


@pytest.mark.parametrize("expanded", [False, True])
def test_the_derivation_prints_the_energy_functions_there_are_and_only_those(expanded):
    """A disc (J = 2) on a spring (5) prints T and V; with a damper (3) also the
    dissipation function D = 3 phidot^2 / 2; without, no D line (nor a V line without
    the spring), in the named and the expanded derivation alike."""
    def disc(spring, damper):
        phi = md.coordinate("phi")
        mech = md.Mechanism("disc", [phi])
        mech.link("disc", J=2, angle=phi)
        if spring:
            mech.spring("spring", 5, stretch=phi)
        if damper:
            mech.damper("damper", 3, stretch=phi)
        mech.load("drive", 1, along=phi)
        lines = [line.split("&=")[0].strip() for line in
                 mech.latex(expanded=expanded).splitlines() if "&=" in line]
        return lines, mech.latex(expanded=expanded)

    lines, text = disc(spring=True, damper=True)
    assert lines[:3] == ["T", "V", "D"]
    assert r"D &= \frac{3 \dot{\phi}^{2}}{2} \\" in text
    lines, _ = disc(spring=True, damper=False)
    assert lines[:2] == ["T", "V"] and "D" not in lines
    lines, _ = disc(spring=False, damper=False)
    assert lines[0] == "T" and "V" not in lines and "D" not in lines


def test_the_named_equation_of_motion_has_half_the_inertia_slope(capsys):
    """The named form of the Scotch yoke: I_red = J_1A + m_3 x_yoke'^2, so the velocity
    term 1/2 dI_red/dphi phi'^2 is m_3 x_yoke' x_yoke'' phi'^2."""
    text = _in_process(capsys, MODELS / "scotch_yoke.py", "--format", "text")
    line = next(line for line in text.splitlines() if "equation of motion:" in line)
    lhs = line.split("equation of motion:")[1].split("=")[0]
    lhs = lhs.replace("x_yoke''", "w").replace("x_yoke'", "v")     # the transmission functions
    m3, J1A, speed, acceleration, v, w = sp.symbols("m_3 J_1A phidot phiddot v w")
    names = {str(s): s for s in (m3, J1A, speed, acceleration, v, w)}
    by_hand = (J1A + m3 * v**2) * acceleration + m3 * v * w * speed**2
    assert sp.expand(sp.parse_expr(lhs, local_dict=names) - by_hand) == 0

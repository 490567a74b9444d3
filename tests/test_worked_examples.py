"""Worked examples 1-6 (../shared/reference/worked-examples.md), through the public API.

Every reference formula below is written out here from the worked-example text; none is
taken from the code under test. Each model is loaded as a user would load it and its
derived reduced inertia, reduced moment and equation of motion are compared symbolically
(``simplify(a - b) == 0``) or, for the numbered results, numerically.
"""
from pathlib import Path

import pytest
import sympy as sp

import mechdyn as md
from mechdyn.cli.command import main

MODELS = Path(__file__).resolve().parent.parent / "models"


def load(name):
    return md.load_model(MODELS / f"{name}.py")


def symbols_of(model, names):
    """The model's parameter symbols, by name (the names the worked example uses)."""
    known = {s.name: s for s in model.params}
    known.update({s.name: s for s in model.mechanism.equations().parameters})
    return [known[n] for n in names.split()]


def plain_state(model):
    """phi, omega, eps: the plain symbols of the single coordinate of ``model``."""
    (q,) = model.mechanism.coordinates
    return md.plain(q), md.plain(md.speed(q)), md.plain(md.acceleration(q))


def is_zero(expr):
    return sp.simplify(expr) == 0


def textbook_form(inertia, moment, phi, omega, eps):
    """Lagrange's equation for E = I_red omega^2/2 (worked example 0), as lhs - rhs."""
    return inertia * eps + sp.diff(inertia, phi) / 2 * omega**2 - moment


def derived_form(model):
    """The derived equation of motion ``M a = f``, as lhs - rhs."""
    (eq,) = model.mechanism.equations().eqs
    return eq.lhs - eq.rhs


def check_one_dof(model, inertia, moment):
    """Reduced inertia, reduced moment, textbook form and M a = f of a 1-DOF model."""
    mech = model.mechanism
    phi, omega, eps = plain_state(model)
    assert is_zero(mech.reduced_inertia() - inertia), mech.reduced_inertia()
    assert is_zero(mech.reduced_moment() - moment), mech.reduced_moment()
    expected = textbook_form(inertia, moment, phi, omega, eps)
    textbook = mech.equations().textbook_equation
    assert is_zero(textbook.lhs - textbook.rhs - expected)
    assert is_zero(derived_form(model) - expected)


# --------------------------------------------------------------------- 1. shoe brake
def test_shoe_brake_reduced_quantities_and_stop():
    model = load("shoe_brake")
    I, f, P, R = symbols_of(model, "I f P R")
    phi, omega, eps = plain_state(model)
    mech = model.mechanism
    # The friction moment f * 2P * R opposes the turning: M_red = -M_fr while omega > 0.
    w = sp.Symbol("w", positive=True)
    inertia = mech.reduced_inertia()
    moment = mech.reduced_moment().subs(omega, w)
    assert is_zero(inertia - I)
    assert is_zero(moment - (-f * 2 * P * R))
    (eq,) = mech.equations().eqs
    assert is_zero((eq.lhs - eq.rhs).subs(omega, w) - (I * eps + f * 2 * P * R))
    # Turning the other way the brake pushes the other way.
    assert is_zero(mech.reduced_moment().subs(omega, -w) - f * 2 * P * R)

    # Case 1, uniformly decelerated: stops at t = 50 s after 2500 rad.
    values = {I: 0.4, f: 0.2, P: 20, R: 0.1}
    decel = float((moment / inertia).subs(values))
    omega0 = 100.0
    t_stop = -omega0 / decel
    assert t_stop == pytest.approx(50.0, rel=1e-12)
    assert omega0 * t_stop + decel * t_stop**2 / 2 == pytest.approx(2500.0, rel=1e-12)


# ---------------------------------------------------------------------- 2. gear pair
def test_gear_pair_reduced_quantities():
    model = load("gear_pair")
    z1, z2, J1, J2, M1, M2 = symbols_of(model, "z_1 z_2 J_1 J_2 M_1 M_2")
    check_one_dof(model, J1 + J2 * (z1 / z2) ** 2, M1 - M2 * z1 / z2)


def test_gear_pair_matches_dalembert():
    """d'Alembert: each gear's static balance with its inertia moment added, the
    contact force F at the pitch circles eliminated by hand."""
    model = load("gear_pair")
    z1, z2, J1, J2, M1, M2 = symbols_of(model, "z_1 z_2 J_1 J_2 M_1 M_2")
    phi, omega, eps = plain_state(model)
    F, module = sp.symbols("F m", positive=True)
    r1, r2 = module * z1 / 2, module * z2 / 2            # pitch radii
    eps1 = sp.Symbol("eps_1")
    eps2 = eps1 * r1 / r2                                # rolling without slip
    # gear 1: J1 eps1 = M1 - F r1;  gear 2: J2 eps2 = F r2 - M2
    force = sp.solve(sp.Eq(J2 * eps2, F * r2 - M2), F)[0]
    (dalembert,) = sp.solve(sp.Eq(J1 * eps1, M1 - force * r1), eps1)
    (eq,) = model.mechanism.equations().eqs
    (derived,) = sp.solve(eq, eps)
    assert is_zero(derived - dalembert)
    assert is_zero(dalembert - (M1 - M2 * z1 / z2) / (J1 + J2 * (z1 / z2) ** 2))


# ---------------------------------------------------------------- 3. cam + follower
def test_cam_follower_reduced_quantities():
    model = load("cam_follower")
    J1A, m2, h, Phi, M1, F2 = symbols_of(model, "J_1A m_2 h Phi M_1 F_2")
    check_one_dof(model, J1A + m2 * (h / Phi) ** 2, M1 - F2 * h / Phi)
    phi, omega, eps = plain_state(model)
    (eq,) = model.mechanism.equations().eqs
    (derived,) = sp.solve(eq, eps)
    assert is_zero(derived - (M1 - F2 * h / Phi) / (J1A + m2 * (h / Phi) ** 2))


# -------------------------------------------------------------------- 4. scotch yoke
def test_scotch_yoke_full_equation_of_motion():
    model = load("scotch_yoke")
    J1A, m3, l, M1, F3 = symbols_of(model, "J_1A m_3 l M_1 F_3")
    phi, omega, eps = plain_state(model)
    check_one_dof(model, J1A + m3 * (l * sp.sin(phi)) ** 2, M1 - F3 * l * sp.sin(phi))
    # M1 - F3 l sin(phi) = (J1A + m3 l^2 sin^2 phi) eps + m3 l^2 sin(phi) cos(phi) omega^2
    full = ((J1A + m3 * l**2 * sp.sin(phi) ** 2) * eps
            + m3 * l**2 * sp.sin(phi) * sp.cos(phi) * omega**2
            - (M1 - F3 * l * sp.sin(phi)))
    assert is_zero(derived_form(model) - full)


def test_scotch_yoke_matches_dalembert():
    """d'Alembert: yoke m3 x'' = N + F3 with x = l cos(phi); the crank pin at
    (l cos phi, l sin phi) takes -N along x, a moment N l sin(phi) on the crank."""
    model = load("scotch_yoke")
    J1A, m3, l, M1, F3 = symbols_of(model, "J_1A m_3 l M_1 F_3")
    phi, omega, eps = plain_state(model)
    x_acc = -l * sp.sin(phi) * eps - l * sp.cos(phi) * omega**2
    normal = m3 * x_acc - F3
    crank = J1A * eps - (M1 + normal * l * sp.sin(phi))
    assert is_zero(derived_form(model) - crank)


# ------------------------------------------------------------------- 5. planetary
def test_planetary_reduced_quantities_and_start():
    model = load("planetary_2kh")
    J1, J2, J3, JH, M1, MH = symbols_of(model, "J_1 J_2 J_3 J_H M_1 M_H")
    z1, z2, z3, z4 = 20, 40, 20, 40
    # Willis: i_1H = 1 - z2 z4/(z1 z3); (omega2 - omegaH)/(omega1 - omegaH) = -z1/z2.
    i_1H = 1 - sp.Rational(z2 * z4, z1 * z3)
    assert i_1H == -3
    ratio_H = 1 / i_1H                                       # omega_H / omega_1 = -1/3
    ratio_2 = ratio_H - sp.Rational(z1, z2) * (1 - ratio_H)  # omega_2 / omega_1 = -1
    assert ratio_2 == -1
    inertia = J1 + (J2 + J3) * ratio_2**2 + JH * ratio_H**2
    # The carrier load resists the carrier's turning: its power is -M_H |omega_H|.
    moment = M1 - MH * abs(ratio_H)
    check_one_dof(model, inertia, moment)

    params = {s: v for s, v in model.params.items() if s != M1}
    assert float(model.mechanism.reduced_inertia().subs(params)) == pytest.approx(0.80, abs=1e-12)
    # a) the least starting moment makes M_red vanish
    (least,) = sp.solve(model.mechanism.reduced_moment().subs(params), M1)
    assert float(least) == pytest.approx(5.0, abs=1e-12)
    # b) 600 rpm in 3 s uniformly: eps1 = 20 pi / 3, M1 = 5 + 0.8 eps1 = 21.76 N m
    phi, omega, eps = plain_state(model)
    (eq,) = model.mechanism.equations().eqs
    (needed,) = sp.solve(eq.subs(params).subs(eps, 20 * sp.pi / 3), M1)
    assert float(needed) == pytest.approx(21.76, abs=0.005)


# ------------------------------------------------------------------ 6. rope hoist
def test_rope_hoist_reduced_quantities():
    model = load("rope_hoist")
    I1, R1, R2, m2, rho2, r2, m3, Mc, g = symbols_of(model, "I_1 R_1 R_2 m_2 rho_2 r_2 m_3 M_c g")
    phi, omega, eps = plain_state(model)
    M_0, M_t = symbols_of(model, "M_0 M_t")
    M = M_0 + M_t * md.t                     # the worked example's 4200 + 200 t N m
    I_red2 = m2 * rho2**2 + m3 * r2**2
    G3 = m3 * g
    # shaft 1 turns R2/R1 as fast as shaft 2 (belt without slip)
    inertia = I_red2 + I1 * (R2 / R1) ** 2
    moment = M * R2 / R1 - G3 * r2 - Mc
    check_one_dof(model, inertia, moment)
    # the textbook's eps2, written over R1^2
    eps2 = (M * R1 * R2 - (G3 * r2 + Mc) * R1**2) / (I1 * R2**2 + I_red2 * R1**2)
    mech = model.mechanism
    assert is_zero(mech.reduced_moment() / mech.reduced_inertia() - eps2)


def test_rope_hoist_angular_acceleration_numbers():
    model = load("rope_hoist")
    mech = model.mechanism
    eps2 = sp.expand((mech.reduced_moment() / mech.reduced_inertia()).subs(model.params))
    assert eps2.free_symbols == {md.t}
    slope, intercept = sp.Poly(eps2, md.t).all_coeffs()
    assert float(slope) == pytest.approx(4.0336, abs=1e-4)
    assert float(intercept) == pytest.approx(0.45983, abs=1e-4)
    I_red2 = 150 * 0.3**2 + 400 * 0.2**2
    assert I_red2 == pytest.approx(29.5)
    assert float(mech.reduced_inertia().subs(model.params)) == pytest.approx(
        8 * (0.4 / 0.6) ** 2 + 29.5, rel=1e-12)


# --------------------------------------------------------------------------- LaTeX
def test_latex_derivation_of_scotch_yoke():
    text = load("scotch_yoke").mechanism.latex()
    assert "\\begin{align*}" in text and "\\end{align*}" in text
    assert "\\dot{\\phi}" in text and "\\ddot{\\phi}" in text      # dots, Greek letter
    assert "J_{1A}" in text and "m_{3}" in text                   # subscripts
    lines = {line.split("&=")[0].strip(): line for line in text.splitlines() if "&=" in line}
    assert "T" in lines
    inertia = lines["I_{\\mathrm{red}}"]         # in the named transmission function
    assert inertia.endswith("J_{1A} + m_{3} \\left(x_{\\text{yoke}}^{\\prime}\\right)^{2} \\\\")
    assert "\\sin" in lines["x_{\\text{yoke}}^{\\prime}"]
    moment = lines["M_{\\mathrm{red}}"]
    assert "F_{3}" in moment and "M_{1}" in moment
    assert any("\\frac{d I_{\\mathrm{red}}}{d \\phi}" in key for key in lines)


def test_latex_greek_subscripted_coordinates_and_parameters():
    text = load("rope_hoist").mechanism.latex()
    assert "\\dot{\\phi}_{2}" in text and "\\ddot{\\phi}_{2}" in text
    assert "\\rho_{2}" in text and "I_{\\mathrm{red}}" in text and "M_{\\mathrm{red}}" in text
    assert "phidot" not in text and "rho_2" not in text


def test_latex_of_two_dof_mechanism():
    phi_1, phi_2 = md.coordinates("phi_1 phi_2")
    J1, J2, k = sp.symbols("J_1 J_2 k", positive=True)
    mech = md.Mechanism("two discs", [phi_1, phi_2])
    mech.link("disc 1", J=J1, angle=phi_1)
    mech.link("disc 2", J=J2, angle=phi_2)
    mech.spring("shaft", k, stretch=phi_2 - phi_1)
    text = mech.latex()
    assert "\\ddot{\\phi}_{1}" in text and "\\ddot{\\phi}_{2}" in text
    assert "I_{\\mathrm{red}}" not in text          # no reduced quantities for 2 DOF
    assert "\\dot{\\phi}_{1}" in text


# ----------------------------------------------------------------- command line
def test_cli_equations_latex(capsys):
    assert main(["equations", str(MODELS / "scotch_yoke.py")]) == 0
    out = capsys.readouterr().out
    assert "\\begin{align*}" in out and "\\dot{\\phi}" in out
    assert "I_{\\mathrm{red}}" in out and "M_{\\mathrm{red}}" in out


def test_cli_equations_text(capsys):
    assert main(["equations", str(MODELS / "scotch_yoke.py"), "--format", "text"]) == 0
    out = capsys.readouterr().out
    assert "\\" not in out
    J1A, m3, l, M1, F3 = sp.symbols("J_1A m_3 l M_1 F_3", positive=True)
    phi = sp.Symbol("phi")
    names = {"J_1A": J1A, "m_3": m3, "l": l, "M_1": M1, "F_3": F3, "phi": phi}
    found, defined = {}, []
    for line in out.splitlines():     # primes read as _p: x_yoke' -> x_yoke_p
        label, _, rest = line.strip().replace("'", "_p").partition(": ")
        if label in ("position", "transmission function", "reduced inertia",
                     "reduced moment"):
            name, _, expr = rest.strip().partition(" = ")
            found[name] = sp.parse_expr(expr, local_dict=names)
            defined.append(name)
    named = {sp.Symbol(name): expr for name, expr in found.items()
             if name not in ("I_red", "M_red")}
    assert defined == ["x_yoke", "x_yoke_p", "x_yoke_p_p", "I_red", "M_red"]  # each once
    assert is_zero(found["I_red"].subs(named) - (J1A + m3 * l**2 * sp.sin(phi) ** 2))
    assert is_zero(found["M_red"].subs(named) - (M1 - F3 * l * sp.sin(phi)))


def test_cli_missing_model_names_the_file(capsys, tmp_path):
    missing = tmp_path / "no_such_model.py"
    assert main(["equations", str(missing)]) == 2
    assert "no_such_model.py" in capsys.readouterr().err

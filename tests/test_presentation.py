"""What the result objects show a person: summaries, LaTeX and figures state the values
that were computed, with the numbers checked against hand results (the forced
oscillator's closed form, the linearised machine, the shoe brake's 100 - 2t)."""
import math
import re

import numpy as np
import pytest
import sympy as sp

import mechdyn as md

x = md.coordinate("x")
phi = md.coordinate("phi")


def numbers_after(label, text):
    """The floats following ``label`` in ``text``."""
    match = re.search(re.escape(label) + r"\s*([-+0-9.e ]+)", text)
    assert match, f"{label!r} not in {text!r}"
    return [float(v) for v in match.group(1).split()]


# forced damped oscillator m x'' + c x' + k x = F cos(W t), m = 1
C_, K_, F_, W_ = 0.8, 4.0, 1.5, 1.3
D2 = (K_ - W_ ** 2) ** 2 + (C_ * W_) ** 2


def forced(method="auto"):
    mech = md.Mechanism("forced oscillator", [x])
    mech.link("mass", m=1, x=x)
    mech.spring("spring", K_, stretch=x)
    mech.damper("damper", C_, stretch=x)
    mech.load("force", F_ * sp.cos(W_ * md.t), along=x)
    scene = md.Scene("steady", initial={x: 0, md.speed(x): 0}, t_end=1)
    return md.periodic_steady_state(mech, scene, {}, method=method)


def test_periodic_summary_states_period_method_state_amplitude_and_closure():
    text = forced().summary()
    first = text.splitlines()[0]
    assert first.startswith("forced oscillator — scene 'steady': periodic motion, T = ")
    assert numbers_after("T =", first)[0] == pytest.approx(2 * math.pi / W_, rel=1e-5)
    assert "(initial parameters; linear in the state)" in first
    # the periodic state at t = 0: x = F (k - W^2) / D^2 (closed form)
    assert numbers_after("x =", text)[0] == pytest.approx(F_ * (K_ - W_ ** 2) / D2, rel=1e-5)
    low, high, amplitude = numbers_after("\n  x ", text)
    assert amplitude == pytest.approx(F_ / math.sqrt(D2), rel=1e-4)
    assert low == pytest.approx(-amplitude, rel=1e-4) and high == pytest.approx(amplitude,
                                                                                 rel=1e-4)
    assert numbers_after("closure |y(t0 + T) - y(t0)| =", text)[0] < 1e-8
    assert "asymptotically stable" in text


def test_periodic_summary_of_shooting_counts_newton_steps(tmp_path):
    steady = forced(method="shooting")
    assert f"(shooting, {steady.iterations} Newton steps; linear in the state)" in \
        steady.summary()
    steady.plot(tmp_path / "period.png")
    assert (tmp_path / "period.png").stat().st_size > 1000


def linearised_machine():
    # J w w' = M_0 (1 - w/w_0) + A cos(phi): mean speed w_0 (the process averages out).
    J = sp.Symbol("J", positive=True)
    mech = md.Mechanism("machine", [phi])
    mech.link("flywheel", J=J, angle=phi)
    mech.load("motor", md.motors.dc_shunt(400.0, 110.0)(md.speed(phi)), along=phi)
    mech.load("process", 20.0 * sp.cos(phi), along=phi)
    return mech, md.Scene("run", initial={phi: 0, md.speed(phi): 100}, t_end=1), J


def test_steady_running_summary_and_figure_show_the_cycle():
    mech, scene, J = linearised_machine()
    running = md.steady_running(mech, scene, {J: 2.0})
    text = running.summary()
    assert text.startswith("machine — scene 'run': steady running over a cycle of 6.28319 rad")
    assert len(text.splitlines()) == 5
    assert text.splitlines()[1].startswith("  periodic state at phi = ")
    mean = numbers_after("mean speed", text)[0]
    assert mean == pytest.approx(110.0, rel=1e-4)
    delta = numbers_after("coefficient of speed fluctuation delta =", text)[0]
    assert delta == pytest.approx(running.delta, rel=1e-5)
    assert f"(1/{1 / running.delta:.4g})" in text
    assert numbers_after("omega max", text)[0] == pytest.approx(running.omega_max, rel=1e-5)
    assert numbers_after("min", text.split("omega max")[1])[0] == pytest.approx(
        running.omega_min, rel=1e-5)
    assert str(running.floquet) in text
    fig = running.plot()
    ax = fig.axes[0]
    curve, *levels = ax.lines
    assert np.array_equal(curve.get_xdata(), running.phi)
    assert np.array_equal(curve.get_ydata(), running.omega)
    assert [line.get_ydata()[0] for line in levels] == pytest.approx(
        [running.omega_mean, running.omega_max, running.omega_min])
    assert [line.get_linestyle() for line in levels] == ["-", "--", "--"]
    assert [t.get_text() for t in ax.get_legend().get_texts()] == [
        "omega(phi)", f"mean {running.omega_mean:.5g}", f"max {running.omega_max:.5g}",
        f"min {running.omega_min:.5g}"]
    assert ax.get_xlabel() == "phi [rad]" and ax.get_ylabel() == "omega [rad/s]"
    assert ax.get_title() == f"machine — scene 'run': delta = {running.delta:.4g}"


def test_flywheel_summary_states_the_sized_and_the_textbook_inertia():
    # The energy swing of A cos(phi) over a cycle is 2 A = 40 J (the motor is nearly
    # constant at the mean speed).
    mech, scene, J = linearised_machine()
    sized = md.flywheel(mech, scene, {J: 2.0}, delta=1 / 50, inertia=J)
    text = sized.summary()
    assert numbers_after("flywheel J =", text)[0] == pytest.approx(sized.inertia, rel=1e-5)
    assert numbers_after("for delta =", text)[0] == pytest.approx(0.02, rel=1e-9)
    assert numbers_after("steady running gives", text)[0] == pytest.approx(0.02, rel=1e-3)
    assert numbers_after("(Delta E_max =", text)[0] == pytest.approx(40.0, rel=0.02)
    assert numbers_after("textbook Delta E_max / (delta omega_mean^2): J =", text)[0] == \
        pytest.approx(sized.textbook, rel=1e-5)
    assert numbers_after("omega_mean =", text)[0] == pytest.approx(110.0, rel=1e-3)
    assert numbers_after("own mean I_red", text)[0] == pytest.approx(sized.own_inertia,
                                                                     rel=1e-5)


def test_closed_form_latex_of_the_shoe_brake():
    brake = md.load_model("models/shoe_brake.py")
    sol = md.closed_form(brake.mechanism, brake.scenes["braking"], brake.params)
    assert sol.latex().splitlines() == [
        f"% {sol.classification}", r"\begin{align*}",
        r"\dot{\phi}(t) &= 100 - 2 t \\", r"\phi(t) &= - t^{2} + 100 t \\",
        r"t_{\mathrm{stop}} &= 50, \quad \phi_{\mathrm{stop}} = 2500", r"\end{align*}"]


def test_equations_display_as_latex_in_jupyter():
    disc = md.Mechanism("disc", [phi])
    disc.link("disc", J=2, angle=phi)
    disc.load("drive", 6, along=phi)
    assert disc.equations()._repr_latex_() == r"$\displaystyle 2 \ddot{\phi} = 6$"


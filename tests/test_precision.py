"""Work-precision reports (mechdyn.analyse.precision) and the `mechdyn precision` command.

Reference values are worked out by hand: the shoe brake stops at 50 s and 2500 rad
(worked example 1); the slider-crank's reduced inertia comes from differentiating its
exact kinematics by hand below.
"""
import dataclasses
import math
from pathlib import Path

import pytest

import mechdyn as md
from mechdyn.cli import main

MODELS = Path(__file__).resolve().parent.parent / "models"
ALL_METHODS = ["RK45", "DOP853", "LSODA", "Radau", "BDF"]


def model(name):
    return md.load_model(MODELS / f"{name}.py")


def test_shoe_brake_report_uses_the_closed_form_and_every_method_meets_1e9_on_the_stop():
    brake = model("shoe_brake")
    table = md.work_precision(brake.mechanism, brake.scenes["braking"], brake.params,
                              methods=ALL_METHODS, rtols=[1e-4, 1e-8], repeats=1)
    assert table.reference.kind == "closed form"
    assert table.reference.events == {("end", "stopped(phi)"): [50.0]}
    phi_stop, omega_stop = table.reference.states([50.0])[:, 0]
    assert (phi_stop, omega_stop) == pytest.approx((2500.0, 0.0), abs=1e-9)
    assert [row.method for row in table.rows] == [m for m in ALL_METHODS for _ in (1, 2)]
    for row in table.rows:
        assert not row.failed, row.failure
        (label, error), = row.event_errors
        assert label == "stopped(phi)"
        assert error < 1e-9, (row.method, row.rtol, error)
        assert row.runs >= 1 and row.time > 0 and row.nfev > 0 and row.steps > 0
    assert "closed form" in str(table) and "stopped(phi)" in str(table)


def _reduced_inertia_by_hand(phi, r=0.1, L=0.4, J_1=0.01, m_2=0.5, m_3=1.0):
    """I_red of the exact slider-crank: sum of m v^2 + J w^2 per unit crank speed."""
    J_2 = m_2 * L**2 / 12
    s, c = math.sin(phi), math.cos(phi)
    root = math.sqrt(L**2 - r**2 * s**2)
    root_rate = -r**2 * s * c / root            # d root / d phi
    slider = -r * s + root_rate                 # d x_slider / d phi
    rod_x, rod_y = -r * s + root_rate / 2, r * c / 2
    rod_turn = r * c / root                     # d asin(r sin(phi) / L) / d phi
    return J_1 + m_3 * slider**2 + m_2 * (rod_x**2 + rod_y**2) + J_2 * rod_turn**2


def test_slider_crank_model_is_the_exact_mechanism():
    crank = model("slider_crank")
    inertia = crank.mechanism.reduced_inertia()
    values = {symbol: value for symbol, value in crank.params.items()}
    q = md.plain(crank.mechanism.coordinates[0])
    for angle in (0.0, 0.7, math.pi / 3, 2.0):
        assert float(inertia.subs(values).subs(q, angle)) == pytest.approx(
            _reduced_inertia_by_hand(angle), rel=1e-12)


def test_slider_crank_error_falls_as_the_tolerance_tightens():
    crank = model("slider_crank")
    scene = dataclasses.replace(crank.scenes["startup"], t_end=0.2)
    rtols = [1e-4, 1e-6, 1e-8]
    table = md.work_precision(crank.mechanism, scene, crank.params, methods=ALL_METHODS,
                              rtols=rtols, repeats=1)
    assert table.reference.kind == "numerical"
    assert table.reference.agreement < 1e-9        # DOP853 and Radau agree
    for method in ALL_METHODS:
        rows = [r for r in table.rows if r.method == method]
        assert [r.rtol for r in rows] == rtols
        errors = [r.error for r in rows]
        assert all(not r.failed for r in rows), method
        assert errors[-1] < errors[0] / 100, (method, errors)          # it does fall
        assert all(b < 3 * a for a, b in zip(errors, errors[1:])), (method, errors)
        for r in rows:
            assert r.l2_error >= r.final_error > 0, (method, r.rtol)
    assert table.cheapest(1e-6).error <= 1e-6


def test_a_failing_method_is_a_failure_row_not_an_exception():
    brake = model("shoe_brake")
    table = md.work_precision(brake.mechanism, brake.scenes["braking"], brake.params,
                              methods=["RK45", "Euler"], rtols=[1e-6], repeats=1)
    good, bad = table.rows
    assert not good.failed and good.error < 1e-9
    assert bad.failed and "Euler" in bad.failure and math.isnan(bad.error)
    assert "FAILED" in str(table)
    assert table.cheapest(1e-6) is good


def test_cheapest_refuses_a_target_below_the_reference_agreement():
    crank = model("slider_crank")
    scene = dataclasses.replace(crank.scenes["startup"], t_end=0.05)
    table = md.work_precision(crank.mechanism, scene, crank.params, methods=["DOP853"],
                              rtols=[1e-6], repeats=1)
    assert table.reference.agreement > 0
    with pytest.raises(md.MechdynError, match="reference"):
        table.cheapest(table.reference.agreement / 10)


def test_precision_command_prints_the_table_and_writes_a_png(tmp_path, capsys):
    png = tmp_path / "wp.png"
    status = main(["precision", str(MODELS / "shoe_brake.py"), "--scene", "braking",
                   "--methods", "RK45", "LSODA", "--rtols", "1e-6", "1e-9",
                   "--plot", str(png), "--target", "1e-6"])
    out = capsys.readouterr().out
    assert status == 0
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "closed form" in out and "cheapest meeting 1.0e-06:" in out
    assert out.count("RK45 ") >= 2 and out.count("LSODA ") >= 2

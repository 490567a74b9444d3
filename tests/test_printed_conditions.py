"""The printed derivation writes a load's switching condition as the user wrote it
(issue 42): in the named positions and their rates, in the sense it was written,
not in sympy's canonical form of the raw coordinates (``phidot r sin(phi) + ... < 0``
for "the ram moves down")."""
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import sympy as sp
from sympy.core.relational import Relational

import mechdyn as md

ROOT = Path(__file__).resolve().parents[1]
PRESS = ROOT / "tests" / "data" / "pressing_ram.py"


def _equations(model, *options):
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    done = subprocess.run([sys.executable, "-m", "mechdyn.cli", "equations", str(model),
                           *options], capture_output=True, text=True, env=env, timeout=120)
    assert done.returncode == 0, done.stderr
    return done.stdout


def _law_line(text, name):
    return next(line for line in text.splitlines() if f"F_{name}(phi, phidot) =" in line
                or f"F_{{\\text{{{name}}}}}" in line.split("&=")[0])


def test_the_press_prints_its_condition_in_the_ram_position_and_rate_as_written():
    text = _law_line(_equations(PRESS, "--format", "text"), "workpiece")
    assert text.endswith("= Piecewise((-F_p, x_ram > -h + l + r and phidot*x_ram' > 0), "
                         "(0, True))")
    latex = _law_line(md.load_model(PRESS).mechanism.latex(), "workpiece")
    assert ("x_{\\text{ram}} > - h + l + r \\wedge \\dot{\\phi} x_{\\text{ram}}^{\\prime} > 0"
            in latex)
    assert latex == _law_line(_equations(PRESS), "workpiece")       # the CLI's LaTeX


def _press(moving, height=lambda x: x):
    """The press of tests/data/pressing_ram.py, its ram at ``height(x_ram)`` and the
    workpiece acting while ``moving(rate of the ram's position)``."""
    phi = md.coordinate("phi")
    r, l, h, J_c, m_r, F_p = sp.symbols("r l h J_c m_r F_p", positive=True)
    x_ram = height(r * sp.cos(phi) + sp.sqrt(l**2 - r**2 * sp.sin(phi)**2))
    press = md.Mechanism("press", [phi])
    press.link("crank", J=J_c, angle=phi)
    press.link("ram", m=m_r, y=x_ram)
    near = abs(x_ram) > r + l - h
    press.load("workpiece", sp.Piecewise((-F_p, near & moving(sp.diff(x_ram, md.t))),
                                         (0, True)), along=x_ram)
    return press


def test_the_sense_is_the_one_written_for_either_direction_and_axis():
    cases = [(lambda v: v > 0, lambda x: x, "phidot*y_ram' > 0"),
             (lambda v: v < 0, lambda x: x, "phidot*y_ram' < 0"),
             (lambda v: v < 0, lambda x: -x, "phidot*y_ram' < 0"),    # y up: moving down
             (lambda v: 0 < v, lambda x: -x, "phidot*y_ram' > 0")]
    for moving, height, expected in cases:
        book = _press(moving, height).derivation()
        law = next(rhs for label, _, lhs, rhs in book.steps if lhs.startswith("F_workpiece"))
        assert expected in sp.sstr(law)


def test_the_printed_condition_means_what_the_numerics_compute():
    """Written back in the coordinates, the printed relations hold exactly where the
    law the simulation uses acts (random states, both senses)."""
    rng = np.random.default_rng(3)
    for moving, height in ((lambda v: v > 0, lambda x: x), (lambda v: v < 0, lambda x: -x)):
        press = _press(moving, height)
        book = press.derivation()
        law = next(rhs for label, _, lhs, rhs in book.steps if lhs.startswith("F_workpiece"))
        numeric = press.equations().works["workpiece"].forces[0][0]
        printed = law.atoms(sp.Piecewise).pop().args[0][1]
        relations = [book.expand(book.expand(rel)) for rel in printed.atoms(Relational)]
        assert len(relations) == 2
        names = {s.name: s for s in numeric.free_symbols}
        args = [names[n] for n in ("phi", "phidot", "r", "l", "h", "F_p")]
        acts = sp.lambdify(args, numeric)
        holds = [sp.lambdify(args, rel) for rel in relations]
        for phi, phidot in zip(rng.uniform(-np.pi, np.pi, 200), rng.uniform(-5, 5, 200)):
            point = (phi, phidot, 0.05, 0.25, 0.01, 1.0)
            assert acts(*point) == (-1.0 if all(h(*point) for h in holds) else 0.0)


def test_a_closed_loop_press_prints_its_ram_speed_as_the_transmission_function():
    """The toggle press (two loops) writes "the ram moves down" as y' phidot < 0 in its
    reduced moment, y' = dy/dphi its printed transmission function."""
    text = _equations(ROOT / "models" / "toggle_press.py", "--format", "text")
    moment = next(line for line in text.splitlines() if "reduced moment:" in line)
    assert "Piecewise((k_w*(-y + y_c), y < y_c and y'*phidot < 0), (0, True))" in moment
    force = next(line for line in text.splitlines() if "Q[workpiece, y]" in line)
    assert force.endswith("Piecewise((k_w*(-y + y_c), y < y_c and ydot < 0), (0, True))")

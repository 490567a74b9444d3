"""The generated Jacobian against the exact sympy derivative, for every scene of every
bundled model (issue 20 item 3). The reference is built here from the equations alone:
``dy/dt = [u, M^-1 f]`` with the friction signs fixed (``f = f_smooth - sum s_k F_k
grad_k``, as conventions.md states), ``M^-1 f`` solved symbolically (parameters, time and all
states but the one differentiated replaced by numbers), differentiated by sympy and
evaluated to 30 digits at random states, times, parameter values and friction signs."""
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

import mechdyn as md

MODELS = sorted(Path(__file__).resolve().parent.parent.glob("models/*.py"))
SCENES = [(path.stem, name) for path in MODELS for name in md.load_model(path).scenes]


def test_every_bundled_model_has_a_scene_here():
    assert {name for name, _ in SCENES} == {path.stem for path in MODELS}
    assert len(SCENES) >= 12


def _random_point(rng, eqs, compiled, params):
    """Parameter values scaled by random factors in [0.8, 1.25], a random state, time and
    friction signs (the state is redrawn while the mass matrix is not positive definite)."""
    values = {}
    for symbol, value in params.items():
        if str(symbol) in compiled.param_names:
            values[str(symbol)] = float(sp.sympify(value)) * rng.uniform(0.8, 1.25)
    signs = [float(s) for s in rng.choice([-1.0, 1.0], size=len(compiled.frictions))]
    n = compiled.dof
    mass = eqs.mass_matrix.xreplace({s: values[s.name] for s in eqs.parameters})
    for _ in range(50):
        y = np.concatenate([rng.uniform(-1.5, 1.5, n), rng.uniform(-3, 3, n)])
        time = float(rng.uniform(0, 2))
        at = dict(zip(eqs.q, y[:n])) | {md.t: time}
        if np.linalg.eigvalsh(np.array(mass.xreplace(at), dtype=float))[0] > 0:
            return values, signs, y, time
    raise AssertionError("no state with a positive definite mass matrix found")


def exact_jacobian(eqs, values, signs, y, time):
    """d[u, M^-1 f]/d[q, u] by sympy at one point (30 digits): column j is the derivative
    at eps = 0 of the right-hand side along the line y + eps e_j, solved symbolically in
    the single variable eps."""
    numbers = {s: sp.Float(values[s.name], 30) for s in eqs.parameters}
    numbers[md.t] = sp.Float(time, 30)
    forcing = eqs.smooth_forcing
    for sign, friction in zip(signs, eqs.frictions):
        forcing = forcing - sign * friction.magnitude * friction.gradient
    mass, forcing = eqs.mass_matrix.xreplace(numbers), forcing.xreplace(numbers)
    states = list(eqs.q) + list(eqs.u)
    eps = sp.Symbol("eps")
    point = [sp.Float(v, 30) for v in y]
    rhs = sp.Matrix(list(eqs.u) + list(mass.LUsolve(forcing)))
    columns = []
    for j in range(len(states)):
        line = {x: v + eps if i == j else v for i, (x, v) in enumerate(zip(states, point))}
        columns.append([sp.diff(e, eps).xreplace({eps: 0}).evalf(30)
                        for e in rhs.xreplace(line)])
    rhs = rhs.xreplace(dict(zip(states, point)))
    return np.array(columns, dtype=float).T, np.array(rhs.evalf(30), dtype=float).ravel()


@pytest.mark.parametrize("model_name, scene_name", SCENES)
def test_generated_jacobian_equals_the_exact_derivative(model_name, scene_name):
    model = md.load_model(Path(__file__).resolve().parent.parent / "models" / f"{model_name}.py")
    scene = model.scenes[scene_name]
    compiled = model.mechanism.compile(scene)
    eqs = model.mechanism.equations(scene)
    rng = np.random.default_rng(sum(map(ord, model_name + scene_name)))
    for _ in range(2):
        values, signs, y, time = _random_point(rng, eqs, compiled, model.params)
        expected, rhs = exact_jacobian(eqs, values, signs, y, time)
        p = compiled.parameter_vector(values, signs)
        got = compiled.jac(time, np.array(y), p)
        scale = np.abs(expected).max()
        assert np.allclose(got, expected, rtol=1e-9, atol=1e-11 * scale), \
            f"{model_name}/{scene_name} at t = {time}, y = {y}, signs {signs}"
        assert np.allclose(compiled.rhs(time, np.array(y), p), rhs, rtol=1e-10,
                           atol=1e-12 * np.abs(rhs).max())

"""The generated Jacobian against the exact sympy derivative, for every scene of every
bundled model (issue 20 item 3). The reference is built here from the equations alone:
``dy/dt = [u, a]`` with ``[M -G'; G 0] [a; lambda] = [f; -bias]`` (closed loops and
gears: ``G = dg/dq`` and ``bias = d/dt(G u + dg/dt) - G a`` taken here from each
constraint's expression ``g(q, t)``; no constraint: ``M a = f``), the friction signs
fixed (``f = f_smooth - sum s_k F_k grad_k``, as conventions.md states). Its derivative
is exact: ``d[a; lambda]/dy_j = K^-1 (dr/dy_j - dK/dy_j [a; lambda])`` with every partial
derivative taken by sympy, evaluated to 30 digits at random states, times, parameter
values (the model's, read by ``parameter_vector``, scaled at random) and friction signs.

Mechanisms with constraints have no analytic Jacobian by design: their ``jac`` is central
differences of ``rhs`` with step ``h_j = 1e-7 max(1, |y_j|)``. There ``rhs`` is held to
the exact value as tightly as everywhere, and ``jac`` to the exact derivative within the
textbook error of central differences, ``delta / h_j + h_j^2 / 6 * |third derivative|``:
``delta``, the rounding of ``rhs``, bounded as for a stable solve of ``K`` (size N,
condition number kappa) by ``N kappa eps max|rhs|``, and the third derivative taken as
large as the Jacobian."""
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

import mechdyn as md

MODELS = sorted(Path(__file__).resolve().parent.parent.glob("models/*.py"))
SCENES = [(path.stem, name) for path in MODELS for name in md.load_model(path).scenes]
EPS = np.finfo(float).eps


def test_every_bundled_model_has_a_scene_here():
    assert {name for name, _ in SCENES} == {path.stem for path in MODELS}
    assert len(SCENES) >= 12


def _constraint_rows(eqs):
    """``G`` and ``bias`` from each constraint's expression: ``g'' = G a + bias``."""
    q, u = list(eqs.q), list(eqs.u)
    grads, biases = [], []
    for constraint in eqs.constraints:
        g = constraint.expression
        grad = [sp.diff(g, x) for x in q]
        rate = sum((gi * ui for gi, ui in zip(grad, u)), sp.diff(g, md.t))
        biases.append(sum((sp.diff(rate, x) * ux for x, ux in zip(q, u)), sp.diff(rate, md.t)))
        grads.append(grad)
    return sp.Matrix(len(grads), len(q), lambda i, j: grads[i][j]), sp.Matrix(biases)


def _system(eqs, values, signs):
    """``K`` and ``r`` of ``K [a; lambda] = r`` in the states and t, parameters numbered."""
    forcing = eqs.smooth_forcing
    for sign, friction in zip(signs, eqs.frictions):
        forcing = forcing - sign * friction.magnitude * friction.gradient
    n, m = eqs.dof, len(eqs.constraints)
    grad, bias = _constraint_rows(eqs)
    K = sp.zeros(n + m, n + m)
    K[:n, :n] = eqs.mass_matrix
    r = sp.zeros(n + m, 1)
    r[:n, 0] = forcing
    if m:
        K[:n, n:], K[n:, :n], r[n:, 0] = -grad.T, grad, -bias
    numbers = {s: sp.Float(values[s.name], 30) for s in K.free_symbols | r.free_symbols
               if s.name in values}           # a gear's ratio is in its constraint only
    return K.xreplace(numbers), r.xreplace(numbers)


def _allowed_motions(eqs, K, at):
    """A basis of the motions the constraints allow at ``at`` (all motions without)."""
    n = eqs.dof
    grad = np.array(K[n:, :n].xreplace(at).evalf(), dtype=float).reshape(-1, n)
    if not len(grad):
        return np.eye(n)
    _, singular, vt = np.linalg.svd(grad)
    rank = int(np.sum(singular > 1e-12 * singular.max()))
    return vt[rank:].T


def _random_point(rng, eqs, compiled, params):
    """Parameter values scaled by random factors in [0.8, 1.25], a random state, time and
    friction signs (the state is redrawn while the mass matrix is not positive definite on
    the motions the constraints allow)."""
    model_values = compiled.parameter_vector(params)[:len(compiled.param_names)]
    values = {name: value * rng.uniform(0.8, 1.25)
              for name, value in zip(compiled.param_names, model_values)}
    signs = [float(s) for s in rng.choice([-1.0, 1.0], size=len(compiled.frictions))]
    n = compiled.dof
    K, _ = _system(eqs, values, signs)
    for _ in range(50):
        y = np.concatenate([rng.uniform(-1.5, 1.5, n), rng.uniform(-3, 3, n)])
        time = float(rng.uniform(0, 2))
        at = dict(zip(eqs.q, y[:n])) | {md.t: time}
        basis = _allowed_motions(eqs, K, at)
        mass = np.array(K[:n, :n].xreplace(at).evalf(), dtype=float)
        if np.linalg.eigvalsh(basis.T @ mass @ basis)[0] > 0:
            return values, signs, y, time
    raise AssertionError("no state with a positive definite mass matrix found")


def exact_jacobian(eqs, values, signs, y, time):
    """d[u, a]/d[q, u], [u, a] and the condition number of ``K`` at one point, to 30
    digits (module docstring)."""
    n = eqs.dof
    K, r = _system(eqs, values, signs)
    states = list(eqs.q) + list(eqs.u)
    at = dict(zip(states, [sp.Float(v, 30) for v in y])) | {md.t: sp.Float(time, 30)}
    K_at, r_at = K.xreplace(at).evalf(30), r.xreplace(at).evalf(30)
    solution = K_at.LUsolve(r_at)
    columns = []
    for x in states:
        change = (r.diff(x).xreplace(at) - K.diff(x).xreplace(at) * solution).evalf(30)
        columns.append([1 if x == speed else 0 for speed in eqs.u]
                       + list(K_at.LUsolve(change)[:n, 0]))
    rhs = list(y[n:]) + list(solution[:n, 0])
    return (np.array(columns, dtype=float).T, np.array([float(v) for v in rhs]),
            np.linalg.cond(np.array(K_at, dtype=float)))


@pytest.mark.parametrize("model_name, scene_name", SCENES)
def test_generated_jacobian_equals_the_exact_derivative(model_name, scene_name):
    model = md.load_model(Path(__file__).resolve().parent.parent / "models" / f"{model_name}.py")
    scene = model.scenes[scene_name]
    compiled = model.mechanism.compile(scene)
    eqs = model.mechanism.equations(scene)
    rng = np.random.default_rng(sum(map(ord, model_name + scene_name)))
    for _ in range(2):
        values, signs, y, time = _random_point(rng, eqs, compiled, model.params)
        expected, rhs, kappa = exact_jacobian(eqs, values, signs, y, time)
        p = compiled.parameter_vector(values, signs)
        where = f"{model_name}/{scene_name} at t = {time}, y = {y}, signs {signs}"
        size = eqs.dof + len(eqs.constraints)
        # rhs rounds as a stable solve of K (docstring): 16 N kappa eps max|rhs|, >= 1e-12
        rounding = max(1e-12, 16 * size * kappa * EPS) * np.abs(rhs).max()
        assert np.allclose(compiled.rhs(time, np.array(y), p), rhs, rtol=1e-10,
                           atol=rounding), where
        got = compiled.jac(time, np.array(y), p)
        scale = np.abs(expected).max()
        if not eqs.constraints:
            assert np.allclose(got, expected, rtol=1e-9, atol=1e-11 * scale), where
            continue
        steps = 1e-7 * np.maximum(1.0, np.abs(y))          # central differences
        error = size * kappa * EPS * np.abs(rhs).max() / steps + steps ** 2 / 6 * scale
        assert np.all(np.abs(got - expected) <= error[np.newaxis, :]), where

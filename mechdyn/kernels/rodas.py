"""One Rodas5P step: Jacobian, stages, error norm, step-size factor, dense output.

Rodas5P (Steinebach, "Construction of Rosenbrock-Wanner method Rodas5P and numerical
benchmarks within the Julia Differential Equations package", BIT 63, 27 (2023); the
stiff default of DifferentialEquations.jl) is a stiffly accurate, L-stable Rosenbrock
method of order 5 with an embedded order-4 solution and a 4th-order dense output:
8 stages, one LU decomposition of (I / (h gamma) - J) per step and no Newton iteration,
so its cost per step is fixed and it cannot thrash the way an implicit method's Newton
solver can at tight tolerances. In the transformed form used here (Hairer & Wanner,
Solving ODEs II, IV.7)::

    (I / (h gamma) - J) k_s = f(t + c_s h, y + sum_j A[s, j] k_j)
                              + h d_s df/dt + sum_j C[s, j] / h k_j
    y_new = y + sum_j A[7, j] k_j + k_7        (error estimate: k_7)

Dense output: y(t + x h) = (1 - x) y + x (y_new + (1 - x)(k1 + x (k2 + x k3))) with
k_m = sum_j H[m, j] k_j, i.e. a degree-4 polynomial in x. Step-size control is
Hairer's rodas.f (safety 0.9, new/old step within [0.2, 6], Gustafsson's predictive
controller) with the exponent 1/5 of the order-4 error estimate.
"""
import math

import numpy as np
from numba import njit

from .iteration import factor, matvec, solve
from .linalg import stage_sum

GAMMA = 0.21193756319429014
A = np.zeros((8, 8))
A[1, :1] = [3.0]
A[2, :2] = [2.849394379747939, 0.45842242204463923]
A[3, :3] = [-6.954028509809101, 2.489845061869568, -10.358996098473584]
A[4, :4] = [2.8029986275628964, 0.5072464736228206, -0.3988312541770524,
            -0.04721187230404641]
A[5, :5] = [-7.502846399306121, 2.561846144803919, -11.627539656261098,
            -0.18268767659942256, 0.030198172008377946]
A[6, :6] = [*A[5, :5], 1.0]
A[7, :7] = [*A[5, :5], 1.0, 1.0]
C = np.zeros((8, 8))
C[1, :1] = [-14.155112264123755]
C[2, :2] = [-17.97296035885952, -2.859693295451294]
C[3, :3] = [147.12150275711716, -1.41221402718213, 71.68940251302358]
C[4, :4] = [165.43517024871676, -0.4592823456491126, 42.90938336958603,
            -5.961986721573306]
C[5, :5] = [24.854864614690072, -3.0009227002832186, 47.4931110020768,
            5.5814197821558125, -0.6610691825249471]
C[6, :6] = [30.91273214028599, -3.1208243349937974, 77.79954646070892,
            34.28646028294783, -19.097331116725623, -28.087943162872662]
C[7, :7] = [37.80277123390563, -3.2571969029072276, 112.26918849496327,
            66.9347231244047, -40.06618937091002, -54.66780262877968, -9.48861652309627]
STAGE_TIMES = np.array([0.0, 0.6358126895828704, 0.4095798393397535, 0.9769306725060716,
                        0.4288403609558664, 1.0, 1.0, 1.0])
D = np.array([0.21193756319429014, -0.42387512638858027, -0.3384627126235924,
              1.8046452872882734, 2.325825639765069, 0.0, 0.0, 0.0])
H = np.array([
    [25.948786856663858, -2.5579724845846235, 10.433815404888879, -2.3679251022685204,
     0.524948541321073, 1.1241088310450404, 0.4272876194431874, -0.17202221070155493],
    [-9.91568850695171, -0.9689944594115154, 3.0438037242978453, -24.495224566215796,
     20.176138334709044, 15.98066361424651, -6.789040303419874, -6.710236069923372],
    [11.419903575922262, 2.8879645146136994, 72.92137995996029, 80.12511834622643,
     -52.072871366152654, -59.78993625266729, -0.15582684282751913, 4.883087185713722]])

SAFETY = 0.9
MIN_FACTOR = 0.2
MAX_FACTOR = 6.0
EXPONENT = 1.0 / 5.0
EPS = np.finfo(np.float64).eps
CUBE_ROOT_EPS = EPS ** (1.0 / 3.0)


@njit
def jacobian(rhs, jac, has_jac, t, y, f0, p, J, y_work, f_work):
    """J = df/dy at (t, y): the model's ``jac``, or central differences with increments
    eps^(1/3) max(|y_j|, 1e-5) (relative error ~eps^(2/3): forward differences, error
    ~sqrt(eps), cost Rodas5P most of its accuracy at tight tolerances, as a Rosenbrock
    method needs the exact Jacobian). Returns the RHS evaluations spent."""
    if has_jac:
        jac(t, y, p, J)
        return 0
    n = y.shape[0]
    for i in range(n):
        y_work[i] = y[i]
    for j in range(n):
        step = CUBE_ROOT_EPS * max(1e-5, abs(y[j]))
        y_work[j] = y[j] + step
        forward = y_work[j] - y[j]          # the increment actually taken
        rhs(t, y_work, p, f_work)
        for i in range(n):
            J[i, j] = f_work[i]
        y_work[j] = y[j] - step
        backward = y[j] - y_work[j]
        rhs(t, y_work, p, f_work)
        y_work[j] = y[j]
        for i in range(n):
            J[i, j] = (J[i, j] - f_work[i]) / (forward + backward)
    return 2 * n


@njit
def time_derivative(rhs, t, y, f0, p, dfdt):
    """df/dt at (t, y) by a forward difference (rodas.f's increment)."""
    delta = math.sqrt(EPS * max(1e-5, abs(t)))
    rhs(t + delta, y, p, dfdt)
    for i in range(y.shape[0]):
        dfdt[i] = (dfdt[i] - f0[i]) / delta


@njit
def attempt(rhs, t, y, f0, h, t_new, p, atol, rtol, J, dfdt, autonomous, W, pivots, ks,
            y_stage, f_stage, y_new, f_new, plan, order, position, core, b_work):
    """Try a step of size ``h`` to ``t_new``: fills ks, y_new and f_new = f(t_new, y_new).
    The iteration matrix is factored and solved as ``plan`` says
    (:mod:`mechdyn.kernels.iteration`; ``order`` and ``position`` its renumbering,
    ``core`` and ``b_work`` its work space).

    Returns the error norm: inf if something is not finite, NaN if the iteration matrix
    is singular (the caller halves the step).
    """
    n = y.shape[0]
    inverse_h = 1.0 / h
    inverse_hg = inverse_h / GAMMA
    if not factor(J, inverse_hg, plan, order, W, core, pivots):
        return math.nan
    for s in range(8):
        if s == 0:
            for i in range(n):
                f_stage[i] = f0[i]
        else:
            for i in range(n):
                y_stage[i] = y[i] + stage_sum(A[s], ks, i, s)
            rhs(t + STAGE_TIMES[s] * h, y_stage, p, f_stage)
        for i in range(n):
            total = f_stage[i]
            if not autonomous:
                total += h * D[s] * dfdt[i]
            for j in range(s):
                total += C[s, j] * inverse_h * ks[j, i]
            ks[s, i] = total
        solve(J, inverse_hg, plan, order, position, W, pivots, ks[s], b_work)
    for i in range(n):
        y_new[i] = y_stage[i] + ks[7, i]
    rhs(t_new, y_new, p, f_new)
    err = 0.0
    for i in range(n):
        if not (math.isfinite(y_new[i]) and math.isfinite(f_new[i])):
            return math.inf
        scale = atol[i] + rtol * max(abs(y[i]), abs(y_new[i]))
        err += (ks[7, i] / scale) ** 2
    err = math.sqrt(err / n)
    return err if math.isfinite(err) else math.inf


@njit(inline="always")
def step_factor(err, h, rejected_before, h_accepted, err_accepted):
    """New step / old step after an error norm ``err`` (rodas.f's rule, with
    Gustafsson's predictive controller once a step has been accepted)."""
    if math.isnan(err):      # singular iteration matrix
        return 0.5
    if math.isinf(err):      # not finite
        return MIN_FACTOR
    divisor = max(1.0 / MAX_FACTOR, min(1.0 / MIN_FACTOR, err ** EXPONENT / SAFETY))
    if err <= 1.0:
        if h_accepted > 0.0:
            predicted = (h_accepted / h) * (err * err / err_accepted) ** EXPONENT / SAFETY
            divisor = max(divisor, max(1.0 / MAX_FACTOR, min(1.0 / MIN_FACTOR, predicted)))
        factor = 1.0 / divisor
        return min(factor, 1.0) if rejected_before else factor
    return 1.0 / divisor


@njit
def dense_output(y, y_new, ks, poly):
    """Monomial coefficients poly[0:5] of the 4th-order interpolant (module doc);
    the higher rows of ``poly`` are zeroed."""
    for i in range(y.shape[0]):
        k1 = stage_sum(H[0], ks, i, 8)
        k2 = stage_sum(H[1], ks, i, 8)
        k3 = stage_sum(H[2], ks, i, 8)
        poly[0, i] = y[i]
        poly[1, i] = y_new[i] - y[i] + k1
        poly[2, i] = k2 - k1
        poly[3, i] = k3 - k2
        poly[4, i] = -k3
        for k in range(5, poly.shape[0]):
            poly[k, i] = 0.0


@njit
def spectral_radius(J, v, w, u, plan, order, position):
    """Estimate of J's spectral radius by two steps of power iteration from ``v``,
    sqrt(|J J v| / |v|) (exact for a dominant real pair +-lambda or complex pair +-i w,
    the oscillators of mechanics); ``v`` is replaced by the normalised J J v so that the
    estimate sharpens from step to step. The products use the structure ``plan`` found
    (:func:`mechdyn.kernels.iteration.matvec`)."""
    n = v.shape[0]
    norm_v = 0.0
    for i in range(n):
        norm_v += v[i] * v[i]
    if not norm_v > 0.0:
        for i in range(n):
            v[i] = 1.0 + i
            norm_v += v[i] * v[i]
    matvec(J, v, w, plan, order, position)
    matvec(J, w, u, plan, order, position)
    norm_u = 0.0
    for i in range(n):
        norm_u += u[i] * u[i]
    if not (norm_u > 0.0 and math.isfinite(norm_u)):
        for i in range(n):
            v[i] = 0.0
        return 0.0
    scale = 1.0 / math.sqrt(norm_u)
    for i in range(n):
        v[i] = u[i] * scale
    return math.sqrt(math.sqrt(norm_u / norm_v))

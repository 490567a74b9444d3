"""The peers of benchmarks/peers.py: the slider-crank and the N-disc chain in PyDy (Kane +
Cython code generation + odeint) and in CasADi (cvodes).

Every builder returns ``(derive s, generate s, run)`` where ``run()`` integrates over
``0 .. t_end`` from rest and returns ``(end state, RHS evaluations)``. The slider-crank is
the exact one of models/slider_crank.py with the values of benchmarks/obvious.py; the
chain is benchmarks/scaling.py's (values from ``scaling.chain_values``).
"""
from __future__ import annotations

import time

import numpy as np
import sympy as sp

import obvious

SLIDER_NAMES = list(obvious.SLIDER_CRANK)


# ------------------------------------------------------------------------- PyDy
def _pydy_run(kane, q, u, constants, values, t_end, rtol, atol):
    from pydy.codegen.ode_function_generators import generate_ode_function
    from scipy.integrate import odeint
    start = time.perf_counter()
    rhs = generate_ode_function(kane.forcing_full, q, u, constants,
                                mass_matrix=kane.mass_matrix_full, generator="cython")
    generate = time.perf_counter() - start
    p = np.asarray(values, dtype=float)
    y0 = np.zeros(2 * len(q))

    def run():
        states, info = odeint(rhs, y0, [0.0, t_end], args=(p,), rtol=rtol, atol=atol,
                              full_output=True, mxstep=10 ** 6)
        return states[-1], int(info["nfe"][-1])
    return generate, run


def pydy_slider_crank(t_end, rtol, atol):
    """Kane's method of the exact slider-crank (positions as functions of phi)."""
    from sympy.physics.mechanics import KanesMethod, dynamicsymbols
    start = time.perf_counter()
    q, u = dynamicsymbols("phi omega")
    r, L, J_1, m_2, J_2, m_3, M_0, omega_0 = constants = sp.symbols(SLIDER_NAMES)
    N, crank, bodies = obvious.slider_crank_bodies(q, r, L, J_1, m_2, J_2, m_3)
    kane = KanesMethod(N, [q], [u], kd_eqs=[q.diff() - u])
    kane.kanes_equations(bodies, [(crank, M_0 * (1 - u / omega_0) * N.z)])
    kane.mass_matrix_full, kane.forcing_full                       # formed here
    derive = time.perf_counter() - start
    values = [obvious.SLIDER_CRANK[name] for name in SLIDER_NAMES]
    return (derive,) + _pydy_run(kane, [q], [u], list(constants), values, t_end, rtol,
                                 atol)


def pydy_chain(n, values, t_end, rtol, atol):
    """Kane's method of the chain of n discs on a fixed axis."""
    from sympy.physics.mechanics import (KanesMethod, Point, ReferenceFrame, RigidBody,
                                         dynamicsymbols, inertia)
    start = time.perf_counter()
    q = dynamicsymbols(f"phi_1:{n + 1}")
    u = dynamicsymbols(f"omega_1:{n + 1}")
    J, k, c = (sp.symbols(f"J_1:{n + 1}"), sp.symbols(f"k_1:{n}"), sp.symbols(f"c_1:{n}"))
    M, b = sp.symbols("M b")
    N, O = ReferenceFrame("N"), Point("O")
    O.set_vel(N, 0)
    frames = [ReferenceFrame(f"A{i + 1}") for i in range(n)]
    for i, frame in enumerate(frames):
        frame.orient_axis(N, N.z, q[i])
        frame.set_ang_vel(N, u[i] * N.z)
    bodies = [RigidBody(f"disc {i + 1}", O, frames[i], 0,
                        (inertia(frames[i], 0, 0, J[i]), O)) for i in range(n)]
    torque = [sp.S.Zero] * n
    torque[0] += M
    torque[-1] -= b * u[-1]
    for i in range(n - 1):
        moment = k[i] * (q[i + 1] - q[i]) + c[i] * (u[i + 1] - u[i])
        torque[i] += moment
        torque[i + 1] -= moment
    kane = KanesMethod(N, q, u, kd_eqs=[q[i].diff() - u[i] for i in range(n)])
    kane.kanes_equations(bodies, [(frames[i], torque[i] * N.z) for i in range(n)])
    kane.mass_matrix_full, kane.forcing_full
    derive = time.perf_counter() - start
    constants = list(J) + list(k) + list(c) + [M, b]
    p = values["J"] + values["k"] + values["c"] + [values["M"], values["b"]]
    return (derive,) + _pydy_run(kane, q, u, constants, p, t_end, rtol, atol)


def timed(run, repeats):
    """The shortest of ``repeats`` calls of ``run`` (wall time) and the last call's value."""
    best, value = float("inf"), None
    for _ in range(repeats):
        started = time.perf_counter()
        value = run()
        best = min(best, time.perf_counter() - started)
    return best, value


# ----------------------------------------------------------------------- CasADi
def _casadi_run(x, p, ode, values, t_end, rtol, atol):
    import casadi as ca
    start = time.perf_counter()
    integrate = ca.integrator("F", "cvodes", {"x": x, "p": p, "ode": ode}, 0.0, t_end,
                              {"reltol": rtol, "abstol": atol, "max_num_steps": 10 ** 6})
    generate = time.perf_counter() - start
    p_values = np.asarray(values, dtype=float)
    y0 = np.zeros(x.shape[0])

    def run():
        end = np.asarray(integrate(x0=y0, p=p_values)["xf"]).ravel()
        stats = integrate.stats()
        return end, int(stats.get("nfevals", stats.get("nrhs", 0)) or 0)
    return generate, run


def casadi_slider_crank(t_end, rtol, atol):
    """The Lagrangian's reduced inertia I(phi) by casadi's own differentiation:
    I eps + 1/2 I' omega^2 = M."""
    import casadi as ca
    start = time.perf_counter()
    phi, omega, p = ca.SX.sym("phi"), ca.SX.sym("omega"), ca.SX.sym("p", 8)
    r, L, J_1, m_2, J_2, m_3, M_0, omega_0 = (p[i] for i in range(8))
    root = ca.sqrt(L**2 - r**2 * ca.sin(phi)**2)
    places = ca.vertcat(r * ca.cos(phi) + root,                    # slider x
                        r * ca.cos(phi) + root / 2, r * ca.sin(phi) / 2,   # rod centre
                        -ca.asin(r * ca.sin(phi) / L))             # rod angle
    d = ca.jacobian(places, phi)
    inertia_ = J_1 + m_3 * d[0]**2 + m_2 * (d[1]**2 + d[2]**2) + J_2 * d[3]**2
    slope = ca.jacobian(inertia_, phi)
    eps = (M_0 * (1 - omega / omega_0) - slope * omega**2 / 2) / inertia_
    x, ode = ca.vertcat(phi, omega), ca.vertcat(omega, eps)
    derive = time.perf_counter() - start
    values = [obvious.SLIDER_CRANK[name] for name in SLIDER_NAMES]
    return (derive,) + _casadi_run(x, p, ode, values, t_end, rtol, atol)


def casadi_chain(n, values, t_end, rtol, atol):
    """The chain's equations written by hand: J_i phi_i'' = the moments on disc i."""
    import casadi as ca
    start = time.perf_counter()
    q, u = ca.SX.sym("q", n), ca.SX.sym("u", n)
    p = ca.SX.sym("p", 3 * n)                              # J, k, c, M, b
    J, k, c = p[:n], p[n:2 * n - 1], p[2 * n - 1:3 * n - 2]
    M, b = p[3 * n - 2], p[3 * n - 1]
    moments = [0] * n
    for i in range(n - 1):
        moment = k[i] * (q[i + 1] - q[i]) + c[i] * (u[i + 1] - u[i])
        moments[i] += moment
        moments[i + 1] -= moment
    moments[0] += M
    moments[-1] -= b * u[n - 1]
    acc = ca.vertcat(*[moments[i] / J[i] for i in range(n)])
    x, ode = ca.vertcat(q, u), ca.vertcat(u, acc)
    derive = time.perf_counter() - start
    p_values = values["J"] + values["k"] + values["c"] + [values["M"], values["b"]]
    return (derive,) + _casadi_run(x, p, ode, p_values, t_end, rtol, atol)

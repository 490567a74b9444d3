"""The obvious path: sympy.physics.mechanics.LagrangesMethod + lambdify + solve_ivp.

What a user without mechdyn writes for the benchmark machines (the exact slider-crank
of models/slider_crank.py, the three-mass drive of benchmarks/elastic_drive.py and the
shoe brake of models/shoe_brake.py, same parameters): frames, points and bodies,
Lagrange's equations, ``lambdify`` of the full mass matrix and forcing,
``np.linalg.solve`` in the right-hand side, ``solve_ivp`` (the brake: its friction
moment ``-M sign(omega)`` and a terminal event at zero speed). Also the hand-written
Python right-hand sides the compiled ones are compared with.

    python benchmarks/obvious.py slider_crank|elastic_drive|shoe_brake [--rtol 1e-6]

runs one whole simulation (the whole-process benchmark times this command).
"""
from __future__ import annotations

import argparse
import math

import numpy as np
import sympy as sp
from scipy.integrate import solve_ivp
from sympy.physics.mechanics import (LagrangesMethod, Lagrangian, Particle, Point,
                                     ReferenceFrame, RigidBody, dynamicsymbols, inertia)

SLIDER_CRANK = {"r": 0.1, "L": 0.4, "J_1": 0.01, "m_2": 0.5, "J_2": 0.5 * 0.4**2 / 12,
                "m_3": 1.0, "M_0": 5.0, "omega_0": 100.0}
ELASTIC_DRIVE = {"J_1": 0.05, "J_2": 0.02, "J_3": 0.5, "k_1": 2000.0, "k_2": 5000.0,
                 "c_1": 1.0, "c_2": 1.0, "M_0": 40.0, "omega_0": 150.0, "M_L": 10.0}
SHOE_BRAKE = {"I": 0.4, "f": 0.2, "P": 20.0, "R": 0.1, "omega_0": 100.0}
T_END = {"slider_crank": 5.0, "elastic_drive": 0.5, "shoe_brake": 60.0}
STATES = {"slider_crank": 2, "elastic_drive": 6, "shoe_brake": 2}


def slider_crank_bodies(q, r, L, J_1, m_2, J_2, m_3):
    """The exact slider-crank in sympy.physics.mechanics: ``(N, crank frame, bodies)``."""
    N = ReferenceFrame("N")
    crank, rod = ReferenceFrame("A"), ReferenceFrame("B")
    crank.orient_axis(N, N.z, q)
    rod.orient_axis(N, N.z, -sp.asin(r * sp.sin(q) / L))
    O = Point("O")
    O.set_vel(N, 0)
    pin = O.locatenew("P", r * crank.x)
    slider = O.locatenew("C", (r * sp.cos(q) + sp.sqrt(L**2 - r**2 * sp.sin(q)**2)) * N.x)
    middle = O.locatenew("G", (pin.pos_from(O) + slider.pos_from(O)) / 2)
    for point in (pin, slider, middle):
        point.set_vel(N, point.pos_from(O).dt(N))
    bodies = [RigidBody("crank", O, crank, 0, (inertia(crank, 0, 0, J_1), O)),
              RigidBody("rod", middle, rod, m_2, (inertia(rod, 0, 0, J_2), middle)),
              Particle("slider", slider, m_3)]
    return N, crank, bodies


def slider_crank_equations():
    """LagrangesMethod of the exact slider-crank: (method, q, parameter symbols)."""
    q = dynamicsymbols("phi")
    r, L, J_1, m_2, J_2, m_3, M_0, omega_0 = sp.symbols(list(SLIDER_CRANK))
    N, crank, bodies = slider_crank_bodies(q, r, L, J_1, m_2, J_2, m_3)
    moment = M_0 * (1 - q.diff() / omega_0)
    method = LagrangesMethod(Lagrangian(N, *bodies), [q], forcelist=[(crank, moment * N.z)],
                             frame=N)
    method.form_lagranges_equations()
    return method, [q], [r, L, J_1, m_2, J_2, m_3, M_0, omega_0]


def elastic_drive_equations():
    """LagrangesMethod of the three-mass drive: (method, q, parameter symbols)."""
    q = dynamicsymbols("phi_1 phi_2 phi_3")
    J_1, J_2, J_3, k_1, k_2, c_1, c_2, M_0, omega_0, M_L = sp.symbols(list(ELASTIC_DRIVE))
    N = ReferenceFrame("N")
    O = Point("O")
    O.set_vel(N, 0)
    frames = [ReferenceFrame(f"A{i}") for i in range(3)]
    for frame, angle in zip(frames, q):
        frame.orient_axis(N, N.z, angle)
    bodies = [RigidBody(f"body{i}", O, frame, 0, (inertia(frame, 0, 0, J), O))
              for i, (frame, J) in enumerate(zip(frames, (J_1, J_2, J_3)))]
    u = [qi.diff() for qi in q]
    V = k_1 * (q[0] - q[1])**2 / 2 + k_2 * (q[1] - q[2])**2 / 2
    dampers_1, dampers_2 = c_1 * (u[0] - u[1]), c_2 * (u[1] - u[2])
    forces = [(frames[0], (M_0 * (1 - u[0] / omega_0) - dampers_1) * N.z),
              (frames[1], (dampers_1 - dampers_2) * N.z),
              (frames[2], (dampers_2 - M_L) * N.z)]
    method = LagrangesMethod(Lagrangian(N, *bodies) - V, q, forcelist=forces, frame=N)
    method.form_lagranges_equations()
    return method, q, [J_1, J_2, J_3, k_1, k_2, c_1, c_2, M_0, omega_0, M_L]


def shoe_brake_equations():
    """LagrangesMethod of the braked disc: (method, q, parameter symbols)."""
    q = dynamicsymbols("phi")
    I, f, P, R = sp.symbols("I f P R")
    N = ReferenceFrame("N")
    disc = ReferenceFrame("A")
    disc.orient_axis(N, N.z, q)
    O = Point("O")
    O.set_vel(N, 0)
    body = RigidBody("disc", O, disc, 0, (inertia(disc, 0, 0, I), O))
    friction = -f * 2 * P * R * sp.sign(q.diff())
    method = LagrangesMethod(Lagrangian(N, body), [q], forcelist=[(disc, friction * N.z)],
                             frame=N)
    method.form_lagranges_equations()
    return method, [q], [I, f, P, R]


def rhs_of(method, q, parameters, values):
    """solve_ivp right-hand side: lambdify full mass matrix and forcing, solve."""
    states = list(q) + [qi.diff() for qi in q]
    mass = sp.lambdify([states, parameters], method.mass_matrix_full)
    forcing = sp.lambdify([states, parameters], method.forcing_full)
    p = [values[str(s)] for s in parameters]

    def rhs(t, y):
        return np.linalg.solve(mass(y, p), forcing(y, p)).ravel()
    return rhs


def obvious_rhs(name):
    if name == "slider_crank":
        return rhs_of(*slider_crank_equations(), SLIDER_CRANK)
    if name == "shoe_brake":
        return rhs_of(*shoe_brake_equations(), SHOE_BRAKE)
    return rhs_of(*elastic_drive_equations(), ELASTIC_DRIVE)


def _stopped(t, y):
    return y[1]


_stopped.terminal, _stopped.direction = True, -1


def simulate(rhs, name, rtol, method="RK45"):
    """solve_ivp from the scene's start with dense output (atol = rtol / 100, as the
    scenes); the brake stops at zero speed."""
    y0 = np.zeros(STATES[name])
    events = None
    if name == "shoe_brake":
        y0[1], events = SHOE_BRAKE["omega_0"], _stopped
    return solve_ivp(rhs, (0.0, T_END[name]), y0, method=method, rtol=rtol,
                     atol=rtol / 100, dense_output=True, events=events)


# ------------------------------------------------------ hand-written right-hand sides
def slider_crank_by_hand(t, y, r=0.1, L=0.4, J_1=0.01, m_2=0.5, J_2=0.5 * 0.4**2 / 12,
                         m_3=1.0, M_0=5.0, omega_0=100.0):
    """I(phi) eps + 1/2 I'(phi) omega^2 = M, kinematics differentiated by hand."""
    phi, omega = y
    s, c = math.sin(phi), math.cos(phi)
    lam = r / L
    root = math.sqrt(1 - lam * lam * s * s)
    root_1 = -lam * lam * s * c / root
    root_2 = -lam * lam * ((c * c - s * s) * root * root + lam * lam * s * s * c * c) / root**3
    x3_1, x3_2 = -r * s + L * root_1, -r * c + L * root_2          # slider
    xg_1, xg_2 = -r * s + L * root_1 / 2, -r * c + L * root_2 / 2  # rod's centre
    yg_1, yg_2 = r * c / 2, -r * s / 2
    b_1 = lam * c / root                                           # rod angle
    b_2 = (-lam * s * root - lam * c * root_1) / (root * root)
    inertia_ = J_1 + m_3 * x3_1 * x3_1 + m_2 * (xg_1 * xg_1 + yg_1 * yg_1) + J_2 * b_1 * b_1
    half_slope = m_3 * x3_1 * x3_2 + m_2 * (xg_1 * xg_2 + yg_1 * yg_2) + J_2 * b_1 * b_2
    moment = M_0 * (1 - omega / omega_0)
    return [omega, (moment - half_slope * omega * omega) / inertia_]


def elastic_drive_by_hand(t, y, J_1=0.05, J_2=0.02, J_3=0.5, k_1=2000.0, k_2=5000.0,
                          c_1=1.0, c_2=1.0, M_0=40.0, omega_0=150.0, M_L=10.0):
    p1, p2, p3, u1, u2, u3 = y
    s1 = k_1 * (p1 - p2) + c_1 * (u1 - u2)
    s2 = k_2 * (p2 - p3) + c_2 * (u2 - u3)
    return [u1, u2, u3, (M_0 * (1 - u1 / omega_0) - s1) / J_1, (s1 - s2) / J_2,
            (s2 - M_L) / J_3]


def shoe_brake_exact(times, I=0.4, f=0.2, P=20.0, R=0.1, omega_0=100.0):
    """The braked disc in closed form: constant deceleration 2 f P R / I to rest."""
    decel = 2 * f * P * R / I
    t = np.minimum(times, omega_0 / decel)
    return np.array([omega_0 * t - decel * t**2 / 2, omega_0 - decel * t])


def main(argv=None):
    parser = argparse.ArgumentParser(description="one run of the obvious path")
    parser.add_argument("name", choices=sorted(T_END))
    parser.add_argument("--rtol", type=float, default=1e-6)
    parser.add_argument("--method", default="RK45")
    args = parser.parse_args(argv)
    solution = simulate(obvious_rhs(args.name), args.name, args.rtol, args.method)
    print(f"{args.name}: t = {solution.t[-1]}, y = {solution.y[:, -1]}, "
          f"nfev = {solution.nfev}")


if __name__ == "__main__":
    main()

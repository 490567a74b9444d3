"""Size scaling of large models (issue 26): a chain of N discs, mechdyn against a numba
floor and sympy's LagrangesMethod + lambdify.

    python benchmarks/scaling.py [--sizes 5 20 50 100 200] [--peer-sizes 5 20 50]

The chain: N discs J_i on shafts k_i with dampers c_i between neighbours, a drive moment
M on the first disc and a load -b phidot_N on the last; 0-1 s at rtol 1e-8, atol 1e-10,
from rest. Every size runs in a fresh process with an empty mechdyn cache
(``MECHDYN_CACHE`` a new temporary folder; numba's cache of the integration kernel, made
once per installation, is loaded before timing). Columns (wall time):

* derive: ``mech.equations(scene)``; generate: ``mech.compile(scene)`` (code
  generation and the Python form of the functions);
* first run: the first ``mech.simulate(scene, backend="compiled")`` after them (numba
  compiles the generated functions, then the run); "CPU" is the process time of the
  three (on a shared machine wall time also counts other processes' turns);
* warm run: the same run again, whole (best of 5), and its cost per right-hand side
  evaluation; "run x floor" is that against the floor per RHS (the issue's acceptance:
  within 5x at N = 100);
* kernel / RHS: the compiled kernel alone (``mechdyn.kernels.Integration``, DOP853, the
  same tolerances) stepping the generated functions, per RHS evaluation;
* floor / RHS: the same kernel stepping the chain's accelerations written by hand in
  numba (a loop over the shafts; the chain's mass matrix is diagonal, so a division is
  its whole solve), per RHS evaluation; "x floor" is kernel / floor;
* RHS alone: one call of the generated ``rhs`` (and of the hand-written one) from a
  compiled loop, without the integrator;
* the end state's largest difference between mechdyn's run and the floor's run.

A constant mass matrix (``--constant-sizes``): the same discs in relative angles (disc i
turns by ``b_0 + .. + b_i``: a dense ``M`` of the inertias alone, ``n^3/6`` to factor),
generated twice in one process: as mechdyn does (``M`` factored once per parameter
vector, appended to ``p``) and with the factorisation left in ``rhs`` (the code before);
one ``rhs`` call from a compiled loop (compiled backend) and from Python (the scipy
backend), and the largest difference of their results. (N = 100 is not in the default:
deriving the relative-angle chain takes minutes, a derivation cost, not the solve's.)

Sparse Jacobian (``--sparse-sizes``): Radau on ``backend="scipy"`` over the chain (a
diagonal mass matrix), warm runs of one compiled scene: the generated Jacobian handed to
scipy as a sparse CSC matrix of its structural non-zeros (a sparse LU) against the dense
array (the code before).

Peers (``--peer-sizes``): sympy's LagrangesMethod (derivation, ``mass_matrix_full`` and
``forcing_full``), lambdify with numpy, scipy's DOP853 solving ``M y' = f`` with
``numpy.linalg.solve`` per call. PyDy and CasADi (neither a dependency) are not timed
by this script; the table says whether they are installed.
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
RTOL, ATOL, T_END = 1e-8, 1e-10, 1.0


def chain(n):
    """The chain in mechdyn, its scene and its parameter values."""
    import sympy as sp
    import mechdyn as md
    J = sp.symbols(f"J_1:{n + 1}", positive=True)
    k = sp.symbols(f"k_1:{n}", positive=True)
    c = sp.symbols(f"c_1:{n}", positive=True)
    M, b = sp.symbols("M b", positive=True)
    phi = md.coordinates(" ".join(f"phi_{i + 1}" for i in range(n)))
    mech = md.Mechanism(f"chain of {n}", phi)
    for i in range(n):
        mech.link(f"disc {i + 1}", J=J[i], angle=phi[i])
    for i in range(n - 1):
        mech.spring(f"shaft {i + 1}", k[i], stretch=phi[i + 1] - phi[i])
        mech.damper(f"damping {i + 1}", c[i], stretch=phi[i + 1] - phi[i])
    mech.load("drive", M, along=phi[0])
    mech.load("brake", -b * md.speed(phi[-1]), along=phi[-1])
    scene = md.Scene("run", initial={**{q: 0 for q in phi}, **{md.speed(q): 0 for q in phi}},
                     t_end=T_END, rtol=RTOL, atol=ATOL)
    values = chain_values(n)
    params = {**dict(zip(J, values["J"])), **dict(zip(k, values["k"])),
              **dict(zip(c, values["c"])), M: values["M"], b: values["b"]}
    return mech, scene, params, phi


def chain_values(n):
    """The chain's values; with ``MECHDYN_BENCH_STIFF=1`` in the environment (``peers.py
    --stiff``, inherited by its fresh processes) issue 39's stiff chain: shafts of 1e6
    N m/rad with 5 N m s/rad dampers, J_i = 0.01 (1 + i mod 3), M = 5, b = 0.02."""
    if os.environ.get("MECHDYN_BENCH_STIFF") == "1":
        return {"J": [0.01 * (1 + i % 3) for i in range(n)], "k": [1e6] * (n - 1),
                "c": [5.0] * (n - 1), "M": 5.0, "b": 0.02}
    return {"J": [1.0 + 0.01 * i for i in range(n)], "k": [1000.0] * (n - 1),
            "c": [1.0] * (n - 1), "M": 10.0, "b": 2.0}


def floor_functions():
    """The chain's accelerations written by hand in numba: p = [J..., k..., c..., M, b]."""
    from numba import njit
    from mechdyn.kernels import RHS_SIGNATURE, model_functions

    @njit(RHS_SIGNATURE, error_model="numpy")
    def chain_rhs(t, y, p, out):
        n = y.shape[0] // 2
        for i in range(n):
            out[i] = y[n + i]
            out[n + i] = 0.0
        for i in range(n - 1):
            moment = p[n + i] * (y[i + 1] - y[i]) + p[2 * n - 1 + i] * (y[n + i + 1] - y[n + i])
            out[n + i] += moment
            out[n + i + 1] -= moment
        out[n] += p[3 * n - 2]
        out[2 * n - 1] -= p[3 * n - 1] * y[2 * n - 1]
        for i in range(n):
            out[n + i] /= p[i]
    return model_functions(chain_rhs)


def rhs_alone(functions, p, n, calls=20000, repeats=5):
    """Best time of one call of the model's rhs, called from compiled code."""
    import numpy as np
    from numba import njit
    from mechdyn.kernels.functions import as_rhs

    @njit
    def call_many(addresses, p, y, out, calls):
        rhs = as_rhs(addresses[0], addresses[1])
        for _ in range(calls):
            rhs(0.0, y, p, out)
    y, out = np.linspace(0.0, 1.0, 2 * n), np.zeros(2 * n)
    p = np.asarray(p, dtype=float)
    best = None
    for _ in range(repeats):
        start = time.perf_counter()
        call_many(functions.addresses, p, y, out, calls)
        elapsed = (time.perf_counter() - start) / calls
        best = elapsed if best is None else min(best, elapsed)
    return best


def kernel_run(functions, p, n, repeats=10):
    """Best wall time of a kernel run over 0-1 s, its RHS count and end state."""
    import numpy as np
    from mechdyn.kernels import CHUNK_FULL, DOP853, Integration
    best = None
    for _ in range(repeats):
        run = Integration(functions, np.asarray(p, dtype=float), 0.0, np.zeros(2 * n),
                          method=DOP853, rtol=RTOL, atol=ATOL, detect_switch=False)
        start = time.perf_counter()
        while run.advance(T_END, 2000).status == CHUNK_FULL:
            pass
        elapsed = time.perf_counter() - start
        best = elapsed if best is None else min(best, elapsed)
    return best, int(run.stats["nfev"]), run.y.copy()


def measure_mechdyn(n):
    """One size, in this (fresh) process."""
    import numpy as np
    import mechdyn.kernels  # noqa: F401  (the kernel's own numba cache, not timed)
    from mechdyn.compile.numba_model import numba_functions
    from mechdyn.derive.selection import select
    mech, scene, params, phi = chain(n)
    row = {"n": n}
    cpu = time.process_time()
    start = time.perf_counter()
    mech.equations(scene)
    row["derive"] = time.perf_counter() - start
    start = time.perf_counter()
    compiled = mech.compile(scene)
    row["generate"] = time.perf_counter() - start
    start = time.perf_counter()
    mech.simulate(scene, params, backend="compiled")
    row["first"] = time.perf_counter() - start
    row["cpu"] = time.process_time() - cpu
    row["warm"] = None
    for _ in range(5):                              # the best of 5 (a shared machine)
        start = time.perf_counter()
        result = mech.simulate(scene, params, backend="compiled")
        elapsed = time.perf_counter() - start
        row["warm"] = elapsed if row["warm"] is None else min(row["warm"], elapsed)
    row["warm_per_rhs"] = row["warm"] / result.stats["nfev"]
    p = compiled.parameter_vector(params)
    elapsed, nfev, end = kernel_run(numba_functions(compiled), p, n)
    row["kernel_per_rhs"] = elapsed / nfev
    values = chain_values(n)
    floor_p = values["J"] + values["k"] + values["c"] + [values["M"], values["b"]]
    elapsed, floor_nfev, floor_end = kernel_run(floor_functions(), floor_p, n)
    row["floor_per_rhs"] = elapsed / floor_nfev
    row["rhs_alone"] = rhs_alone(numba_functions(compiled), p, n)
    row["floor_alone"] = rhs_alone(floor_functions(), floor_p, n)
    row["nfev"] = nfev
    row["difference"] = float(np.max(np.abs(end - floor_end)))
    return row


def measure_lagranges_method(n):
    """LagrangesMethod + lambdify + scipy for the same chain, in this process."""
    import numpy as np
    import sympy as sp
    from scipy.integrate import solve_ivp
    from sympy.physics.mechanics import LagrangesMethod, ReferenceFrame, dynamicsymbols
    values = chain_values(n)
    q = dynamicsymbols(f"phi_1:{n + 1}")
    qd = [qi.diff(dynamicsymbols._t) for qi in q]
    J = sp.symbols(f"J_1:{n + 1}")
    k = sp.symbols(f"k_1:{n}")
    c = sp.symbols(f"c_1:{n}")
    M, b = sp.symbols("M b")
    frame = ReferenceFrame("N")
    frames = [frame.orientnew(f"A{i + 1}", "Axis", [q[i], frame.z]) for i in range(n)]
    T = sum(J[i] * qd[i] ** 2 / 2 for i in range(n))
    V = sum(k[i] * (q[i + 1] - q[i]) ** 2 / 2 for i in range(n - 1))
    torque = [sp.S.Zero] * n
    torque[0] += M
    torque[-1] -= b * qd[-1]
    for i in range(n - 1):
        damping = c[i] * (qd[i + 1] - qd[i])
        torque[i] += damping
        torque[i + 1] -= damping
    row = {"n": n}
    start = time.perf_counter()
    method = LagrangesMethod(T - V, q, forcelist=[(frames[i], torque[i] * frame.z)
                                                  for i in range(n)], frame=frame)
    method.form_lagranges_equations()
    mass, forcing = method.mass_matrix_full, method.forcing_full
    row["derive"] = time.perf_counter() - start
    start = time.perf_counter()
    states = list(q) + list(qd)
    plain = sp.symbols(f"x0:{2 * n}")
    swap = dict(zip(qd, plain[n:])) | dict(zip(q, plain[:n]))
    args = [plain, list(J) + list(k) + list(c) + [M, b]]
    mass_f = sp.lambdify(args, mass.xreplace(swap), "numpy")
    forcing_f = sp.lambdify(args, forcing.xreplace(swap), "numpy")
    row["generate"] = time.perf_counter() - start
    p = values["J"] + values["k"] + values["c"] + [values["M"], values["b"]]

    def rhs(t, y):
        return np.linalg.solve(mass_f(y, p), forcing_f(y, p)).ravel()
    start = time.perf_counter()
    result = solve_ivp(rhs, (0, T_END), np.zeros(len(states)), method="DOP853",
                       rtol=RTOL, atol=ATOL)
    row["first"] = time.perf_counter() - start
    start = time.perf_counter()
    result = solve_ivp(rhs, (0, T_END), np.zeros(len(states)), method="DOP853",
                       rtol=RTOL, atol=ATOL)
    row["warm"] = time.perf_counter() - start
    row["warm_per_rhs"] = row["warm"] / result.nfev
    return row


def relative_chain(n):
    """The chain in relative angles: a dense constant mass matrix."""
    import sympy as sp
    import mechdyn as md
    twists = md.coordinates(" ".join(f"b{i}" for i in range(n)))
    mech = md.Mechanism("relative chain", twists)
    inertias, stiffness = sp.symbols(f"J0:{n}", positive=True), sp.symbols(f"k1:{n}", positive=True)
    for i in range(n):
        mech.link(f"disc {i}", J=inertias[i], angle=sum(twists[:i + 1]))
        if i:
            mech.spring(f"shaft {i}", stiffness[i - 1], stretch=twists[i])
    mech.load("drive", 3, along=twists[0])
    scene = md.Scene("run", initial={**{b: 0 for b in twists}, **{md.speed(b): 0 for b in twists}},
                     t_end=T_END, rtol=RTOL, atol=ATOL)
    params = {f"J{i}": 1.0 + 0.01 * i for i in range(n)} | {f"k{i}": 1e3 for i in range(1, n)}
    return mech, scene, params


def measure_constant(n):
    """rhs with a constant M factored once per parameter vector against factored per call."""
    import numpy as np
    import mechdyn.compile.generate as generation
    from mechdyn.compile.generated import CompiledScene
    from mechdyn.compile.numba_model import numba_functions
    from mechdyn.derive.selection import select
    mech, scene, params = relative_chain(n)
    eqs = mech.equations(scene)
    row, results, hoisting = {"n": n}, {}, generation.is_constant
    for name in ("once", "per_call"):
        if name == "per_call":
            generation.is_constant = lambda mass: False     # the generator before the hoist
        meta, source = generation.generate(eqs, select(mech, scene))
        generation.is_constant = hoisting
        compiled = CompiledScene(meta, source, f"constant-mass-{name}-{n}")
        p = compiled.parameter_vector(params)
        row[f"{name}_compiled"] = rhs_alone(numba_functions(compiled), p, n, calls=2000)
        y = np.linspace(0.0, 1.0, 2 * n).tolist()
        compiled.rhs(0.0, y, p)
        start, calls = time.perf_counter(), 200
        for _ in range(calls):
            results[name] = compiled.rhs(0.0, y, p)
        row[f"{name}_python"] = (time.perf_counter() - start) / calls
    row["difference"] = float(np.max(np.abs(np.subtract(results["once"], results["per_call"]))))
    return row


def measure_sparse(n):
    """Radau on scipy over the chain: the Jacobian as a sparse matrix (sparse LU) against
    the dense one (the code before), the same compiled scene, warm runs."""
    import numpy as np
    import mechdyn as md
    mech, scene, params, phi = chain(n)
    scene = md.Scene("radau", initial=scene.initial, t_end=T_END, rtol=RTOL, atol=ATOL,
                     method="Radau", backend="scipy")
    compiled = mech.compile(scene)
    pattern, row, ends = compiled.meta["jac_sparsity"], {"n": n}, {}
    for name in ("sparse", "dense"):
        if name == "dense":
            del compiled.meta["jac_sparsity"]
        mech.simulate(scene, params)
        start = time.perf_counter()
        result = mech.simulate(scene, params)
        row[name] = time.perf_counter() - start
        row[f"{name}_nlu"] = result.stats["nlu"]
        ends[name] = np.array([result.final(q) for q in phi])
    compiled.meta["jac_sparsity"] = pattern
    row["difference"] = float(np.max(np.abs(ends["sparse"] - ends["dense"])))
    return row


def in_fresh_process(kind, n):
    env = dict(os.environ, MECHDYN_CACHE=tempfile.mkdtemp(prefix="mechdyn-scaling-"),
               PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    done = subprocess.run([sys.executable, __file__, "--one", kind, str(n)], env=env,
                          capture_output=True, text=True)
    if done.returncode:
        raise SystemExit(f"{kind} at N = {n} failed:\n{done.stderr}")
    return json.loads(done.stdout.strip().splitlines()[-1])


def installed(name):
    import importlib.util
    return importlib.util.find_spec(name) is not None


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--sizes", type=int, nargs="*", default=[5, 20, 50, 100, 200])
    parser.add_argument("--peer-sizes", type=int, nargs="*", default=[5, 20, 50])
    parser.add_argument("--constant-sizes", type=int, nargs="*", default=[20, 50])
    parser.add_argument("--sparse-sizes", type=int, nargs="*", default=[100])
    parser.add_argument("--one", nargs=2, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.one:
        kind, n = args.one[0], int(args.one[1])
        measure = {"mechdyn": measure_mechdyn, "constant": measure_constant,
                   "sparse": measure_sparse,
                   "lagranges": measure_lagranges_method}[kind]
        print(json.dumps(measure(n)))
        return
    print(f"chain of N discs, 0-{T_END:g} s, rtol {RTOL:g}; wall times, fresh process and "
          "empty cache per size\n")
    print("| N | derive s | generate s | first run s | d+g+first s | (CPU s) | warm run s | "
          "warm µs/RHS | run x floor | kernel µs/RHS | floor µs/RHS | x floor | RHS alone µs "
          "(floor) | RHS | end vs floor |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for n in args.sizes:
        r = in_fresh_process("mechdyn", n)
        total = r["derive"] + r["generate"] + r["first"]
        print(f"| {n} | {r['derive']:.2f} | {r['generate']:.2f} | {r['first']:.2f} | "
              f"{total:.2f} | {r['cpu']:.2f} | {r['warm']:.4f} | {r['warm_per_rhs'] * 1e6:.1f} | "
              f"{r['warm_per_rhs'] / r['floor_per_rhs']:.1f} | "
              f"{r['kernel_per_rhs'] * 1e6:.2f} | {r['floor_per_rhs'] * 1e6:.2f} | "
              f"{r['kernel_per_rhs'] / r['floor_per_rhs']:.1f} | "
              f"{r['rhs_alone'] * 1e6:.3f} ({r['floor_alone'] * 1e6:.3f}) | {r['nfev']} | "
              f"{r['difference']:.1e} |", flush=True)
    if args.constant_sizes:
        print("\nconstant mass matrix (relative angles, dense M): one rhs call, µs, M factored "
              "once per parameter vector vs at every call\n")
        print("| N | compiled: once | compiled: per call | speed-up | Python (scipy backend): "
              "once | Python: per call | speed-up | difference |")
        print("|---|---|---|---|---|---|---|---|")
        for n in args.constant_sizes:
            r = in_fresh_process("constant", n)
            print(f"| {n} | {r['once_compiled'] * 1e6:.2f} | {r['per_call_compiled'] * 1e6:.2f} | "
                  f"{r['per_call_compiled'] / r['once_compiled']:.1f}x | "
                  f"{r['once_python'] * 1e6:.0f} | {r['per_call_python'] * 1e6:.0f} | "
                  f"{r['per_call_python'] / r['once_python']:.1f}x | {r['difference']:.1e} |",
                  flush=True)
    if args.sparse_sizes:
        print("\nRadau on backend='scipy' (warm run, s): the Jacobian sparse (sparse LU) "
              "against dense\n")
        print("| N | sparse | dense | speed-up | LU factorisations | end difference |")
        print("|---|---|---|---|---|---|")
        for n in args.sparse_sizes:
            r = in_fresh_process("sparse", n)
            print(f"| {n} | {r['sparse']:.2f} | {r['dense']:.2f} | {r['dense'] / r['sparse']:.1f}x "
                  f"| {r['sparse_nlu']} / {r['dense_nlu']} | {r['difference']:.1e} |", flush=True)
    if args.peer_sizes:
        print("\npeers (same chain; first run = lambdify excluded, integration only)\n")
        print("| N | peer | derive s | generate s | first run s | warm µs/RHS |")
        print("|---|---|---|---|---|---|")
        for n in args.peer_sizes:
            r = in_fresh_process("lagranges", n)
            print(f"| {n} | LagrangesMethod + lambdify + scipy | {r['derive']:.2f} | "
                  f"{r['generate']:.2f} | {r['first']:.2f} | {r['warm_per_rhs'] * 1e6:.1f} |",
                  flush=True)
        for peer in ("pydy", "casadi"):
            state = "installed, not timed here" if installed(peer) else "not installed"
            print(f"| - | {peer} | {state} | | | |")


if __name__ == "__main__":
    main()

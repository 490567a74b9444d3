"""mechdyn at its defaults beside its peers, in one run, with the machine's default BLAS
threading: the slider-crank (issue 24) and the N-disc chain (issue 26).

    python benchmarks/peers.py [--repeats 3] [--rtol 1e-8] [--chain 100] [--skip-slider]
                               [--chain-peers mechdyn lagranges pydy casadi] [--stiff]

Peers: sympy's LagrangesMethod + lambdify + scipy (benchmarks/obvious.py for the
slider-crank, ``scaling.measure_lagranges_method`` for the chain), PyDy (Kane + Cython
code generation + odeint) and CasADi (cvodes; the slider-crank's reduced inertia by
casadi's own differentiation of the same kinematics, the chain's equations by hand),
see benchmarks/peer_models.py. A peer that is not installed prints a "not installed"
row (``pip install ".[bench]"``).

1. The exact slider-crank of models/slider_crank.py, from rest, 0-5 s, rtol 1e-8, atol
   rtol / 100, all in this process. mechdyn's first run is its first ``simulate`` call
   in the process (derivation and compilation, or their disk cache, included); warm =
   minimum over the repeats. The floor: a numba RK4 loop (benchmarks/kernels.py
   ``rk4_floor``) with the scene's own compiled RHS, doing as many RHS evaluations as
   mechdyn's warm run. Every end angle is compared with mechdyn's at rtol 1e-12.
2. The chain of N discs of benchmarks/scaling.py (0-1 s, rtol 1e-8, atol 1e-10), each
   peer in a fresh process (mechdyn with an empty cache): derive (with code generation),
   first run, warm run, µs per RHS evaluation (warm run / evaluations, solver
   included), and the end state's largest difference from the numba floor's run
   (``scaling.floor_functions``: the accelerations written by hand, DOP853 kernel).
   ``--stiff``: the same chain on issue 39's stiff shafts (k = 1e6 N m/rad, c = 5 N m
   s/rad, J_i = 0.01 (1 + i mod 3), M = 5, b = 0.02); each peer at its defaults.
"""
from __future__ import annotations

import argparse
import importlib.util
import json
import os
import subprocess
import sys
import tempfile
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path[:0] = [str(ROOT), str(HERE)]

import mechdyn as md  # noqa: E402
import obvious  # noqa: E402
import peer_models  # noqa: E402
from peer_models import timed  # noqa: E402
import scaling  # noqa: E402
from kernels import rk4_floor  # noqa: E402

T_END = 5.0
PEERS = {"PyDy Kane + Cython + odeint": "pydy", "CasADi + cvodes": "casadi"}
CHAIN_KINDS = ("mechdyn", "lagranges", "pydy", "casadi")
CAP_SECONDS = 600            # a chain peer's process (derive, first run, warm runs), at most


def row(name, setup, first, warm, nfev, end):
    return {"name": name, "setup": setup, "first": first, "warm": warm, "nfev": nfev,
            "end": end}


# ---------------------------------------------------------------- 1. slider-crank
def mechdyn_rows(rtol, repeats):
    started = time.perf_counter()
    model = md.load_model(ROOT / "models" / "slider_crank.py")
    scene = replace(model.scenes["startup"], t_end=T_END, rtol=rtol, atol=rtol / 100)
    mech = model.mechanism
    first = mech.simulate(scene, model.params)
    first_time = time.perf_counter() - started
    warm, res = timed(lambda: mech.simulate(scene, model.params), repeats)
    rows = [row(f"mechdyn default ({'+'.join(res.stats['backends'])}, "
                f"{res.stats['method']}; first run: {'+'.join(first.stats['backends'])})",
                None, first_time, warm, res.stats["nfev"], res.y[:, -1])]
    scipy_scene = replace(scene, backend="scipy")
    first_time, _ = timed(lambda: mech.simulate(scipy_scene, model.params), 1)
    warm_scipy, res_scipy = timed(lambda: mech.simulate(scipy_scene, model.params), repeats)
    rows.append(row(f"mechdyn backend='scipy' ({res_scipy.stats['method']})", None,
                    first_time, warm_scipy, res_scipy.stats["nfev"], res_scipy.y[:, -1]))
    rows.append(floor_row(mech, scene, model.params, res, repeats))
    exact = mech.simulate(replace(scene, rtol=1e-12, atol=1e-14), model.params).y[:, -1]
    return rows, exact


def floor_row(mech, scene, params, res, repeats):
    """The numba RK4 floor with as many RHS evaluations as the warm run ``res``."""
    from mechdyn.compile.numba_model import numba_functions
    compiled = mech.compile(scene)
    functions = numba_functions(compiled)
    p = np.asarray(compiled.parameter_vector(params), dtype=float)
    y0 = np.ascontiguousarray(res.y[:, 0], dtype=float)
    steps = max(1, res.stats["nfev"] // 4)
    floor = rk4_floor(functions.rhs)
    floor(y0, p, res.t_end, 1)                                      # numba compiles
    seconds, end = timed(lambda: floor(y0, p, res.t_end, steps), max(repeats, 3))
    return row("numba RK4 floor, the same RHS, as many evaluations", None, None, seconds,
               4 * steps, None)


def lambdify_rows(rtol, repeats):
    started = time.perf_counter()
    rhs = obvious.obvious_rhs("slider_crank")
    setup = time.perf_counter() - started
    rows = []
    for method in ("LSODA", "RK45"):
        first, _ = timed(lambda: obvious.simulate(rhs, "slider_crank", rtol, method), 1)
        seconds, sol = timed(lambda: obvious.simulate(rhs, "slider_crank", rtol, method),
                             repeats)
        rows.append(row(f"sympy LagrangesMethod + lambdify + solve_ivp {method}", setup,
                        first, seconds, sol.nfev, sol.y[:, -1]))
    return rows


def peer_rows(build, *args, repeats):
    """Rows of the installed peers built by ``build(peer_name)(*args)``."""
    rows = []
    for name, module in PEERS.items():
        if importlib.util.find_spec(module) is None:
            rows.append(row(name + ": not installed", None, None, None, None, None))
            continue
        derive, generate, run = build(module)(*args)
        first, _ = timed(run, 1)
        seconds, (end, nfev) = timed(run, repeats)
        rows.append(row(name, derive + generate, first, seconds, nfev, end))
    return rows


def slider_table(rows, exact, rtol):
    default, floor = rows[0]["warm"], rows[2]["warm"]
    lines = [f"slider-crank 0-{T_END:g} s at rtol {rtol:g}, atol rtol / 100; warm run = "
             "minimum over the repeats; end error = largest relative difference of the end "
             "state from mechdyn at rtol 1e-12", "",
             "| path | derive + generate s | first run s | warm run ms | RHS evals | "
             "µs / RHS | vs mechdyn default | end error |", "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        if r["warm"] is None:
            lines.append(f"| {r['name']} | - | - | - | - | - | - | - |")
            continue
        error = ("-" if r["end"] is None else
                 f"{np.max(np.abs(np.asarray(r['end']) - exact) / np.abs(exact)):.1e}")
        lines.append(f"| {r['name']} | {_s(r['setup'])} | {_s(r['first'])} | "
                     f"{r['warm'] * 1e3:.2f} | {r['nfev']} | "
                     f"{r['warm'] / r['nfev'] * 1e6:.2f} | {r['warm'] / default:.2f}x | "
                     f"{error} |")
    lines += ["", f"mechdyn default warm run / floor: {default / floor:.1f}x "
              "(issue 24 asks for within 3x)"]
    return "\n".join(lines)


def _s(seconds):
    return "-" if seconds is None else f"{seconds:.2f}"


# ----------------------------------------------------------------------- 2. chain
def chain_mechdyn(n, repeats):
    mech, scene, params, _ = scaling.chain(n)
    start = time.perf_counter()
    mech.equations(scene)
    derive = time.perf_counter() - start
    start = time.perf_counter()
    mech.simulate(scene, params)
    first = time.perf_counter() - start
    warm, res = timed(lambda: mech.simulate(scene, params), repeats)
    values = scaling.chain_values(n)
    floor_p = values["J"] + values["k"] + values["c"] + [values["M"], values["b"]]
    floor, floor_nfev, floor_end = scaling.kernel_run(scaling.floor_functions(), floor_p, n,
                                                      repeats=repeats)
    return [{"name": "numba floor (accelerations by hand, DOP853 kernel)", "setup": None,
             "first": None, "warm": floor, "nfev": floor_nfev, "end": floor_end.tolist()},
            {"name": f"mechdyn default ({'+'.join(res.stats['backends'])}, "
                     f"{res.stats['method']})", "setup": derive, "first": first,
             "warm": warm, "nfev": res.stats["nfev"], "end": res.y[:, -1].tolist()}]


def chain_lagranges(n, repeats):
    r = scaling.measure_lagranges_method(n)
    return [{"name": "sympy LagrangesMethod + lambdify + solve_ivp DOP853",
             "setup": r["derive"] + r["generate"], "first": r["first"], "warm": r["warm"],
             "nfev": round(r["warm"] / r["warm_per_rhs"]), "end": None}]


def chain_peer(module, n, repeats):
    build = getattr(peer_models, f"{module}_chain")
    name = next(k for k, v in PEERS.items() if v == module)
    return [{**r, "end": None if r["end"] is None else np.asarray(r["end"]).tolist()}
            for r in peer_rows(lambda _: build, n, scaling.chain_values(n), scaling.T_END,
                               scaling.RTOL, scaling.ATOL, repeats=repeats)
            if r["name"] == name]


def chain_in_fresh_process(kind, n, repeats):
    env = dict(os.environ, MECHDYN_CACHE=tempfile.mkdtemp(prefix="mechdyn-peers-"))
    try:
        done = subprocess.run([sys.executable, __file__, "--chain-one", kind, str(n),
                               "--repeats", str(repeats)], env=env, capture_output=True,
                              text=True, timeout=CAP_SECONDS)
    except subprocess.TimeoutExpired:
        return [{"name": f"{kind}: not finished in {CAP_SECONDS} s", "setup": None,
                 "first": None, "warm": None, "nfev": None, "end": None}]
    if done.returncode:
        return [{"name": f"{kind}: failed ({done.stderr.strip().splitlines()[-1]})",
                 "setup": None, "first": None, "warm": None, "nfev": None, "end": None}]
    return json.loads(done.stdout.strip().splitlines()[-1])


def chain_header(n):
    return "\n".join([
        f"chain of {n} discs, 0-{scaling.T_END:g} s, rtol {scaling.RTOL:g}, atol "
        f"{scaling.ATOL:g}; each peer in a fresh process (mechdyn: empty cache); derive "
        "includes code generation (mechdyn's: in its first run)", "",
        "| path | derive + generate s | first run s | warm run s | RHS evals | µs / RHS | "
        "x floor / RHS | end vs floor |", "|---|---|---|---|---|---|---|---|"])


def chain_line(r, floor):
    """One row of the chain table; ``floor`` the floor's row (or None)."""
    if r["warm"] is None:
        return f"| {r['name']} | - | - | - | - | - | - | - |"
    per = r["warm"] / r["nfev"]
    ratio = "-" if floor is None else f"{per / (floor['warm'] / floor['nfev']):.1f}"
    diff = ("-" if r["end"] is None or floor is None else
            f"{np.max(np.abs(np.asarray(r['end']) - np.asarray(floor['end']))):.1e}")
    return (f"| {r['name']} | {_s(r['setup'])} | {_s(r['first'])} | {r['warm']:.4f} | "
            f"{r['nfev']} | {per * 1e6:.1f} | {ratio} | {diff} |")


def chain_rows(kinds, n, repeats):
    """Each peer's rows in a fresh process, printed as they come."""
    print("\n" + chain_header(n), flush=True)
    floor = None
    for kind in kinds:
        if kind in PEERS.values() and importlib.util.find_spec(kind) is None:
            rows = [{"name": f"{kind}: not installed", "warm": None}]
        else:
            rows = chain_in_fresh_process(kind, n, repeats)
        for r in rows:
            floor = r if r["name"].startswith("numba floor") else floor
            print(chain_line(r, floor), flush=True)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--rtol", type=float, default=1e-8)
    parser.add_argument("--chain", type=int, default=100, help="discs in the chain")
    parser.add_argument("--chain-peers", nargs="*", default=list(CHAIN_KINDS),
                        choices=CHAIN_KINDS, help="which chain rows to run (none: skip)")
    parser.add_argument("--skip-slider", action="store_true")
    parser.add_argument("--stiff", action="store_true",
                        help="the chain on issue 39's stiff shafts (k = 1e6, c = 5)")
    parser.add_argument("--chain-one", nargs=2, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.stiff:                      # read by scaling.chain_values, here and in the
        os.environ["MECHDYN_BENCH_STIFF"] = "1"       # fresh processes of each peer
    if args.chain_one:
        kind, n = args.chain_one[0], int(args.chain_one[1])
        measure = {"mechdyn": chain_mechdyn, "lagranges": chain_lagranges}.get(
            kind, lambda n, repeats: chain_peer(kind, n, repeats))
        print(json.dumps(measure(n, args.repeats)))
        return
    print(f"load average at the start: {os.getloadavg()[0]:.2f}; "
          f"{os.cpu_count()} CPUs; default BLAS threading\n")
    if not args.skip_slider:
        rows, exact = mechdyn_rows(args.rtol, args.repeats)
        rows += lambdify_rows(args.rtol, args.repeats)
        rows += peer_rows(lambda module: getattr(peer_models, f"{module}_slider_crank"),
                          T_END, args.rtol, args.rtol / 100, repeats=args.repeats)
        print(slider_table(rows, exact, args.rtol), flush=True)
    if args.chain_peers:
        chain_rows(args.chain_peers, args.chain, args.repeats)
    print(f"\nload average at the end: {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()

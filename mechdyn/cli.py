"""The ``mechdyn`` command.

    mechdyn equations models/scotch_yoke.py [--format latex|text] [--scene NAME [--solve]]

(``mechdyn linkage``, for closed loops, is in :mod:`mechdyn.cli_linkage`.)
"""
from __future__ import annotations

import argparse
import os
import sys
import traceback

from . import __version__
from .errors import MechdynError, SimulationError

__all__ = ["main"]


def _equations(args):
    from .latex import derivation_latex, derivation_text
    from .model_file import load_model
    model = load_model(args.model)
    scene = model.scene(args.scene) if args.scene else None
    eqs = model.mechanism.equations(scene)
    solution = _solution(model, scene, args.format) if args.solve else None
    print(derivation_latex(eqs) if args.format == "latex" else derivation_text(eqs))
    if solution:
        print(solution)
    return 0


def _solution(model, scene, fmt):
    """The five-case classification and, for cases 1-3, the closed-form solution."""
    from .analytic import classify, closed_form
    from .errors import SceneError
    if scene is None:
        raise SceneError(f"--solve needs --scene NAME (the initial state); scenes of "
                         f"{model.path}: {', '.join(model.scenes) or 'none'}")
    kind = classify(model.mechanism, scene, model.params)
    if not kind.closed_form:
        return f"{kind}: no closed form; integrate it with `mechdyn simulate`"
    solution = closed_form(model.mechanism, scene, model.params)
    return solution.latex() if fmt == "latex" else str(solution)


def _scene_inputs(args):
    """The model file, the scene and the parameters (defaults with ``--param``) a
    scene-running command names."""
    from .model_file import load_model
    model = load_model(args.model)
    return model, model.scene(args.scene), _params(model, args.param)


def _plot(figure_maker, path):
    """Draw to ``path`` (if one was asked for) and say so."""
    if path:
        figure_maker.plot(path)
        print(f"wrote {path}")


def _params(model, assignments):
    """The model's default parameters overridden by ``name=value`` texts."""
    from .parse import assignment
    params = dict(model.params)
    for text in assignments or ():
        name, value = assignment(text)
        params[model.param_symbol(name)] = value
    return params


def _simulate(args):
    model, scene, params = _scene_inputs(args)
    try:
        result = model.mechanism.simulate(scene, params)
    except SimulationError as error:
        if error.partial is not None and args.csv:
            error.partial.to_csv(args.csv)
            print(f"partial result up to the failure written to {args.csv}", file=sys.stderr)
        raise
    print(result.summary())
    if args.csv:
        result.to_csv(args.csv)
        print(f"wrote {args.csv}")
    _plot(result, args.plot)
    return 0


def _add_equations_command(commands):
    equations = commands.add_parser(
        "equations", help="print the derivation (energies, reduced quantities, equations)",
        description="Print the derivation of a model's equations of motion: energies, "
        "generalized forces, reduced inertia and moment, Lagrange's equations.",
        epilog="examples:\n"
        "  mechdyn equations models/scotch_yoke.py\n"
        "  mechdyn equations models/motor_startup.py --scene braking --format text\n"
        "  mechdyn equations models/shoe_brake.py --scene braking --solve",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    _model_argument(equations)
    equations.add_argument("--format", choices=["latex", "text"], default="latex",
                           help="LaTeX (default) or plain text")
    equations.add_argument("--scene", help="only the effects this scene calls for")
    equations.add_argument("--solve", action="store_true",
                           help="classify (five cases) and print the closed-form solution "
                           "of the scene (needs --scene)")
    equations.set_defaults(run=_equations)


def _add_simulate_command(commands):
    simulate = commands.add_parser(
        "simulate", help="simulate a scene and print a summary",
        description="Simulate one scene of a model file and print how it ended, final "
        "and peak values, events and the solver's cost.",
        epilog="examples:\n"
        "  mechdyn simulate models/shoe_brake.py --scene braking\n"
        "  mechdyn simulate models/shoe_brake.py --scene braking --param P=30 "
        "--plot brake.png --csv brake.csv\n\n"
        "exit status 1 if the integration fails (the partial trajectory still goes to --csv)",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    _model_argument(simulate)
    _scene_argument(simulate)
    _param_argument(simulate)
    simulate.add_argument("--plot", metavar="FILE.png", help="save a figure (PNG, SVG, PDF)")
    simulate.add_argument("--csv", metavar="FILE.csv", help="save the trajectory")
    simulate.set_defaults(run=_simulate)


def _precision(args):
    from .precision import work_precision
    model, scene, params = _scene_inputs(args)
    table = work_precision(model.mechanism, scene, params, methods=args.methods,
                           rtols=args.rtols, repeats=args.repeats)
    print(table)
    if args.target is not None:
        best = table.cheapest(args.target)
        print(f"cheapest meeting {args.target:.1e}: " + (
            f"{best.method} at rtol {best.rtol:.0e} ({best.time * 1e3:.2f} ms, error "
            f"{best.error:.1e})" if best else "none of these runs"))
    _plot(table, args.plot)
    return 0


def _add_precision_command(commands):
    from .precision import DEFAULT_METHODS, DEFAULT_RTOLS

    def positive(text):
        value = float(text)
        if not 0 < value < float("inf"):
            raise argparse.ArgumentTypeError(f"{text!r} is not a positive number")
        return value
    precision = commands.add_parser(
        "precision", help="work-precision table: error against run time per method",
        description="Simulate a scene with each method at each tolerance, compare with a "
        "reference (the closed form where one exists, else DOP853 at rtol 1e-13 checked by "
        "Radau) and print final-state, L2 and event-time errors, run time and solver cost.",
        epilog="example:\n  mechdyn precision models/shoe_brake.py --scene braking "
        "--plot wp.png --target 1e-6", formatter_class=argparse.RawDescriptionHelpFormatter)
    _model_argument(precision)
    _scene_argument(precision)
    _param_argument(precision)
    precision.add_argument("--methods", nargs="+", default=list(DEFAULT_METHODS),
                           metavar="METHOD", help="solve_ivp methods or auto (default: "
                           f"{' '.join(DEFAULT_METHODS)})")
    precision.add_argument("--rtols", nargs="+", type=positive, default=list(DEFAULT_RTOLS),
                           metavar="RTOL", help="relative tolerances (default: "
                           f"{' '.join(f'{r:.0e}' for r in DEFAULT_RTOLS)})")
    precision.add_argument("--repeats", type=int, default=3, help="runs per point; the "
                           "time is their minimum (default 3)")
    precision.add_argument("--target", type=positive, metavar="ERROR",
                           help="also print the cheapest method and rtol meeting ERROR")
    precision.add_argument("--plot", metavar="FILE.png", help="save the work-precision "
                           "diagram")
    precision.set_defaults(run=_precision)


def _periodic(args):
    from .fluctuation import applies, steady_running
    from .periodic import periodic_steady_state
    model, scene, params = _scene_inputs(args)
    if args.period is None and applies(model.mechanism, scene):
        solution = steady_running(model.mechanism, scene, params, cycle=args.cycle)
    else:
        solution = periodic_steady_state(model.mechanism, scene, params, period=args.period)
    print(solution.summary())
    _plot(solution, args.plot)
    return 0


def _add_periodic_command(commands):
    from .parse import number
    periodic = commands.add_parser(
        "periodic", help="steady periodic motion, Floquet multipliers, speed fluctuation",
        description="Find the periodic motion of a scene: under periodic forcing or "
        "parametric excitation (period T: --period, else from the sines and cosines of t), "
        "the periodic state, the swing of every state and the Floquet multipliers; for a "
        "one-DOF machine free of t, steady running over a cycle of its coordinate with the "
        "coefficient of speed fluctuation delta.",
        epilog="examples:\n  mechdyn periodic models/loom_sley.py --scene run --plot loom.png\n"
        "  mechdyn periodic models/press_flywheel.py --scene steady --param J_f=2",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    _model_argument(periodic)
    _scene_argument(periodic)
    _param_argument(periodic)
    periodic.add_argument("--period", type=number, metavar="T",
                          help="period in s (a number or arithmetic such as 2*pi/26.18)")
    periodic.add_argument("--cycle", type=number, default="2*pi", metavar="PHI",
                          help="cycle of a one-DOF machine's coordinate (default 2*pi)")
    periodic.add_argument("--plot", metavar="FILE.png", help="save one period as a figure")
    periodic.set_defaults(run=_periodic)


def _models(args):
    from pathlib import Path

    from .model_file import load_model
    folder = Path(args.folder)
    if not folder.is_dir():
        raise MechdynError(f"no folder {folder} in {Path.cwd()}; give the folder of "
                           "model files: mechdyn models DIR (the bundled models are in "
                           "the models/ folder of mechdyn's repository)")
    files = sorted(p for p in folder.glob("*.py") if not p.name.startswith("_"))
    if not files:
        raise MechdynError(f"{folder} holds no model files (*.py)")
    broken = 0
    for path in files:
        try:
            model = load_model(path)
        except MechdynError as error:
            broken += 1
            print(f"{path}\n    cannot be loaded: {' '.join(str(error).split())}")
            continue
        summary = " ".join(model.doc.split("\n\n")[0].split()) or model.mechanism.name
        print(f"{path}  {summary}\n    scenes: {', '.join(model.scenes) or 'none'}")
    return EXIT_USAGE if broken else EXIT_OK


def _add_models_command(commands):
    models = commands.add_parser(
        "models", help="list model files with their scenes and descriptions",
        description="List the model files of a folder: the first line of each file's "
        "docstring (its first paragraph) and its scenes.",
        epilog="examples:\n  mechdyn models            (the models/ folder here)\n"
        "  mechdyn models ~/my_machines", formatter_class=argparse.RawDescriptionHelpFormatter)
    models.add_argument("folder", nargs="?", default="models", metavar="DIR",
                        help="folder of model files (default: models)")
    models.set_defaults(run=_models)


def _report(args):
    from pathlib import Path

    from .report import report
    model, scene, params = _scene_inputs(args)
    page = report(model.mechanism, scene, params, precision=args.precision)
    out = args.output or f"{Path(args.model).stem}_{args.scene}.html"
    page.write(out)
    print(f"wrote {out}")
    if page.failure:
        print(f"mechdyn: simulation failed: {page.failure}", file=sys.stderr)
        return EXIT_FAILED
    return EXIT_OK


def _add_report_command(commands):
    report = commands.add_parser(
        "report", help="write one HTML page: derivation, scene, results, plots",
        description="Write a self-contained HTML page for a scene: the derivation in LaTeX "
        "(typeset by MathJax when online), the mechanism and its parameters, the scene, "
        "the results with events and the default figure; with --precision also the "
        "work-precision table of the integrators.",
        epilog="examples:\n"
        "  mechdyn report models/shoe_brake.py --scene braking -o brake.html\n"
        "  mechdyn report models/motor_startup.py --scene startup --precision\n\n"
        "exit status 1 if the simulation fails (the page still shows the derivation and "
        "the partial result)", formatter_class=argparse.RawDescriptionHelpFormatter)
    _model_argument(report)
    _scene_argument(report)
    _param_argument(report)
    report.add_argument("-o", "--output", metavar="FILE.html",
                        help="the page to write (default: MODEL_SCENE.html here)")
    report.add_argument("--precision", action="store_true",
                        help="add the work-precision table (runs every integrator at "
                        "several tolerances)")
    report.set_defaults(run=_report)


def _grid_axis(model, text):
    """``name=start:stop:count`` (evenly spaced) or ``name=v1,v2,...`` -> (name, values)."""
    import numpy as np

    from .parse import ValueTextError, number
    name, sep, values = text.partition("=")
    if not sep or not name.strip().isidentifier():
        raise ValueTextError(f"--grid {text!r}: expected name=start:stop:count or "
                             "name=v1,v2,..., e.g. P=10:100:50")
    name = str(model.param_symbol(name.strip()))
    if ":" in values:
        parts = values.split(":")
        if len(parts) != 3:
            raise ValueTextError(f"--grid {text!r}: expected start:stop:count")
        start, stop, count = (number(part) for part in parts)
        if count != int(count) or count < 1:
            raise ValueTextError(f"--grid {text!r}: count must be a whole number >= 1")
        return name, list(np.linspace(start, stop, int(count)))
    return name, [number(value) for value in values.split(",")]


def _sweep(args):
    from contextlib import ExitStack

    from .sweeps import sweep
    model, scene, params = _scene_inputs(args)
    grid = dict(_grid_axis(model, text) for text in args.grid)
    with ExitStack() as stack:
        executor = None
        if args.dask:
            executor = stack.enter_context(_dask_client(args.dask)).get_executor()
        elif args.workers:
            from concurrent.futures import ProcessPoolExecutor
            executor = stack.enter_context(ProcessPoolExecutor(args.workers))
        table = sweep(model.mechanism, scene, params, grid, executor, out=args.out)
    y = args.y or table.default_y
    if y not in table.columns:
        raise MechdynError(f"--y {y!r}: not a column ({', '.join(table.columns)})")
    shown = table.parameters + [y] + (["t_end"] if y != "t_end" else [])
    print("  ".join(f"{c:>14}" for c in shown) + "  reason or error")
    for row in table.rows:
        cells = "  ".join(f"{row[c]:>14.6g}" for c in shown)
        print(f"{cells}  {row['error'] or row['reason']}")
    if args.out:
        print(f"wrote {args.out}")
    if args.plot:
        table.plot(y, args.plot)
        print(f"wrote {args.plot}")
    if table.failed:
        print(f"mechdyn: {len(table.failed)} of {len(table)} points failed", file=sys.stderr)
        return EXIT_FAILED
    return EXIT_OK


def _dask_client(address):
    try:
        from distributed import Client
    except ImportError:
        raise MechdynError("--dask needs dask.distributed: pip install 'mechdyn[dask]'") from None
    try:
        return Client(address, timeout=30)
    except (OSError, TimeoutError) as error:
        raise MechdynError(f"--dask {address}: cannot reach the scheduler ({error})") from None


def _add_sweep_command(commands):
    sweep = commands.add_parser(
        "sweep", help="simulate a scene over a grid of parameter values",
        description="Simulate a scene at every point of a parameter grid (all combinations "
        "of the --grid axes), deriving and compiling once. Rows stream to --out as points "
        "finish; rerun with the same --out to resume after an interruption.",
        epilog="examples:\n"
        "  mechdyn sweep models/shoe_brake.py --scene braking --grid P=10:100:10 "
        "--plot stop.png\n"
        "  mechdyn sweep models/hoist_drive.py --scene lift_start --grid E_k=2e6:8e6:4 "
        "--grid d_r=500,1100 --y peak:rope --out hoist.csv --workers 2\n"
        "  mechdyn sweep models/shoe_brake.py --scene braking --grid P=10:100:1000 "
        "--dask tcp://scheduler:8786 --out brake.csv\n\n"
        "columns: the swept parameters, t_end, reason, final:STATE per coordinate and "
        "speed, peak:OUTPUT per output, error\n"
        "exit status 1 if any point failed (its row holds the error; the others are kept)",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    _model_argument(sweep)
    _scene_argument(sweep)
    sweep.add_argument("--grid", action="append", required=True,
                       metavar="NAME=START:STOP:COUNT",
                       help="a swept parameter: COUNT evenly spaced values, or NAME=V1,V2,...; "
                       "repeatable (full factorial)")
    _param_argument(sweep)
    where = sweep.add_mutually_exclusive_group()
    where.add_argument("--workers", type=int, metavar="N",
                       help="local worker processes (default: all cores)")
    where.add_argument("--dask", metavar="ADDRESS",
                       help="run on a Dask cluster, e.g. tcp://host:8786 (needs mechdyn[dask])")
    sweep.add_argument("--out", metavar="FILE.csv", help="stream the rows to this file "
                       "(an existing file of the same sweep is resumed)")
    sweep.add_argument("--plot", metavar="FILE.png",
                       help="plot --y against the first swept parameter")
    sweep.add_argument("--y", metavar="COLUMN", help="the column to show and plot "
                       "(default: t_end if the scene stops, else the first peak)")
    sweep.set_defaults(run=_sweep)


# ------------------------------------------------------------- shared options
def _model_argument(parser):
    parser.add_argument("model", help="model file (defines mechanism, params, scenes); "
                        "`mechdyn models` lists them")


def _scene_argument(parser, required=True):
    parser.add_argument("--scene", required=required, metavar="NAME", help="scene name")


def _param_argument(parser):
    parser.add_argument("--param", action="append", metavar="NAME=VALUE",
                        help="override a parameter (a number or arithmetic such as 2*pi, "
                        "never eval'ed); repeatable")


# ------------------------------------------------------------- parser and main
EXIT_OK, EXIT_FAILED, EXIT_USAGE, EXIT_BUG = 0, 1, 2, 3
_EXIT_CODES = """exit status:
  0  success
  1  a simulation failed (integration error; in a sweep: at least one point failed)
  2  usage or input error: bad option, model file, scene, parameter or value
  3  internal error (a bug in mechdyn: rerun with --debug and report the traceback)"""


class _Formatter(argparse.RawDescriptionHelpFormatter):
    """Examples keep their lines; command names fit beside their help."""

    def __init__(self, prog):
        super().__init__(prog, max_help_position=30)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="mechdyn", description="Dynamics of machines and mechanisms: derive, "
        "print and simulate the equations of motion of a model file (a Python file "
        "defining `mechanism`, `params` and `scenes`).",
        epilog="examples:\n"
        "  mechdyn models\n"
        "  mechdyn equations models/shoe_brake.py\n"
        "  mechdyn simulate models/shoe_brake.py --scene braking --plot brake.png\n\n"
        "`mechdyn COMMAND --help` shows a command's options and examples.\n\n"
        + _EXIT_CODES, formatter_class=_Formatter)
    parser.add_argument("--version", action="version", version=f"mechdyn {__version__}")
    parser.add_argument("--debug", action="store_true",
                        help="show the traceback of an error (also after the command)")
    commands = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    _add_equations_command(commands)
    _add_simulate_command(commands)
    _add_precision_command(commands)
    _add_models_command(commands)
    _add_report_command(commands)
    _add_sweep_command(commands)
    _add_periodic_command(commands)
    from .cli_linkage import add_linkage_command
    add_linkage_command(commands)
    for command in commands.choices.values():
        command.add_argument("--debug", action="store_true", default=argparse.SUPPRESS,
                             help="show the traceback of an error")
    return parser


def main(argv=None) -> int:
    """Run the command line; returns the exit status (see ``mechdyn --help``)."""
    args = build_parser().parse_args(argv)          # usage errors exit with 2 here
    try:
        return args.run(args)
    except BrokenPipeError:              # output piped into e.g. `head`: not an error
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return EXIT_OK
    except KeyboardInterrupt:
        print("mechdyn: interrupted", file=sys.stderr)
        return 130
    except Exception as error:
        if args.debug:
            traceback.print_exc()
        status, prefix = _classify(error)
        message = " ".join(str(error).split()) or type(error).__name__
        hint = "" if args.debug or status != EXIT_BUG else " (rerun with --debug for the traceback)"
        print(f"mechdyn: {prefix}{message}{hint}", file=sys.stderr)
        return status


def _classify(error):
    """Exit status and message prefix of an error."""
    if isinstance(error, SimulationError):
        return EXIT_FAILED, "simulation failed: "
    if isinstance(error, MechdynError):
        return EXIT_USAGE, "error: "
    if isinstance(error, OSError):
        return EXIT_USAGE, f"error: {type(error).__name__}: "
    return EXIT_BUG, f"internal error: {type(error).__name__}: "


if __name__ == "__main__":
    sys.exit(main())

"""The ``mechdyn`` command.

    mechdyn equations models/scotch_yoke.py [--format latex|text] [--scene NAME [--solve]]

(``mechdyn linkage``, for closed loops, is in :mod:`mechdyn.cli.linkage`.)
"""
from __future__ import annotations

import argparse
from pathlib import Path
import os
import sys
import traceback
import warnings

from mechdyn.version import __version__
from mechdyn.errors import MechdynError, MechdynWarning, SimulationError

__all__ = ["main"]


def _equations(args):
    from mechdyn.derive.latex import derivation_latex, derivation_text
    from mechdyn.declare.model_file import load_model
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
    from mechdyn.derive.analytic import classify
    from mechdyn.derive.closed_form import closed_form
    from mechdyn.errors import SceneError
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
    from mechdyn.declare.model_file import load_model
    model = load_model(args.model)
    scene = model.scene(args.scene)
    return model, scene, _params(model, scene, args.param)


def _plot(figure_maker, path):
    """Draw to ``path`` (if one was asked for) and say so."""
    if path:
        figure_maker.plot(path)
        print(f"wrote {path}")


def _params(model, scene, assignments):
    """The model's default parameters overridden by ``name=value`` texts (a value may
    carry a unit: ``P=2 kN``, checked against the parameter's declared unit)."""
    from mechdyn.declare.parameters import ParameterSet
    from mechdyn.parse import assignment
    overrides = dict(assignment(text) for text in assignments or ())
    return ParameterSet(overrides, defaults=model.params, mechanism=model.mechanism,
                        scene=scene)


def _simulate(args):
    try:
        with _progress(args) as progress:
            result = _run_scene_or_cycle(args, progress)
    except SimulationError as error:
        if error.partial is not None and args.csv:
            error.partial.to_csv(args.csv)
            print(f"partial result up to the failure written to {args.csv}", file=sys.stderr)
        raise
    print(result.summary(units=args.units))
    if args.csv:
        result.to_csv(args.csv, sample=args.sample, units=args.units)
        print(f"wrote {args.csv}")
    if args.plot:
        result.plot(args.plot, sample=args.sample, units=args.units)
        print(f"wrote {args.plot}")
    return 0


def _run_scene_or_cycle(args, progress):
    """The result of ``--scene NAME``, or of the duty cycle ``--scene A+B+C``; the same
    single-scene command as before runs from the warm start (:mod:`mechdyn.cli.warm`)."""
    from mechdyn.cli import warm
    name = None if "+" in args.scene else warm.entry_name(args.model, args.scene, args.param)
    result = warm.recall(name, progress)       # no model file, no sympy
    if result is not None:
        return result
    before = set(sys.modules)
    from mechdyn.declare.model_file import load_model
    from mechdyn.parse import assignment
    model = load_model(args.model)
    if "+" in args.scene and args.scene not in model.scenes:
        from mechdyn.analyse.cycle import duty_cycle
        overrides = dict(assignment(text) for text in args.param or ())
        return duty_cycle(model, args.scene, overrides, progress=progress)
    scene = model.scene(args.scene)
    params = _params(model, scene, args.param)
    if progress is not None:
        progress.t_start = scene.t_start
    result = model.mechanism.simulate(scene, params, progress=progress)
    if name is not None:
        from mechdyn.simulate.simulation import atol_vector
        warm.remember(name, model, scene, result,
                      atol_vector(result.compiled, model.mechanism, scene),
                      warm.local_modules(before, Path(args.model).parent))
    return result


def _progress(args):
    """The progress line on stderr: for runs past two seconds when stderr is a terminal
    (``--progress``: whatever stderr is; ``--no-progress``: never)."""
    from contextlib import nullcontext

    from mechdyn.progress import ProgressLine
    shown = args.progress if args.progress is not None else sys.stderr.isatty()
    return ProgressLine(sys.stderr) if shown else nullcontext()


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
        "--plot brake.png --csv brake.csv\n"
        "  mechdyn simulate models/motor_startup.py --scene startup --param 'M_L=0.06 kN*m' "
        "--units speed=rpm,power=kW --csv run.csv --sample 0.01\n"
        "  mechdyn simulate models/press_cycle.py --scene startup+steady+braking "
        "--plot cycle.png\n\n"
        "--scene A+B+C runs a duty cycle: each phase starts where the one before ended "
        "(one summary, plot and CSV with a phase column)\n"
        "exit status 1 if the integration fails (the partial trajectory still goes to --csv)",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    _model_argument(simulate)
    simulate.add_argument("--scene", required=True, metavar="NAME",
                          help="scene name, or A+B+C: a duty cycle of scenes run one after "
                          "another")
    _param_argument(simulate)
    simulate.add_argument("--plot", metavar="FILE.png", help="save a figure (PNG, SVG, PDF)")
    simulate.add_argument("--csv", metavar="FILE.csv", help="save the trajectory")
    _units_argument(simulate)
    _sample_argument(simulate)
    _progress_argument(simulate)
    simulate.set_defaults(run=_simulate)


def _precision(args):
    from mechdyn.analyse.precision import work_precision
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
    from mechdyn.simulate.methods import COMPARED as DEFAULT_METHODS, COMPARED_RTOLS as DEFAULT_RTOLS

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
    from mechdyn.analyse.fluctuation import applies, steady_running
    from mechdyn.analyse.periodic import periodic_steady_state
    model, scene, params = _scene_inputs(args)
    if args.period is None and applies(model.mechanism, scene):
        solution = steady_running(model.mechanism, scene, params, cycle=args.cycle)
    else:
        solution = periodic_steady_state(model.mechanism, scene, params, period=args.period)
    print(solution.summary())
    _plot(solution, args.plot)
    return 0


def _add_periodic_command(commands):
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
    periodic.add_argument("--period", type=_quantity("s", "period", positive=False),
                          metavar="T",
                          help="period in s (a number or arithmetic such as 2*pi/26.18, "
                          "or with a unit: '40 ms')")
    periodic.add_argument("--cycle", type=_quantity("rad", "cycle", positive=False),
                          default="2*pi",
                          metavar="PHI",
                          help="cycle of a one-DOF machine's coordinate (default 2*pi)")
    periodic.add_argument("--plot", metavar="FILE.png", help="save one period as a figure")
    periodic.set_defaults(run=_periodic)


def _models(args):
    from pathlib import Path

    from mechdyn.declare.model_file import load_model
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
            reason = " ".join(str(error).split())
            if reason.startswith(str(path)):
                reason = reason[len(str(path)):].lstrip(":, ")
            print(f"{path}  cannot be loaded: {reason}")
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

    from mechdyn.report.document import report
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
        description="Write a self-contained HTML page for a scene: the derivation "
        "(MathML: no network needed), the mechanism and its parameters, the scene, "
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


def _grid_axis(model, text, max_points):
    """``name=start:stop:count`` (evenly spaced) or ``name=v1,v2,...`` -> (name, SI
    values); a unit after the values applies to all of them (``P=1:3:3 kN``), else
    every value or none carries one (``P=500 N,2 kN``). A count above ``max_points`` is
    refused before any value is made."""
    import re

    import numpy as np

    from mechdyn.declare.parameters import to_number
    from mechdyn.parse import ValueTextError, number
    name, sep, values = text.partition("=")
    if not sep or not name.strip().isidentifier():
        raise ValueTextError(f"--grid {text!r}: expected name=start:stop:count or "
                             "name=v1,v2,..., e.g. P=10:100:50 or P=1:3:3 kN")
    name = str(model.param_symbol(name.strip()))
    declared = model.mechanism.parameter_units.get(name)
    common = re.fullmatch(r"\s*(\S+)\s+([^,:]+?)\s*", values)
    body, unit = (common.group(1), common.group(2)) if common else (values, "")

    def value(part):
        try:
            return to_number(name, f"{part} {unit}" if unit else part, declared)
        except MechdynError as error:
            raise ValueTextError(f"--grid {text!r}: {error}") from None
    parts = body.split(":") if ":" in body else body.split(",")
    with_unit = [_has_unit(part) for part in parts] if not unit else []
    if any(with_unit) and not all(with_unit[:2 if ":" in body else None]):
        raise ValueTextError(f"--grid {text!r}: some values carry a unit and others do "
                             "not (bare numbers are SI); give every value its unit or one "
                             "unit after all of them, e.g. P=10,20,50 kN")
    if ":" not in body:
        return name, [value(part) for part in parts]
    if len(parts) != 3:
        raise ValueTextError(f"--grid {text!r}: expected start:stop:count")
    start, stop = value(parts[0]), value(parts[1])
    try:
        count = number(parts[2])
    except ValueTextError as error:
        raise ValueTextError(f"--grid {text!r}: count: {error}") from None
    if count != int(count) or count < 1:
        raise ValueTextError(f"--grid {text!r}: count must be a whole number >= 1")
    if count > max_points:
        raise ValueTextError(f"--grid {text!r}: {count:,.0f} values, more than "
                             f"--max-points {max_points:,}")
    return name, list(np.linspace(start, stop, int(count)))


def _has_unit(text) -> bool:
    from mechdyn.parse import ValueTextError, quantity
    try:
        return bool(quantity(text)[1])
    except ValueTextError:
        return False                    # its own error comes when it is read


def _sweep(args):
    from contextlib import ExitStack

    from mechdyn.analyse.sweeps import sweep
    model, scene, params = _scene_inputs(args)
    grid = dict(_grid_axis(model, text, args.max_points) for text in args.grid)
    with ExitStack() as stack:
        executor = None
        if args.dask:
            executor = stack.enter_context(_dask_client(args.dask)).get_executor()
        table = sweep(model.mechanism, scene, params, grid, executor, out=args.out,
                      workers=args.workers, max_points=args.max_points, fresh=args.fresh,
                      wait=args.wait)
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
    from mechdyn.analyse.sweep_file import MAX_POINTS
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
    where.add_argument("--workers", type=_whole_number, metavar="N",
                       help="local worker processes (default: all cores)")
    where.add_argument("--dask", metavar="ADDRESS",
                       help="run on a Dask cluster, e.g. tcp://host:8786 (needs mechdyn[dask])")
    sweep.add_argument("--out", metavar="FILE.csv", help="stream the rows to this file "
                       "(an existing file of the same sweep is resumed; FILE.csv.meta.json "
                       "records the sweep, FILE.csv.lock keeps other sweeps out)")
    sweep.add_argument("--fresh", action="store_true",
                       help="discard the rows of an existing --out file instead of resuming")
    sweep.add_argument("--wait", type=_seconds, default=0.0, metavar="SECONDS",
                       help="wait this long for another sweep writing --out (default: "
                       "stop at once)")
    sweep.add_argument("--max-points", type=_whole_number, default=MAX_POINTS, metavar="N",
                       help=f"refuse grids with more points (default {MAX_POINTS:,})")
    sweep.add_argument("--plot", metavar="FILE.png",
                       help="plot --y against the first swept parameter")
    sweep.add_argument("--y", metavar="COLUMN", help="the column to show and plot "
                       "(default: t_end if the scene stops, else the first peak)")
    sweep.set_defaults(run=_sweep)


def _characteristic(args):
    from mechdyn.analyse.characteristics import characteristic
    from mechdyn.declare.model_file import load_model
    model = load_model(args.model)
    scene = model.scene(args.scene) if args.scene else None
    curves = characteristic(model.mechanism, scene, _params(model, scene, args.param),
                            drive=args.drive)
    print(curves.summary(args.units))
    if args.plot:
        curves.plot(args.plot, units=args.units)
        print(f"wrote {args.plot}")
    return EXIT_OK


def _add_characteristic_command(commands):
    command = commands.add_parser(
        "characteristic", help="motor and load characteristics, operating points, stability",
        description="Draw the drive's moment M(omega) against the reduced moment of the "
        "load (the mean over a cycle where it depends on the position) for a one-DOF "
        "machine, and list the operating points where they balance: stable where "
        "dM_motor/domega < dM_load/domega.",
        epilog="examples:\n"
        "  mechdyn characteristic models/motor_startup.py --scene startup --plot ml.png\n"
        "  mechdyn characteristic models/press_flywheel.py --scene steady --units speed=rpm "
        "--plot press.png", formatter_class=argparse.RawDescriptionHelpFormatter)
    _model_argument(command)
    _scene_argument(command, required=False)
    _param_argument(command)
    command.add_argument("--drive", metavar="NAME", help="the driving load (name or tag; "
                         "default: the load named or tagged motor)")
    command.add_argument("--plot", metavar="FILE.png", help="save the characteristics")
    _units_argument(command)
    command.set_defaults(run=_characteristic)


def _animate(args):
    from mechdyn.report.animation import animate
    model, scene, params = _scene_inputs(args)
    with _progress(args) as progress:
        if progress is not None:
            progress.t_start = scene.t_start
        result = model.mechanism.simulate(scene, params, progress=progress)
    film = animate(model.mechanism, result, params, args.out, sample=args.sample,
                   fps=args.fps)
    print(f"wrote {film.path}: {film.frames} frames, every {film.times[1] - film.times[0]:.4g} "
          f"s of the motion at {film.fps:g} frames per second" if film.frames > 1 else
          f"wrote {film.path}: 1 frame")
    return EXIT_OK


def _add_animate_command(commands):
    command = commands.add_parser(
        "animate", help="draw the links over the simulated motion into a GIF",
        description="Simulate a scene and draw its links (their declared points, or the "
        "centre of mass with a tick along the link's angle) frame by frame into a GIF: "
        "one frame per --sample seconds of the motion (default 1/fps: real time).",
        epilog="examples:\n"
        "  mechdyn animate models/slider_crank.py --scene startup --out crank.gif\n"
        "  mechdyn animate models/scotch_yoke.py --scene startup --out yoke.gif "
        "--sample 0.01 --fps 20", formatter_class=argparse.RawDescriptionHelpFormatter)
    _model_argument(command)
    _scene_argument(command)
    _param_argument(command)
    command.add_argument("--out", metavar="FILE.gif", default="animation.gif",
                         help="the GIF to write (default animation.gif)")
    _sample_argument(command)
    command.add_argument("--fps", type=float, default=25.0,
                         help="frames per second of the GIF (default 25)")
    _progress_argument(command)
    command.set_defaults(run=_animate)


# ------------------------------------------------------------- shared options
def _seconds(text):
    """An argparse type: a finite time >= 0 in seconds."""
    try:
        value = float(text)
    except ValueError:
        value = -1.0
    if not 0 <= value < float("inf"):
        raise argparse.ArgumentTypeError(f"{text!r} is not a time in seconds >= 0")
    return value


def _whole_number(text):
    """An argparse type: a whole number >= 1."""
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number >= 1")
    return value


def _model_argument(parser):
    parser.add_argument("model", help="model file (defines mechanism, params, scenes); "
                        "`mechdyn models` lists them")


def _scene_argument(parser, required=True):
    parser.add_argument("--scene", required=required, metavar="NAME", help="scene name")


def _param_argument(parser):
    parser.add_argument("--param", action="append", metavar="NAME=VALUE",
                        help="override a parameter (a number or arithmetic such as 2*pi, "
                        "never eval'ed, SI unless a unit follows: 'P=2 kN', "
                        "'omega_s=1500 rpm'); repeatable")


def _units_argument(parser):
    parser.add_argument("--units", metavar="KIND=UNIT,...",
                        help="show results in these units: kinds angle, speed, "
                        "acceleration, length, velocity, force, moment, power (or a column "
                        "name), e.g. speed=rpm,power=kW,rope=kN")


def _quantity(unit, what, positive=True):
    """An argparse type: a value (positive if asked), SI or a text with a unit of
    ``unit``'s dimension (``"1 ms"`` for seconds)."""
    def convert(text):
        from mechdyn.units import to_si
        try:
            value = to_si(text, unit)
        except MechdynError as error:
            raise argparse.ArgumentTypeError(str(error)) from None
        if positive and not value > 0:
            raise argparse.ArgumentTypeError(f"{text!r} is not a positive {what}")
        return value
    convert.__name__ = what
    return convert


def _progress_argument(parser):
    parser.add_argument("--progress", action=argparse.BooleanOptionalAction, default=None,
                        help="show the simulated time on stderr for runs longer than two "
                        "seconds (default: when stderr is a terminal)")


def _sample_argument(parser):
    parser.add_argument("--sample", type=_quantity("s", "time step"), metavar="DT",
                        help="CSV rows and plot points every DT seconds (or a time with "
                        "its unit, '1 ms') from the dense output instead of the solver's "
                        "steps")


# ------------------------------------------------------------- parser and main
EXIT_OK, EXIT_FAILED, EXIT_USAGE, EXIT_BUG = 0, 1, 2, 3
_EXIT_CODES = """exit status:
  0  success
  1  a simulation failed (integration error; in a sweep: at least one point failed)
  2  usage or input error: bad option, model file, scene, parameter or value
  3  internal error (a bug in mechdyn: rerun with --debug and report the traceback)
  130  interrupted (Ctrl-C); a sweep keeps its finished rows and resumes"""


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
    _add_characteristic_command(commands)
    _add_animate_command(commands)
    from mechdyn.cli.linkage import add_linkage_command
    add_linkage_command(commands)
    for command in commands.choices.values():
        command.add_argument("--debug", action="store_true", default=argparse.SUPPRESS,
                             help="show the traceback of an error")
    return parser


def main(argv=None) -> int:
    """Run the command line; returns the exit status (see ``mechdyn --help``)."""
    args = build_parser().parse_args(argv)          # usage errors exit with 2 here
    with warnings.catch_warnings():
        others = warnings.showwarning

        def show(message, category, *where, **more):
            """mechdyn's own warnings as one line, ``mechdyn: warning: ...``."""
            if issubclass(category, MechdynWarning):
                print(f"mechdyn: warning: {message}", file=sys.stderr)
            else:
                others(message, category, *where, **more)
        warnings.showwarning = show
        return _run(args)


def _run(args) -> int:
    try:
        _check_outputs(args)                        # before any work is done
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


# Files a command writes: option -> (attribute, suffixes it can write, what it is).
_PLOT_SUFFIXES = (".png", ".pdf", ".svg", ".svgz", ".eps", ".ps", ".jpg", ".jpeg", ".tif",
                  ".tiff", ".webp", ".pgf")
_OUTPUTS = {"--plot": ("plot", _PLOT_SUFFIXES, "a figure"),
            "--csv": ("csv", (".csv", ".txt"), "a CSV file"),
            "--out": ("out", (".csv", ".txt"), "a CSV file"),
            "-o": ("output", (".html", ".htm"), "an HTML page")}


def _check_outputs(args):
    """Refuse output files that could not be written, before anything is computed: an
    unsupported suffix, a missing folder, a folder in the file's place, plots without
    matplotlib."""
    from importlib.util import find_spec
    from pathlib import Path
    for option, (attribute, suffixes, what) in _OUTPUTS.items():
        value = getattr(args, attribute, None)
        if not value:
            continue
        if attribute == "out" and getattr(args, "command", None) == "animate":
            suffixes, what = (".gif",), "an animation"
        path = Path(value)
        if path.suffix.lower() not in suffixes:
            suffix = f"the suffix {path.suffix!r}" if path.suffix else "no suffix"
            raise MechdynError(f"{option} {value}: cannot write {what} with {suffix}; "
                               f"use one of {', '.join(suffixes)}")
        if path.is_dir():
            raise MechdynError(f"{option} {value}: is a folder; give a file name")
        folder = path.parent if str(path.parent) else Path(".")
        if not folder.is_dir():
            raise MechdynError(f"{option} {value}: no folder {folder}")
        if attribute == "plot" and find_spec("matplotlib") is None:
            raise MechdynError("--plot needs matplotlib: pip install 'mechdyn[plot]'")


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

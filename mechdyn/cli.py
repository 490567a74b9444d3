"""The ``mechdyn`` command.

    mechdyn equations models/scotch_yoke.py [--format latex|text] [--scene NAME [--solve]]
"""
from __future__ import annotations

import argparse
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


def _params(model, assignments):
    """The model's default parameters overridden by ``name=value`` texts."""
    from .parse import assignment
    params = dict(model.params)
    for text in assignments or ():
        name, value = assignment(text)
        params[model.param_symbol(name)] = value
    return params


def _simulate(args):
    from .model_file import load_model
    model = load_model(args.model)
    scene = model.scene(args.scene)
    try:
        result = model.mechanism.simulate(scene, _params(model, args.param))
    except SimulationError as error:
        if error.partial is not None and args.csv:
            error.partial.to_csv(args.csv)
            print(f"partial result up to the failure written to {args.csv}", file=sys.stderr)
        raise
    print(result.summary())
    if args.csv:
        result.to_csv(args.csv)
        print(f"wrote {args.csv}")
    if args.plot:
        result.plot(args.plot)
        print(f"wrote {args.plot}")
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
    from .model_file import load_model
    from .precision import work_precision
    model = load_model(args.model)
    table = work_precision(model.mechanism, model.scene(args.scene),
                           _params(model, args.param), methods=args.methods,
                           rtols=args.rtols, repeats=args.repeats)
    print(table)
    if args.target is not None:
        best = table.cheapest(args.target)
        print(f"cheapest meeting {args.target:.1e}: " + (
            f"{best.method} at rtol {best.rtol:.0e} ({best.time * 1e3:.2f} ms, error "
            f"{best.error:.1e})" if best else "none of these runs"))
    if args.plot:
        table.plot(args.plot)
        print(f"wrote {args.plot}")
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
        + _EXIT_CODES, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--version", action="version", version=f"mechdyn {__version__}")
    parser.add_argument("--debug", action="store_true",
                        help="show the traceback of an error (also after the command)")
    commands = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    _add_equations_command(commands)
    _add_simulate_command(commands)
    _add_precision_command(commands)
    for command in commands.choices.values():
        command.add_argument("--debug", action="store_true", default=argparse.SUPPRESS,
                             help="show the traceback of an error")
    return parser


def main(argv=None) -> int:
    """Run the command line; returns the exit status (see ``mechdyn --help``)."""
    args = build_parser().parse_args(argv)          # usage errors exit with 2 here
    try:
        return args.run(args)
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

"""The ``mechdyn`` command.

    mechdyn equations models/scotch_yoke.py [--format latex|text] [--scene NAME [--solve]]
"""
from __future__ import annotations

import argparse
import sys

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


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="mechdyn", description="Dynamics of machines and mechanisms: derive, "
        "print and simulate the equations of motion of a model file.")
    parser.add_argument("--debug", action="store_true", help="show tracebacks on errors")
    commands = parser.add_subparsers(dest="command", required=True)
    equations = commands.add_parser(
        "equations", help="print the derivation (energies, reduced quantities, equations)",
        epilog="example: mechdyn equations models/scotch_yoke.py --format text")
    equations.add_argument("model", help="model file (defines mechanism, params, scenes)")
    equations.add_argument("--format", choices=["latex", "text"], default="latex")
    equations.add_argument("--scene", help="only the effects this scene calls for")
    equations.add_argument("--solve", action="store_true",
                           help="classify (five cases) and print the closed-form solution "
                           "of the scene (needs --scene)")
    equations.set_defaults(run=_equations)
    simulate = commands.add_parser(
        "simulate", help="simulate a scene and print a summary",
        epilog="example: mechdyn simulate models/shoe_brake.py --scene braking "
        "--param P=30 --plot brake.png --csv brake.csv")
    simulate.add_argument("model", help="model file (defines mechanism, params, scenes)")
    simulate.add_argument("--scene", required=True, help="scene name")
    simulate.add_argument("--param", action="append", metavar="NAME=VALUE",
                          help="override a parameter (a number or arithmetic, never eval'ed)")
    simulate.add_argument("--plot", metavar="FILE.png", help="save a figure")
    simulate.add_argument("--csv", metavar="FILE.csv", help="save the trajectory")
    simulate.set_defaults(run=_simulate)
    return parser


def main(argv=None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return args.run(args)
    except MechdynError as error:
        if args.debug:
            raise
        print(f"mechdyn: error: {error}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())

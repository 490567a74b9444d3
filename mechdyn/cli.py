"""The ``mechdyn`` command.

    mechdyn equations models/scotch_yoke.py [--format latex|text] [--scene NAME]
"""
from __future__ import annotations

import argparse
import sys

from .errors import MechdynError

__all__ = ["main"]


def _equations(args):
    from .latex import derivation_latex, derivation_text
    from .model_file import load_model
    model = load_model(args.model)
    scene = model.scene(args.scene) if args.scene else None
    eqs = model.mechanism.equations(scene)
    print(derivation_latex(eqs) if args.format == "latex" else derivation_text(eqs))
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
    equations.set_defaults(run=_equations)
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

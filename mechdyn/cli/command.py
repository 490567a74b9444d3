"""The ``mechdyn`` command.

    mechdyn equations models/scotch_yoke.py [--format latex|text] [--scene NAME [--solve]]

(``mechdyn linkage``, for closed loops, is in :mod:`mechdyn.cli.linkage`; ``mechdyn fmu``
in :mod:`mechdyn.cli.fmu`.)
"""
from __future__ import annotations

import argparse
import os
import sys
import traceback
import warnings
from mechdyn.version import __version__
from mechdyn.errors import MechdynError, MechdynWarning, SimulationError
from mechdyn.cli.arguments import EXIT_BUG, EXIT_FAILED, EXIT_OK, EXIT_USAGE
from mechdyn.cli.model_commands import (_add_animate_command, _add_characteristic_command,
                                        _add_models_command, _add_sweep_command)
from mechdyn.cli.scene_commands import (_add_equations_command, _add_periodic_command,
                                        _add_precision_command, _add_report_command,
                                        _add_simulate_command)

__all__ = ["main"]


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
    from mechdyn.cli.fmu import add_fmu_command
    add_fmu_command(commands)
    from mechdyn.cli.design import add_design_commands
    add_design_commands(commands)
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
        if attribute == "out" and getattr(args, "command", None) == "fmu":
            suffixes, what = (".fmu",), "an FMU"
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

"""What the commands share: the model, scene, parameter, unit, progress and sampling
arguments, parameter values read by the restricted parser, and the exit codes."""
from __future__ import annotations

import argparse

from mechdyn.errors import MechdynError

__all__ = []


def _scene_inputs(args):
    """The model file, the scene and the parameters (defaults with ``--param``) a
    scene-running command names."""
    from mechdyn.declare.model_file import load_model
    model = load_model(args.model)
    scene = model.scene(args.scene)
    return model, scene, _params(model, scene, args.param)


def _plot(figure_maker, path, *before, **options):
    """Draw to ``path`` (if one was asked for: ``figure_maker.plot(*before, path,
    **options)``) and say so."""
    if path:
        figure_maker.plot(*before, path, **options)
        print(f"wrote {path}")


def _params(model, scene, assignments):
    """The model's default parameters overridden by ``name=value`` texts (a value may
    carry a unit: ``P=2 kN``, checked against the parameter's declared unit)."""
    from mechdyn.declare.parameters import ParameterSet
    from mechdyn.parse import assignment
    overrides = dict(assignment(text) for text in assignments or ())
    return ParameterSet(overrides, defaults=model.params, mechanism=model.mechanism,
                        scene=scene)


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


def _display_units(text):
    """An argparse type: ``KIND=UNIT,...`` whose units are known (checked before any
    work; a misspelt unit gets a suggestion)."""
    from mechdyn.display import Display
    from mechdyn.units import dimension
    try:
        for unit in Display(text).choices.values():
            dimension(unit)
    except MechdynError as error:
        raise argparse.ArgumentTypeError(str(error)) from None
    return text


def _units_argument(parser):
    parser.add_argument("--units", metavar="KIND=UNIT,...", type=_display_units,
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

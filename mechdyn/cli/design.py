"""``mechdyn sensitivities`` and ``mechdyn optimize``: a scene's exact sensitivities, and
parameters sized by optimisation (:mod:`mechdyn.analyse.sensitivities`,
:mod:`mechdyn.analyse.optimize`)."""
from __future__ import annotations

import argparse

from mechdyn.cli.arguments import (_model_argument, _param_argument, _plot, _scene_argument,
                                   _scene_inputs)
from mechdyn.cli.common import command_parser, exit_status

__all__ = ["add_design_commands"]


def _bounds(text):
    """``NAME=LOW:HIGH`` (values may carry units) -> ``(name, (low text, high text))``."""
    name, sep, rest = text.partition("=")
    low, colon, high = rest.partition(":")
    if not (sep and colon and name.strip().isidentifier() and low.strip() and high.strip()):
        raise argparse.ArgumentTypeError(f"{text!r}: expected NAME=LOW:HIGH, e.g. J_f=0.1:5")
    return name.strip(), (low.strip(), high.strip())


def _speed_guess(parser):
    parser.add_argument("--speed-guess", type=float, metavar="OMEGA",
                        help="first guess of the steady speed at the cycle start (rad/s; "
                        "for mean_speed and fluctuation)")


def _sensitivities(args):
    from mechdyn.analyse.sensitivities import sensitivities
    model, scene, params = _scene_inputs(args)
    result = sensitivities(model.mechanism, scene, params, args.wrt, args.measure,
                           speed_guess=args.speed_guess)
    print(result.summary())
    _plot(result, args.plot)
    return 0


def _optimize(args):
    from mechdyn.analyse.optimize import optimize
    model, scene, params = _scene_inputs(args)
    best = optimize(model.mechanism, scene, params, dict(args.vary), minimize=args.minimize,
                    maximize=args.maximize, subject_to=args.subject_to or (),
                    speed_guess=args.speed_guess)
    print(best.summary())
    return exit_status(not best.success and f"the optimisation did not converge: "
                       f"{best.message}")


def add_design_commands(commands):
    sens = command_parser(
        commands, "sensitivities", "exact derivatives of measures by parameters",
        "Derivatives of a scene's measures (t_end, stop_angle, final:STATE; mean_speed and "
        "fluctuation of steady running) with respect to parameters, from the forward "
        "sensitivity equations; printed with units and relative (% per %).",
        ["mechdyn sensitivities models/shoe_brake.py --scene braking --wrt I f P R "
         "--measure t_end stop_angle",
         "mechdyn sensitivities models/press_flywheel.py --scene steady --wrt J_f F_p "
         "--measure fluctuation mean_speed --plot sens.png"])
    _model_argument(sens)
    _scene_argument(sens)
    _param_argument(sens)
    sens.add_argument("--wrt", nargs="+", required=True, metavar="NAME",
                      help="parameters to differentiate for")
    sens.add_argument("--measure", nargs="+", default=["t_end"], metavar="MEASURE",
                      help="measures (default t_end)")
    _speed_guess(sens)
    sens.add_argument("--plot", metavar="FILE.png", help="save the relative sensitivities "
                      "as a bar chart")
    sens.set_defaults(run=_sensitivities)

    opt = command_parser(
        commands, "optimize", "size parameters: minimise a goal subject to constraints",
        "Choose parameters within bounds to minimise (or maximise) a measure or an "
        "expression of parameters, subject to constraints on measures or parameters, by "
        "SLSQP with exact gradients; prints the optimum, the active constraints with their "
        "multipliers (what each costs) and the number of simulations.",
        ["mechdyn optimize models/press_flywheel.py --scene steady --vary J_f=0.05:5 "
         "--minimize J_f --subject-to 'fluctuation <= 0.05'",
         "mechdyn optimize models/shoe_brake.py --scene braking --vary P=1:100 R=0.05:0.5 "
         "--minimize 'P + 100*R' --subject-to 't_end <= 20 s' 'P <= 15 N'"],
        ["exit status 1 if the optimisation does not converge"])
    _model_argument(opt)
    _scene_argument(opt)
    _param_argument(opt)
    opt.add_argument("--vary", nargs="+", type=_bounds, required=True, metavar="NAME=LOW:HIGH",
                     help="parameters to choose and their bounds")
    goal = opt.add_mutually_exclusive_group(required=True)
    goal.add_argument("--minimize", metavar="GOAL", help="a measure or an expression of "
                      "parameters")
    goal.add_argument("--maximize", metavar="GOAL")
    opt.add_argument("--subject-to", nargs="+", metavar="CONSTRAINT",
                     help="'GOAL <= LIMIT', '>=' or '==' (the limit may carry a unit)")
    _speed_guess(opt)
    opt.set_defaults(run=_optimize)

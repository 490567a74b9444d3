"""Commands on one scene: ``equations``, ``simulate`` (a scene or a duty cycle, with the
warm start), ``precision``, ``periodic``, ``report``.
"""
from __future__ import annotations

import argparse
from contextlib import contextmanager
from pathlib import Path
import sys
import threading
from mechdyn.errors import SimulationError
from mechdyn.cli.arguments import (_model_argument, _param_argument, _params, _plot, _progress_argument, _quantity, _sample_argument, _seconds, _scene_argument, _scene_inputs, _units_argument)
from mechdyn.cli.common import command_parser, exit_status


def _equations(args):
    from mechdyn.derive.equations import printed_equations
    from mechdyn.derive.latex import derivation_latex, derivation_text
    from mechdyn.derive.textbook import Budget
    from mechdyn.declare.model_file import load_model
    model = load_model(args.model)
    scene = model.scene(args.scene) if args.scene else None
    write = derivation_latex if args.format == "latex" else derivation_text
    with announced(f"deriving and simplifying the equations of {model.mechanism.name!r} "
                   f"(at most {args.budget:g} s of simplification; --budget)"):
        eqs = printed_equations(model.mechanism, scene)
        solution = _solution(model, scene, args.format) if args.solve else None
        text = write(eqs, expanded=args.expanded, budget=Budget(args.budget))
    print(text)
    if solution:
        print(solution)
    return 0


@contextmanager
def announced(message, after=1.0):
    """Say ``message`` on stderr if the block takes longer than ``after`` seconds."""
    timer = threading.Timer(after, lambda: print(f"mechdyn: {message} ...", file=sys.stderr,
                                                 flush=True))
    timer.daemon = True
    timer.start()
    try:
        yield
    finally:
        timer.cancel()


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
    _plot(result, args.plot, sample=args.sample, units=args.units)
    return 0


def _run_scene_or_cycle(args, progress):
    """The result of ``--scene NAME``, or of the duty cycle ``--scene A+B+C``; the same
    single-scene command as before runs from the warm start (:mod:`mechdyn.cli.warm`)."""
    from mechdyn.cli import warm
    name = None if "+" in args.scene else warm.entry_name(args.model, args.scene, args.param)
    result = warm.recall(name, progress)       # no model file, no sympy
    if result is not None:
        return result
    from mechdyn.cli.reads import watching
    from mechdyn.declare.model_file import load_model
    from mechdyn.parse import assignment
    with watching() as reads:                # what the model file's code reads
        model = load_model(args.model)
        cycle = "+" in args.scene and args.scene not in model.scenes
        if not cycle:
            scene = model.scene(args.scene)
            params = _params(model, scene, args.param)
    if cycle:
        from mechdyn.analyse.cycle import duty_cycle
        overrides = dict(assignment(text) for text in args.param or ())
        return duty_cycle(model, args.scene, overrides, progress=progress)
    if progress is not None:
        progress.t_start = scene.t_start
        progress.until = " or ".join(map(repr, scene.until))
    result = model.mechanism.simulate(scene, params, progress=progress)
    if name is not None:
        from mechdyn.simulate.simulation import atol_vector
        warm.remember(name, model, scene, result,
                      atol_vector(result.compiled, model.mechanism, scene),
                      reads.record())
    return result


def _progress(args):
    """The progress line on stderr: for runs past two seconds when stderr is a terminal
    (``--progress``: whatever stderr is; ``--no-progress``: never)."""
    from contextlib import nullcontext

    from mechdyn.progress import ProgressLine
    shown = args.progress if args.progress is not None else sys.stderr.isatty()
    return ProgressLine(sys.stderr) if shown else nullcontext()


def _add_equations_command(commands):
    equations = command_parser(
        commands, "equations", "print the derivation (energies, reduced quantities, equations)",
        "Print the derivation of a model's equations of motion: energies, generalized forces, "
        "reduced inertia and moment, Lagrange's equations.",
        ["mechdyn equations models/scotch_yoke.py",
         "mechdyn equations models/motor_startup.py --scene braking --format text",
         "mechdyn equations models/shoe_brake.py --scene braking --solve",
         "mechdyn equations models/slider_crank.py --expanded"])
    _model_argument(equations)
    equations.add_argument("--format", choices=["latex", "text"], default="latex",
                           help="LaTeX (default) or plain text")
    equations.add_argument("--expanded", action="store_true",
                           help="write every term out in the coordinates (default: "
                           "positions and transmission functions as named quantities)")
    equations.add_argument("--budget", type=_seconds, default=10.0, metavar="SECONDS",
                           help="time for simplification; later expressions are printed "
                           "as derived (default 10)")
    equations.add_argument("--scene", help="only the effects this scene calls for")
    equations.add_argument("--solve", action="store_true",
                           help="classify (five cases) and print the closed-form solution "
                           "of the scene (needs --scene)")
    equations.set_defaults(run=_equations)


def _add_simulate_command(commands):
    simulate = command_parser(
        commands, "simulate", "simulate a scene and print a summary",
        "Simulate one scene of a model file and print how it ended, final and peak values, "
        "events and the solver's cost.",
        ["mechdyn simulate models/shoe_brake.py --scene braking",
         "mechdyn simulate models/shoe_brake.py --scene braking --param P=30 --plot brake.png "
         "--csv brake.csv",
         "mechdyn simulate models/motor_startup.py --scene startup --param 'M_L=0.06 kN*m' "
         "--units speed=rpm,power=kW --csv run.csv --sample 0.01",
         "mechdyn simulate models/press_cycle.py --scene startup+steady+braking --plot cycle.png"],
        ["--scene A+B+C runs a duty cycle: each phase starts where the one before ended (one "
         "summary, plot and CSV with a phase column)",
         "exit status 1 if the integration fails (the partial trajectory still goes to --csv)"])
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


def _method(text):
    """An argparse type: a method name (``auto``, a solve_ivp method, a kernel's)."""
    from mechdyn.errors import did_you_mean
    from mechdyn.simulate.methods import KERNEL_ONLY
    from mechdyn.simulate.stepping import METHODS
    known = ("auto", *METHODS, *KERNEL_ONLY)
    if text not in known:
        raise argparse.ArgumentTypeError(f"unknown method {text!r}{did_you_mean(text, known)}; "
                                         f"methods: {', '.join(known)}")
    return text


def _add_precision_command(commands):
    from mechdyn.simulate.methods import COMPARED as DEFAULT_METHODS, COMPARED_RTOLS as DEFAULT_RTOLS

    def positive(text):
        value = float(text)
        if not 0 < value < float("inf"):
            raise argparse.ArgumentTypeError(f"{text!r} is not a positive number")
        return value
    precision = command_parser(
        commands, "precision", "work-precision table: error against run time per method",
        "Simulate a scene with each method at each tolerance, compare with a reference (the "
        "closed form where one exists, else DOP853 at rtol 1e-13 checked by Radau) and print "
        "final-state, L2 and event-time errors, run time and solver cost.",
        ["mechdyn precision models/slider_crank.py --scene startup --plot wp.png --target 1e-6"])
    _model_argument(precision)
    _scene_argument(precision)
    _param_argument(precision)
    precision.add_argument("--methods", nargs="+", default=list(DEFAULT_METHODS), type=_method,
                           metavar="METHOD", help="solve_ivp methods or auto (default: "
                           f"{' '.join(DEFAULT_METHODS)})")
    precision.add_argument("--rtols", nargs="+", type=positive, default=list(DEFAULT_RTOLS),
                           metavar="RTOL", help="relative tolerances (default: "
                           f"{' '.join(f'{r:.0e}' for r in DEFAULT_RTOLS)})")
    precision.add_argument("--repeats", type=int, default=3, help="runs per point; the "
                           "time is their minimum (default 3; fewer once they took 1 s, up "
                           "to 5 times more while they take under 0.1 s in all: the runs "
                           "column shows how many)")
    precision.add_argument("--target", type=positive, metavar="ERROR",
                           help="also print the cheapest method and rtol meeting ERROR")
    precision.add_argument("--plot", metavar="FILE.png", help="save the work-precision "
                           "diagram")
    precision.set_defaults(run=_precision)


def _periodic(args):
    from mechdyn.analyse.fluctuation import applies, flywheel, steady_running
    from mechdyn.analyse.periodic import periodic_steady_state
    from mechdyn.errors import SceneError
    if (args.flywheel_for is None) != (args.inertia is None):
        raise SceneError("--flywheel-for DELTA and --inertia NAME go together: the flywheel "
                         "parameter NAME sized for the coefficient of speed fluctuation DELTA")
    model, scene, params = _scene_inputs(args)
    if args.period is None and applies(model.mechanism, scene):
        if args.flywheel_for is not None:
            sized = flywheel(model.mechanism, scene, params, args.flywheel_for,
                             str(model.param_symbol(args.inertia)), cycle=args.cycle,
                             speed_guess=args.speed_guess)
            print(sized.summary())
            solution = sized.running
        else:
            solution = steady_running(model.mechanism, scene, params, cycle=args.cycle,
                                      speed_guess=args.speed_guess)
    else:
        for option, value in (("--flywheel-for", args.flywheel_for),
                              ("--speed-guess", args.speed_guess)):
            if value is not None:
                raise SceneError(f"{option}: scene {scene.name!r} is not run as the steady "
                                 "running of a one-DOF machine free of t (without --period)")
        solution = periodic_steady_state(model.mechanism, scene, params, period=args.period)
    print(solution.summary())
    _plot(solution, args.plot)
    return 0


def _add_periodic_command(commands):
    periodic = command_parser(
        commands, "periodic", "steady periodic motion, Floquet multipliers, speed fluctuation",
        "Find the periodic motion of a scene: under periodic forcing or parametric excitation "
        "(period T: --period, else from the sines and cosines of t), the periodic state, the "
        "swing of every state and the Floquet multipliers; for a one-DOF machine free of t, "
        "steady running over a cycle of its coordinate with the coefficient of speed "
        "fluctuation delta.",
        ["mechdyn periodic models/loom_sley.py --scene run --plot loom.png",
         "mechdyn periodic models/press_flywheel.py --scene steady --param J_f=2",
         "mechdyn periodic models/press_flywheel.py --scene steady --flywheel-for 0.02 "
         "--inertia J_f --speed-guess '98 rpm'"])
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
    periodic.add_argument("--speed-guess", type=_quantity("rad/s", "speed"), metavar="OMEGA",
                          help="steady running: first guess of the speed at the cycle's "
                          "start, rad/s or with a unit ('98 rpm'; default: the scene's "
                          "initial speed)")
    periodic.add_argument("--flywheel-for", type=_fraction, metavar="DELTA",
                          help="steady running: size the flywheel parameter --inertia for "
                          "this coefficient of speed fluctuation (0 < DELTA < 1)")
    periodic.add_argument("--inertia", metavar="NAME", help="the flywheel parameter "
                          "--flywheel-for sizes (it enters the reduced inertia linearly)")
    periodic.add_argument("--plot", metavar="FILE.png", help="save one period as a figure")
    periodic.set_defaults(run=_periodic)


def _fraction(text):
    """An argparse type: a number strictly between 0 and 1 (arithmetic such as 1/50)."""
    from mechdyn.parse import ValueTextError, number
    try:
        value = number(text)
    except ValueTextError as error:
        raise argparse.ArgumentTypeError(str(error)) from None
    if not 0 < value < 1:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number between 0 and 1")
    return value


def _report(args):
    from pathlib import Path

    from mechdyn.report.document import report
    model, scene, params = _scene_inputs(args)
    page = report(model.mechanism, scene, params, precision=args.precision)
    out = args.output or f"{Path(args.model).stem}_{args.scene}.html"
    page.write(out)
    print(f"wrote {out}")
    return exit_status(page.failure and f"simulation failed: {page.failure}")


def _add_report_command(commands):
    report = command_parser(
        commands, "report", "write one HTML page: derivation, scene, results, plots",
        "Write a self-contained HTML page for a scene: the derivation (MathML: no network "
        "needed), the mechanism and its parameters, the scene, the results with events and the "
        "default figure; with --precision also the work-precision table of the integrators.",
        ["mechdyn report models/shoe_brake.py --scene braking -o brake.html",
         "mechdyn report models/motor_startup.py --scene startup --precision"],
        ["exit status 1 if the simulation fails (the page still shows the derivation and the "
         "partial result)"])
    _model_argument(report)
    _scene_argument(report)
    _param_argument(report)
    report.add_argument("-o", "--output", metavar="FILE.html",
                        help="the page to write (default: MODEL_SCENE.html here)")
    report.add_argument("--precision", action="store_true",
                        help="add the work-precision table (runs every integrator at "
                        "several tolerances)")
    report.set_defaults(run=_report)

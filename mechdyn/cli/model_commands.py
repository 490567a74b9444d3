"""Commands over a model or a parameter grid: ``models``, ``sweep``, ``characteristic``,
``animate``.
"""
from __future__ import annotations

import sys
from mechdyn.errors import MechdynError
from mechdyn.cli.arguments import (_model_argument, _param_argument, _params, _plot, _progress_argument, _quantity, _sample_argument, _scene_argument, _scene_inputs, _seconds, _units_argument, _whole_number)
from mechdyn.cli.common import command_parser, exit_status
from mechdyn.cli.arguments import EXIT_OK, EXIT_USAGE
from mechdyn.cli.scene_commands import _progress


def _models(args):
    from pathlib import Path

    from mechdyn.declare.model_file import bundled_folder  # loaded before the forks
    folder = Path(args.folder) if args.folder else bundled_folder()
    if not folder.is_dir():
        raise MechdynError(f"no folder {folder} in {Path.cwd()}; give the folder of "
                           "model files: mechdyn models DIR (without DIR: the models bundled "
                           "with mechdyn)")
    files = sorted(p for p in folder.glob("*.py") if not p.name.startswith("_"))
    if not files:
        raise MechdynError(f"{folder} holds no model files (*.py)")
    broken = 0
    for path in files:
        shown = path if args.folder else Path(path.stem)     # bundled: by name
        ok, text = _in_child(_described, path, shown)
        broken += not ok
        print(text)
    return EXIT_USAGE if broken else EXIT_OK


def _described(path, shown) -> tuple:
    """``(loaded, the listing's line)`` of one model file (run to find its scenes),
    named ``shown`` when it loads."""
    from mechdyn.declare.model_file import load_model
    try:
        model = load_model(path)
    except MechdynError as error:
        reason = " ".join(str(error).split())
        if reason.startswith(str(path)):
            reason = reason[len(str(path)):].lstrip(":, ")
        return False, f"{path}  cannot be loaded: {reason}"
    summary = " ".join(model.doc.split("\n\n")[0].split()) or model.mechanism.name
    return True, f"{shown}  {summary}\n    scenes: {', '.join(model.scenes) or 'none'}"


def _in_child(function, path, *more) -> tuple:
    """``function(path, *more)`` run in a forked child process, so a model file that ends the
    process (``os._exit``), crashes the interpreter or changes its state cannot take
    the listing with it; where there is no fork, in this process."""
    import json
    import os
    if not hasattr(os, "fork"):
        return function(path, *more)
    sys.stdout.flush()
    sys.stderr.flush()
    read, write = os.pipe()
    pid = os.fork()
    if pid == 0:                                   # the child: answer, then leave
        os.close(read)
        try:
            answer = json.dumps(function(path, *more)).encode()
            with os.fdopen(write, "wb") as pipe:
                pipe.write(answer)
            sys.stdout.flush()
            sys.stderr.flush()
        finally:
            os._exit(0)
    os.close(write)
    try:
        with os.fdopen(read, "rb") as pipe:
            answer = pipe.read()
        _, status = os.waitpid(pid, 0)
        pid = None
    finally:
        if pid is not None:                        # interrupted: the child goes too
            os.kill(pid, 9)
            os.waitpid(pid, 0)
    if answer:
        return tuple(json.loads(answer))
    how = (f"exit status {os.WEXITSTATUS(status)}" if os.WIFEXITED(status) else
           f"signal {os.WTERMSIG(status)}")
    return False, (f"{path}  cannot be loaded: the model file ended its process ({how}) "
                   "before defining its mechanism")


def _add_models_command(commands):
    models = command_parser(
        commands, "models", "list model files with their scenes and descriptions",
        "List the model files of a folder: the first line of each file's docstring (its first "
        "paragraph) and its scenes. Each file is run, as `mechdyn simulate` would run it, to "
        "find its scenes: in a child process of its own, so one that fails or ends the process "
        "is listed as broken and the others are still listed. Only list folders whose files you "
        "would run.",
        ["mechdyn models            (the bundled models, by name)",
         "mechdyn models ~/my_machines"])
    models.add_argument("folder", nargs="?", metavar="DIR",
                        help="folder of model files (default: the models bundled with "
                        "mechdyn, which load_model and every command find by name)")
    models.set_defaults(run=_models)


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
                      wait=args.wait, measures=args.measure, steady=args.steady or None,
                      cycle=args.cycle)
    if "reason" in table.columns and not args.measure and _runs_steadily(model, scene):
        print(f"mechdyn: the columns measure a run of scene {scene.name!r} over "
              f"{scene.t_end:g} s; it can run steadily (one DOF, free of t): --steady or "
              "--measure fluctuation sweeps its steady running", file=sys.stderr)
    y = args.y or table.default_y
    if y not in table.columns:
        raise MechdynError(f"--y {y!r}: not a column ({', '.join(table.columns)})")
    measured = table.columns[len(table.parameters):-1]
    if "reason" not in table.columns or args.measure:
        shown = table.parameters + [c for c in measured if c != "reason"]
    else:
        shown = table.parameters + [y] + (["t_end"] if y != "t_end" else [])
    last = "reason or error" if "reason" in table.columns else "error"
    print("  ".join(f"{table.label(c):>14}" for c in shown) + f"  {last}")
    for row in table.rows:
        cells = "  ".join(f"{row[c]:>14.6g}" for c in shown)
        print(f"{cells}  {row['error'] or row.get('reason', '')}".rstrip())
    if args.out:
        print(f"wrote {args.out}")
    _plot(table, args.plot, y)
    return exit_status(table.failed and f"{len(table.failed)} of {len(table)} points failed")


def _runs_steadily(model, scene) -> bool:
    """Whether ``mechdyn periodic`` would run the scene as steady running."""
    from mechdyn.analyse.fluctuation import applies
    return not scene.until and applies(model.mechanism, scene)


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
    sweep = command_parser(
        commands, "sweep", "simulate a scene over a grid of parameter values",
        "Simulate a scene at every point of a parameter grid (all combinations of the --grid "
        "axes), deriving and compiling once. Rows stream to --out as points finish; rerun with "
        "the same --out to resume after an interruption.",
        ["mechdyn sweep models/shoe_brake.py --scene braking --grid P=10:100:10 --plot stop.png",
         "mechdyn sweep models/hoist_drive.py --scene lift_start --grid E_k=2e6:8e6:4 --grid "
         "d_r=500,1100 --y peak:rope --out hoist.csv --workers 2",
         "mechdyn sweep models/shoe_brake.py --scene braking --grid P=10:100:1000 --dask "
         "tcp://scheduler:8786 --out brake.csv",
         "mechdyn sweep models/press_flywheel.py --scene steady --grid J_f=0.5:4:8 "
         "--measure fluctuation --measure mean_speed --measure peak:motor"],
        ["columns: the swept parameters, then the measures (default t_end, final:STATE per "
         "coordinate and speed, peak:OUTPUT per output), reason, error",
         "measures (--measure): mean_speed, fluctuation, cycle_time (steady running), "
         "peak:OUTPUT, rms:OUTPUT, energy:ELEMENT (per run or steady cycle; energy needs the "
         "scene's output power:ELEMENT), t_end, stop_angle, final:STATE (per run)",
         "a sweep measures steady running (one cycle per point) with --steady or a measure "
         "of steady running; its default measures are mean_speed, fluctuation and the "
         "peaks over the cycle, shown: fluctuation",
         "exit status 1 if any point failed (its row holds the error; the others are kept)"])
    _model_argument(sweep)
    _scene_argument(sweep)
    sweep.add_argument("--grid", action="append", required=True,
                       metavar="NAME=START:STOP:COUNT",
                       help="a swept parameter: COUNT evenly spaced values, or NAME=V1,V2,...; "
                       "repeatable (full factorial)")
    _param_argument(sweep)
    where = sweep.add_mutually_exclusive_group()
    where.add_argument("--workers", type=_whole_number, metavar="N",
                       help="local worker processes (default: this process for the "
                       "first second, then one process per core)")
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
    sweep.add_argument("--measure", action="append", metavar="NAME",
                       help="a measure, a column each (fluctuation, peak:motor, "
                       "energy:brake, ...; see below); repeatable")
    sweep.add_argument("--steady", action="store_true",
                       help="measure steady running (a one-DOF machine free of t, without "
                       "until) instead of a run; implied by mean_speed, fluctuation and "
                       "cycle_time")
    sweep.add_argument("--cycle", type=_quantity("rad", "cycle"), default="2*pi",
                       metavar="PHI", help="steady running's cycle of the coordinate "
                       "(default 2*pi)")
    sweep.add_argument("--y", metavar="COLUMN", help="the column to plot (default: the "
                       "first --measure; fluctuation for steady running; else t_end if "
                       "the scene stops, else the first peak)")
    sweep.set_defaults(run=_sweep)


def _characteristic(args):
    from mechdyn.analyse.characteristics import characteristic
    from mechdyn.declare.model_file import load_model
    model = load_model(args.model)
    scene = model.scene(args.scene) if args.scene else None
    curves = characteristic(model.mechanism, scene, _params(model, scene, args.param),
                            drive=args.drive)
    print(curves.summary(args.units))
    _plot(curves, args.plot, units=args.units)
    return EXIT_OK


def _add_characteristic_command(commands):
    command = command_parser(
        commands, "characteristic", "motor and load characteristics, operating points, stability",
        "Draw the drive's moment M(omega) against the reduced moment of the load (the mean over "
        "a cycle where it depends on the position) for a one-DOF machine, and list the "
        "operating points where they balance: stable where dM_motor/domega < dM_load/domega.",
        ["mechdyn characteristic models/motor_startup.py --scene startup --plot ml.png",
         "mechdyn characteristic models/press_flywheel.py --scene steady --units speed=rpm "
         "--plot press.png"])
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
            progress.until = " or ".join(map(repr, scene.until))
        result = model.mechanism.simulate(scene, params, progress=progress)
    film = animate(model.mechanism, result, params, args.out, sample=args.sample,
                   fps=args.fps)
    print(f"wrote {film.path}: {film.frames} frames, every {film.times[1] - film.times[0]:.4g} "
          f"s of the motion at {film.fps:g} frames per second" if film.frames > 1 else
          f"wrote {film.path}: 1 frame")
    return EXIT_OK


def _add_animate_command(commands):
    command = command_parser(
        commands, "animate", "draw the links over the simulated motion into a GIF",
        "Simulate a scene and draw its links (their declared points, or the centre of mass with "
        "a tick along the link's angle) frame by frame into a GIF: one frame per --sample "
        "seconds of the motion (default 1/fps: real time).",
        ["mechdyn animate models/slider_crank.py --scene startup --out crank.gif",
         "mechdyn animate models/scotch_yoke.py --scene startup --out yoke.gif --sample 0.01 "
         "--fps 20"])
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

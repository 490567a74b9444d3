"""``mechdyn linkage``: the kinematics (and, with --omega, the kinetostatics) of a model
with closed loops over one crank revolution.

    mechdyn linkage models/fourbar_flywheel.py --plot fourbar.png
    mechdyn linkage models/fourbar_flywheel.py --omega 30 --drive motor --forces f.png
"""
from __future__ import annotations

import numpy as np

__all__ = ["add_linkage_command"]


def _linkage(args):
    from mechdyn.cli.arguments import _params
    from mechdyn.analyse.joint_reactions import kinetostatics
    from mechdyn.analyse.linkage import Linkage
    from mechdyn.analyse.linkage_plots import revolution
    from mechdyn.declare.model_file import load_model
    model = load_model(args.model)
    scene = model.scene(args.scene) if args.scene else next(iter(model.scenes.values()), None)
    params = _params(model, scene, args.param)
    if args.drive is not None:                          # refused before the analysis
        _check_drive(model.mechanism, args.drive)
    linkage = Linkage(model.mechanism, params, scene=scene)
    print(linkage.describe(points=args.points))
    if args.plot:
        linkage.plot(args.plot, points=args.points, paths=model.points)
        print(f"wrote {args.plot}")
    if args.omega is None:
        return 0
    angles = revolution(linkage, args.points).phi
    result = kinetostatics(model.mechanism, params, angles, omega=args.omega,
                           drive=args.drive, scene=scene,
                           guess=dict(zip(model.mechanism.coordinates,
                                          linkage.position(angles[0]))))
    driving = result.driving[:-1] if np.isclose(angles[-1] - angles[0], 2 * np.pi) \
        else result.driving
    print(f"  at omega = {args.omega:g} rad/s: driving moment mean {np.mean(driving):.6g}, "
          f"peak {driving[np.argmax(np.abs(driving))]:.6g}, rms "
          f"{np.sqrt(np.mean(driving ** 2)):.6g}")
    for name, reaction in result.reactions.items():
        if reaction.kind == "weld":
            values, what, unit = np.abs(reaction.moment), "moment", "N m"
        else:
            values, what, unit = reaction.magnitude, "force", "N"
        peak = int(np.argmax(values))
        print(f"  joint {name} ({reaction.kind}): peak {what} {values[peak]:.6g} {unit} at "
              f"{np.degrees(angles[peak]) % 360:.1f} deg")
    shaking = np.hypot(*result.shaking_force)
    print(f"  shaking force peak {shaking.max():.6g} N, shaking moment peak "
          f"{np.max(np.abs(result.shaking_moment)):.6g} N m")
    if args.forces:
        result.plot(args.forces)
        print(f"wrote {args.forces}")
    return 0


def _check_drive(mechanism, drive):
    from mechdyn.declare.elements import Load
    from mechdyn.errors import MechdynError, did_you_mean
    loads = [e for e in mechanism.elements.values() if isinstance(e, Load)]
    names = [e.name for e in loads] + sorted({tag for e in loads for tag in e.tags})
    if drive not in names:
        raise MechdynError(f"--drive {drive!r}: no load named or tagged so"
                           f"{did_you_mean(drive, names)}; loads: "
                           f"{', '.join(e.name for e in loads) or 'none'}")


def add_linkage_command(commands):
    from mechdyn.cli.arguments import _model_argument, _param_argument
    from mechdyn.cli.common import command_parser
    from mechdyn.parse import number
    linkage = command_parser(
        commands, "linkage", "closed loops: transmission functions, I_red, toggles, joint forces",
        "Kinematics of a model with closed loops over one crank revolution: Grashof's class "
        "(four-bars), the crank's range, toggle positions and change points, the dependent "
        "coordinates' extreme positions (swing, time ratio), the range of I_red and of the "
        "transmission angle. With --omega also the kinetostatics at that crank speed: driving "
        "moment, joint forces, shaking force.",
        ["mechdyn linkage models/fourbar_flywheel.py --plot fourbar.png",
         "mechdyn linkage models/fourbar_flywheel.py --omega 30 --drive motor --forces "
         "forces.png"])
    _model_argument(linkage)
    linkage.add_argument("--scene", metavar="NAME", help="scene whose loads and initial "
                         "guesses (the assembly branch) to use (default: the first)")
    _param_argument(linkage)
    linkage.add_argument("--points", type=int, default=361,
                         help="crank positions over the revolution (default 361)")
    linkage.add_argument("--plot", metavar="FILE.png", help="transmission functions, "
                         "I_red, transmission angle and coupler curves")
    linkage.add_argument("--omega", type=number, metavar="W",
                         help="uniform crank speed (rad/s) for the kinetostatics")
    linkage.add_argument("--drive", metavar="LOAD", help="the load that drives (its value "
                         "is solved for); default: a moment on the crank")
    linkage.add_argument("--forces", metavar="FILE.png", help="joint forces, driving "
                         "moment, shaking force (with --omega)")
    linkage.set_defaults(run=_linkage)

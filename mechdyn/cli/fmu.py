"""``mechdyn fmu``: a scene as an FMI 2.0 Model Exchange FMU.

    mechdyn fmu models/motor_startup.py --scene startup --out motor.fmu
    mechdyn fmu models/press_cycle.py --scene startup+steady --out steady.fmu
"""
from __future__ import annotations

__all__ = ["add_fmu_command"]


def _fmu(args):
    from mechdyn.cli.arguments import _params
    from mechdyn.declare.model_file import load_model
    from mechdyn.report.fmu import export_fmu
    model = load_model(args.model)
    *earlier, last = args.scene.split("+")
    scene = model.scene(last)
    for name in earlier:
        model.scene(name)                       # every phase named exists, before any run
    start = None
    for name in earlier:                        # a later phase starts where these end
        phase = model.scene(name)
        start = model.mechanism.simulate(phase, _params(model, phase, args.param),
                                         start=start).y[:, -1]
    params = _params(model, scene, args.param)
    path = export_fmu(model.mechanism, scene, params, args.out, inputs=args.input or (),
                      start=start)
    print(f"wrote {path}")
    return 0


def add_fmu_command(commands):
    from mechdyn.cli.arguments import _model_argument, _param_argument
    from mechdyn.cli.common import command_parser
    fmu = command_parser(
        commands, "fmu", "export a scene as an FMI 2.0 Model Exchange FMU",
        "Export one scene of a model file as an FMU (FMI 2.0 Model Exchange): states are the "
        "coordinates and speeds, parameters the scene's parameters (start values from the model "
        "and --param), outputs the scene's outputs and the energies; the binary is built for "
        "this platform with the C compiler ($CC, cc, gcc or clang), its C source is included. "
        "Scenes with friction, stops or closed loops are refused.",
        ["mechdyn fmu models/motor_startup.py --scene startup --out motor.fmu",
         "mechdyn fmu models/press_cycle.py --scene startup+steady --out steady.fmu"],
        ["--scene A+B exports B starting where A ends (A is simulated first)",
         "--input NAME makes a parameter (or the one-symbol value of a load NAME) an input",
         "exit status 2 if the scene cannot be exported (the message names why)"])
    _model_argument(fmu)
    fmu.add_argument("--scene", required=True, metavar="NAME",
                     help="scene name, or A+B: scene B starting where A ends")
    fmu.add_argument("--out", required=True, metavar="FILE.fmu", help="the FMU to write")
    fmu.add_argument("--input", action="append", metavar="NAME",
                     help="a parameter, or a load whose value is one parameter, that the FMU "
                     "reads as an input (e.g. a motor moment from a controller); repeatable")
    _param_argument(fmu)
    fmu.set_defaults(run=_fmu)

"""A scene of a mechanism as an FMI 2.0 Model Exchange FMU: :func:`export_fmu`."""
from mechdyn.report.fmu.build import FmuCompilerError, FmuError
from mechdyn.report.fmu.export import export_fmu

__all__ = ["export_fmu", "FmuError", "FmuCompilerError"]

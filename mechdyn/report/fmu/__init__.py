"""A scene of a mechanism as an FMI 2.0 Model Exchange FMU: :func:`export_fmu`
(:mod:`~mechdyn.report.fmu.export`), the C of its equations
(:mod:`~mechdyn.report.fmu.model_code`, :mod:`~mechdyn.report.fmu.c_code`), the FMI
glue and declarations (``fmi2_glue.c``, ``fmi2_header.h``), ``modelDescription.xml``
(:mod:`~mechdyn.report.fmu.description`) and the build (:mod:`~mechdyn.report.fmu.build`).

>>> import tempfile, zipfile, mechdyn as md
>>> model = md.load_model("models/gear_pair.py")
>>> path = export_fmu(model.mechanism, model.scenes["startup"], model.params,
...                   tempfile.mkdtemp() + "/gears.fmu")
>>> sorted(n for n in zipfile.ZipFile(path).namelist() if not n.startswith("binaries"))
['modelDescription.xml', 'sources/fmi2_glue.c', 'sources/fmi2_header.h', 'sources/model.c']
"""
from mechdyn.report.fmu.build import FmuCompilerError, FmuError
from mechdyn.report.fmu.export import export_fmu

__all__ = ["export_fmu", "FmuError", "FmuCompilerError"]

"""Building an FMU: the shared library compiled from its C sources with the system C
compiler, and the archive written whole or not at all (a temporary file in the target's
folder, renamed over it when complete)."""
from __future__ import annotations

import os
import platform
import shutil
import struct
import subprocess
import sys
import tempfile
import zipfile
from pathlib import Path

from mechdyn.atomic import replacing
from mechdyn.errors import MechdynError

__all__ = ["FmuError", "FmuCompilerError", "find_compiler", "platform_folder", "build_fmu"]

HERE = Path(__file__).resolve().parent
STATIC_SOURCES = ("fmi2_glue.c", "fmi2_header.h")


class FmuError(MechdynError):
    """A mechanism or scene that cannot be exported as an FMU (the message names why).

    Examples
    --------
    >>> import mechdyn as md
    >>> model = md.load_model("shoe_brake")
    >>> try:
    ...     model.mechanism.export_fmu(model.scenes["braking"], model.params, "brake.zip")
    ... except md.FmuError as error:
    ...     print(error)
    brake.zip: an FMU's file name ends in .fmu
    """


class FmuCompilerError(FmuError):
    """No C compiler to build the FMU's binary, or the build failed.

    Examples
    --------
    Without a C compiler on the ``PATH`` (and no ``CC``), before anything is derived:

    >>> import mechdyn as md
    >>> model = md.load_model("shoe_brake")
    >>> import os
    >>> from unittest import mock
    >>> with mock.patch.dict(os.environ, {"PATH": "", "CC": ""}):
    ...     try:
    ...         model.mechanism.export_fmu(model.scenes["braking"], model.params, "brake.fmu")
    ...     except md.FmuCompilerError as error:
    ...         print(type(error).__name__, isinstance(error, md.FmuError))
    FmuCompilerError True
    """


def find_compiler() -> str:
    """The C compiler: ``$CC``, else ``cc``, ``gcc`` or ``clang`` on the PATH."""
    for name in filter(None, (os.environ.get("CC"), "cc", "gcc", "clang")):
        found = shutil.which(name)
        if found:
            return found
    raise FmuCompilerError(
        "exporting an FMU needs a C compiler to build its binary, and none was found "
        "(looked for $CC, cc, gcc, clang): install one (e.g. `apt install gcc`, "
        "Xcode's command line tools) or set CC")


def platform_folder() -> tuple:
    """``(binaries folder, library suffix)`` of this platform in FMI 2.0's naming."""
    bits = "64" if struct.calcsize("P") == 8 else "32"
    if sys.platform.startswith("linux"):
        return f"linux{bits}", ".so"
    if sys.platform == "darwin":
        return f"darwin{bits}", ".dylib"
    if sys.platform.startswith("win"):
        return f"win{bits}", ".dll"
    raise FmuCompilerError(f"no FMI 2.0 platform name for {sys.platform} "
                           f"({platform.machine()})")


def build_fmu(path, identifier: str, model_source: str, description: str,
              documentation: str = "") -> Path:
    """Compile ``model_source`` (with the glue) and write the FMU archive ``path``:
    ``modelDescription.xml``, ``binaries/<platform>/<identifier>.<so>``, ``sources/``
    (the C to build it elsewhere) and ``documentation/``."""
    path = Path(path)
    compiler = find_compiler()
    folder, suffix = platform_folder()
    with tempfile.TemporaryDirectory(prefix="mechdyn-fmu-") as work:
        sources = Path(work) / "sources"
        sources.mkdir()
        (sources / "model.c").write_text(model_source)
        for name in STATIC_SOURCES:
            shutil.copyfile(HERE / name, sources / name)
        library = Path(work) / f"{identifier}{suffix}"
        command = [compiler, "-shared", "-fPIC", "-O2", "-fvisibility=hidden",
                   "-o", str(library), str(sources / "model.c"), "-lm"]
        done = subprocess.run(command, capture_output=True, text=True)
        if done.returncode != 0 or not library.exists():
            raise FmuCompilerError(f"the C compiler ({' '.join(command)}) failed:\n"
                                   f"{(done.stderr or done.stdout).strip()[-2000:]}")
        with replacing(path, "wb") as handle, \
                zipfile.ZipFile(handle, "w", zipfile.ZIP_DEFLATED) as archive:
            archive.writestr("modelDescription.xml", description)
            archive.write(library, f"binaries/{folder}/{library.name}")
            for source in sorted(sources.iterdir()):
                archive.write(source, f"sources/{source.name}")
            if documentation:
                archive.writestr("documentation/index.html", documentation)
    return path

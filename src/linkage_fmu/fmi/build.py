"""Build the FMUs of any linkage (a preset, a description file, a Description or a
Mechanism built from one), in two flavours over one C framework:

- :func:`build_fmu`, the pythonfmu FMU: the installed ``linkage_fmu`` package, the
  linkage's description file and a slave script in its resources; its binary is the
  framework (``framework.c``) with ``backend_pythonfmu.c``, in front of pythonfmu's stock
  wrapper, shipped beside it. The importing process runs the package in its Python.
- :func:`build_native_fmu`, the native FMU: the linkage's traced kernels in C
  (``model.c``) with ``backend_native.c``; no Python in the importing process. It holds
  its C in ``sources/`` and computes the closed form only (``method`` is ``closed_form``).

Each is FMI 2.0 (``fmi2.c``) or FMI 3.0 (``fmi3.c``) co-simulation, compiled with the
system C compiler. Everything generated comes from the linkage's variable table through
the writers of :mod:`~linkage_fmu.fmi.writers`.

Examples
--------
>>> platform(2), platform(3)
('linux64', 'x86_64-linux')
"""

from __future__ import annotations

import hashlib
import shutil
import sysconfig
import tempfile
import uuid
import zipfile
from pathlib import Path

from .. import ranges
from ..ccompiler import compile_shared
from ..errors import AssemblyError
from ..presets import linkage
from . import writers
from .slave import PACKAGE, fingerprint

HERE = Path(__file__).parent
#: the framework and its backends, as shipped in the package
FRAMEWORK = ("framework.h", "framework.c")
#: the FMI headers (from fmpy) each adapter includes
HEADERS = {2: ("fmi2Functions.h", "fmi2FunctionTypes.h", "fmi2TypesPlatform.h"),
           3: ("fmi3Functions.h", "fmi3FunctionTypes.h", "fmi3PlatformTypes.h")}
#: FMI 2.0's and 3.0's name of this platform
PLATFORMS = {2: "linux64", 3: "x86_64-linux"}
#: flags of every FMU binary: IEEE operations as written, only the FMI functions exported
FLAGS = ("-O2", "-ffp-contract=off", "-fno-math-errno", "-fvisibility=hidden")
WRAPPED_LIBRARY = "libpythonfmu-export.so"


def platform(fmi_version: int) -> str:
    """The name of this platform's binaries folder in an FMU of ``fmi_version``."""
    return PLATFORMS[fmi_version]


def fmi_headers() -> Path:
    """The folder of the FMI headers that fmpy ships."""
    import fmpy

    return Path(fmpy.__file__).parent / "c-code"


def _check_version(fmi_version: int) -> None:
    if fmi_version not in (2, 3):
        raise ValueError(f"fmi_version must be 2 or 3, got {fmi_version!r}")


def _stage_sources(folder: Path, mech, flavour: str, fmi_version: int, guid: str,
                   defines: dict | None = None) -> Path:
    """Write into ``folder`` the C of the FMU: the adapter, the framework, the backend,
    ``config.h`` and the FMI headers; return the adapter's path."""
    folder.mkdir(parents=True, exist_ok=True)
    adapter = f"fmi{fmi_version}.c"
    for name in (adapter, *FRAMEWORK, f"backend_{flavour}.c"):
        shutil.copy(HERE / name, folder / name)
    # the pythonfmu backend talks to an FMI 2.0 wrapper, whatever the FMU's version
    for name in {*HEADERS[fmi_version], *(HEADERS[2] if flavour == "pythonfmu" else ())}:
        shutil.copy(fmi_headers() / name, folder / name)
    (folder / "config.h").write_text(writers.config_header(mech, flavour, guid, defines))
    return folder / adapter


def _archive(root: Path, target: Path) -> Path:
    """Zip the folder ``root`` into ``target`` (written whole, or not at all)."""
    target.parent.mkdir(parents=True, exist_ok=True)
    staged = root.parent / "staged.fmu"
    with zipfile.ZipFile(staged, "w", zipfile.ZIP_DEFLATED) as archive:
        for path in sorted(root.rglob("*")):
            if path.is_file():
                archive.write(path, path.relative_to(root).as_posix())
    return Path(shutil.move(staged, target))


def _assembling(source, parameters: dict):
    """The description (its defaults the parameters given) and linkage of an FMU; a
    ValueError, saying why at theta = 0, if the linkage assembles at no crank angle."""
    mech = linkage(source, **parameters)
    d = mech.description.with_defaults(mech.parameters)
    mech = d.build()
    if not ranges.assembles(mech):
        try:
            mech.kinematics(0.0, order=0)
            why = ""
        except AssemblyError as err:
            why = f" ({err.condition} at theta = 0)"
        raise ValueError(f"{d.name} cannot be assembled at any crank angle{why}, so it has no "
                         "FMU; change its lengths")
    return d, mech


def build_fmu(source, out: str | Path = "dist", fmi_version: int = 2, **parameters) -> Path:
    """Build ``out/<model>.fmu``, the pythonfmu FMU of the linkage ``source`` (see
    :func:`~linkage_fmu.presets.linkage`), and return its path; the model identifier is
    the description's ``model``.

    Raises
    ------
    DescriptionError, TypeError, ValueError
        The description or a parameter is invalid, or the linkage assembles at no crank
        angle (one that assembles over part of a revolution is built: its FMU discards
        the steps at the other angles; :func:`~linkage_fmu.ranges.assembles` says where).
    CompilerError
        No C compiler for the framework (nothing is written to ``out`` then).
    """
    import pythonfmu

    _check_version(fmi_version)
    d, mech = _assembling(source, parameters)
    guid = str(uuid.uuid4())
    # a module name of its own: the host's Python keeps one module per name
    module = f"linkage_fmu_{d.model}_{hashlib.sha256(guid.encode()).hexdigest()[:12]}"
    wrapper = Path(pythonfmu.__file__).parent / "resources" / "binaries" / "linux64" / WRAPPED_LIBRARY
    with tempfile.TemporaryDirectory(prefix="linkage_fmu_build_") as tmp:
        root = Path(tmp) / "fmu"
        resources = root / "resources"
        binaries = root / "binaries" / platform(fmi_version)
        binaries.mkdir(parents=True)
        ignore = shutil.ignore_patterns("__pycache__", "*.pyc")
        shutil.copytree(PACKAGE, resources / "linkage_fmu", ignore=ignore)
        (resources / "pythonfmu").mkdir()
        for module_file in Path(pythonfmu.__file__).parent.glob("*.py"):  # as pythonfmu's builder
            shutil.copy(module_file, resources / "pythonfmu" / module_file.name)
        description = f"{d.model}.toml"
        (resources / description).write_text(d.to_toml(), encoding="utf-8")
        (resources / f"{module}.py").write_text(
            writers.slave_script(mech, description, fingerprint(PACKAGE)))
        (resources / "slavemodule.txt").write_text(module)
        (root / "modelDescription.xml").write_bytes(
            writers.model_description(mech, "pythonfmu", fmi_version, guid))
        shutil.copy(wrapper, binaries / WRAPPED_LIBRARY)
        defines = {"WRAPPED_LIBRARY": writers.c_string(WRAPPED_LIBRARY),
                   "PYTHON_VERSION": writers.c_string(sysconfig.get_python_version()),
                   "SLAVE_MODULE": writers.c_string(module)}
        adapter = _stage_sources(Path(tmp) / "src", mech, "pythonfmu", fmi_version, guid, defines)
        include, extra = [adapter.parent], ["_GNU_SOURCE"]  # dladdr
        python_include = Path(sysconfig.get_paths()["include"])
        if (python_include / "Python.h").is_file():
            # without Python's headers the framework cannot start Python itself; the
            # wrapper then does, and a host with a broken Python exits in instantiation
            include.append(python_include)
            extra.append("GUARD_PYTHON_INIT")
        compile_shared([adapter], binaries / f"{d.model}.so", include=include, defines=extra,
                       flags=FLAGS, libraries=["dl", "m", "pthread"])
        return _archive(root, Path(out) / f"{d.model}.fmu")


def build_native_fmu(source, out: str | Path | None = None, fmi_version: int = 2,
                     **parameters) -> Path:
    """Build ``out/<model>.fmu``, the native FMU of the linkage ``source`` (see
    :func:`~linkage_fmu.presets.linkage`), for FMI 2.0 (default ``out``: ``dist/native``)
    or FMI 3.0 (``dist/native3``), and return its path.

    Its binary holds one kernel per structure: every combination of the branch and
    choice parameters, each traced from the linkage's description, so that those
    parameters stay settable; the real-valued parameters are arguments of the kernels'
    parameter step, run when the FMU takes a parameter set.

    Raises
    ------
    DescriptionError, TypeError, ValueError
        The description or a parameter is invalid, or the linkage assembles at no crank
        angle (one that assembles over part of a revolution is built, as by
        :func:`build_fmu`).
    CompilerError
        No C compiler (nothing is written to ``out`` then).
    """
    _check_version(fmi_version)
    d, mech = _assembling(source, parameters)
    model_c, _ = writers.model_source(mech, d.build)
    guid = str(uuid.uuid4())
    out = Path(out or ("dist/native" if fmi_version == 2 else "dist/native3"))
    with tempfile.TemporaryDirectory(prefix="linkage_fmu_native_") as tmp:
        root = Path(tmp) / "fmu"
        sources = root / "sources"
        adapter = _stage_sources(sources, mech, "native", fmi_version, guid)
        (sources / "model.c").write_text(model_c)
        if fmi_version == 3:  # FMI 3.0 lists the sources here, not in the modelDescription
            (sources / "buildDescription.xml").write_bytes(writers.build_description(d.model))
        (root / "resources").mkdir()
        (root / "resources" / f"{d.model}.toml").write_text(d.to_toml(), encoding="utf-8")
        (root / "modelDescription.xml").write_bytes(writers.model_description(
            mech, "native", fmi_version, guid, (adapter.name,) if fmi_version == 2 else ()))
        binaries = root / "binaries" / platform(fmi_version)
        binaries.mkdir(parents=True)
        compile_shared([adapter], binaries / f"{d.model}.so", include=[sources], flags=FLAGS,
                       libraries=["m"])
        return _archive(root, out / f"{d.model}.fmu")

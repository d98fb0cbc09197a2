"""Build the FMUs of any linkage (a preset, a description file, a Description or a
Mechanism built from one), in two flavours over one C framework:

- :func:`build_fmu`, the pythonfmu FMU: the installed ``linkage_fmu`` package, the
  linkage's description file and a slave script in its resources; its binary is the
  framework (``framework.c``) with ``backend_pythonfmu.c``, in front of pythonfmu's stock
  wrapper, shipped beside it. The importing process runs the package in its Python.
- :func:`build_native_fmu`, the native FMU: the linkage's traced kernels in C
  (``model.c``) with ``backend_native.c``; no Python in the importing process. It holds
  its C in ``sources/`` and computes the closed form only (``method`` is ``closed_form``).
  With ``drive``, the drive FMU ``<Model>Drive``: the linkage driven by a moment on its
  crank, its continuous states integrated by the framework (``continuous.c``) in
  co-simulation, or by the importer in model exchange.

Each is FMI 2.0 (``fmi2.c``) or FMI 3.0 (``fmi3.c``) co-simulation (the drive FMU model
exchange too). Every binary is
built by :func:`compile_for`, for one platform of :mod:`~linkage_fmu.fmi.platforms`: this
machine's with the system C compiler, any other with zig's (the ``cross`` extra), and
checked (format, processor, and only the FMI functions exported) before it goes into the
FMU. The pythonfmu FMU is for ``linux64`` only (pythonfmu's wrapper is); the native one
for this machine's platform, or for those asked for (``platforms``). Everything generated
comes from the linkage's variable table through the writers of
:mod:`~linkage_fmu.fmi.writers`.
"""

from __future__ import annotations

import hashlib
import os
import shutil
import sysconfig
import tempfile
import uuid
import zipfile
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

from .. import ranges
from ..ccompiler import CompilerError, compile_shared, find_compiler
from ..errors import AssemblyError, InputError
from ..presets import linkage
from . import binaries, writers
from .platforms import PLATFORMS, ZIG_FLAGS, Platform, folders, host, select
from .slave import PACKAGE, fingerprint

HERE = Path(__file__).parent
#: the framework and its backends, as shipped in the package
FRAMEWORK = ("framework.h", "framework.c", "continuous.c")
#: the FMI headers (from fmpy) each adapter includes
HEADERS = {2: ("fmi2Functions.h", "fmi2FunctionTypes.h", "fmi2TypesPlatform.h"),
           3: ("fmi3Functions.h", "fmi3FunctionTypes.h", "fmi3PlatformTypes.h")}
#: flags of every FMU binary: IEEE operations as written, only the FMI functions exported
FLAGS = ("-ffp-contract=off", "-fno-math-errno", "-fvisibility=hidden")
WRAPPED_LIBRARY = "libpythonfmu-export.so"
#: the platform of the pythonfmu FMU's binaries: that of pythonfmu's wrapper
PYTHONFMU_PLATFORM = "x86_64-linux"
#: functions a binary of each FMI version must export
REQUIRED = {2: ("fmi2Instantiate", "fmi2DoStep", "fmi2GetReal", "fmi2FreeInstance"),
            3: ("fmi3InstantiateCoSimulation", "fmi3DoStep", "fmi3GetFloat64",
                "fmi3FreeInstance")}


def fmi_headers() -> Path:
    """The folder of the FMI headers that fmpy ships."""
    import fmpy

    return Path(fmpy.__file__).parent / "c-code"


def _check_version(fmi_version: int) -> None:
    if fmi_version not in (2, 3):
        raise InputError(f"fmi_version must be 2 or 3, got {fmi_version!r}")


def _stage_sources(folder: Path, mech, flavour: str, fmi_version: int, guid: str,
                   defines: dict | None = None, drive: bool = False) -> Path:
    """Write into ``folder`` the C of the FMU: the adapter, the framework, the backend,
    ``config.h`` and the FMI headers; return the adapter's path."""
    folder.mkdir(parents=True, exist_ok=True)
    adapter = f"fmi{fmi_version}.c"
    for name in (adapter, *FRAMEWORK, f"backend_{flavour}.c"):
        shutil.copy(HERE / name, folder / name)
    # the pythonfmu backend talks to an FMI 2.0 wrapper, whatever the FMU's version
    for name in {*HEADERS[fmi_version], *(HEADERS[2] if flavour == "pythonfmu" else ())}:
        shutil.copy(fmi_headers() / name, folder / name)
    (folder / "config.h").write_text(writers.config_header(mech, flavour, guid, defines, drive))
    return folder / adapter


def compile_for(target: Platform, sources: list[Path], output: Path, fmi_version: int,
                include: list[Path], defines: list[str] | None = None,
                libraries: tuple[str, ...] = (), level: str = "-O2") -> Path:
    """Compile an FMU's C ``sources`` into the library ``output`` for ``target``: with the
    system C compiler if ``target`` is this machine's platform and it has one, else with
    zig's; then check that ``output`` is a library of ``target``'s format and processor
    that exports the FMI ``fmi_version`` functions and nothing else. ``level`` is the
    optimisation flag.

    Raises
    ------
    CompilerError
        No compiler (zig's for another platform: the message names the ``cross`` extra),
        the compiler failed, or the library is not as it must be (a compiler's warnings
        are logged, not shown: :func:`~linkage_fmu.ccompiler.compile_shared`).

    Examples
    --------
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     source = Path(tmp) / "none.c"
    ...     _ = source.write_text("int fmi2Nothing(void) { return 0; }")
    ...     try:
    ...         compile_for(host(), [source], Path(tmp) / "none.so", 2, include=[])
    ...     except CompilerError as err:
    ...         print(str(err).split(": ")[1].split(";")[0])
    fmi2Instantiate is not exported
    """
    here = target == host() and find_compiler() is not None
    output.parent.mkdir(parents=True, exist_ok=True)
    compile_shared(sources, output, include=include, defines=defines or (),
                   flags=(level, *FLAGS, *target.flags, *(() if here else ZIG_FLAGS)),
                   libraries=(*target.libraries, *libraries),
                   target=None if here else target.zig)
    wrong = binaries.problems(output, target.format, [target.machine], f"fmi{fmi_version}",
                              REQUIRED[fmi_version])
    if wrong:
        raise CompilerError(f"{output.name} built for {target.name} is wrong: "
                            f"{'; '.join(wrong)}")
    return output


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
    mech = d.fmu_build()
    if mech.rates:  # driven by time: it must assemble where its drivers start
        start = tuple(float(mech.start[dr.inputs[0]]) for dr in mech.drivers)
        try:
            mech.kinematics(start, order=0, rates=tuple((0.0, 0.0) for _ in start))
        except AssemblyError as err:
            raise InputError(f"{d.name} cannot be assembled where its drivers start, so it "
                             f"has no FMU: {err.condition}") from None
    elif not ranges.assembles(mech):
        try:
            mech.kinematics(0.0, order=0)
            why = ""
        except AssemblyError as err:
            why = f" ({err.condition} at theta = 0)"
        raise InputError(f"{d.name} cannot be assembled at any crank angle{why}, so it has no "
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
    wrapper = (Path(pythonfmu.__file__).parent / "resources" / "binaries" / "linux64"
               / WRAPPED_LIBRARY)
    with tempfile.TemporaryDirectory(prefix="linkage_fmu_build_") as tmp:
        root = Path(tmp) / "fmu"
        resources = root / "resources"
        linux = PLATFORMS[PYTHONFMU_PLATFORM]
        folder = root / "binaries" / linux.folder(fmi_version)
        folder.mkdir(parents=True)
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
        shutil.copy(wrapper, folder / WRAPPED_LIBRARY)
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
        compile_for(linux, [adapter], folder / linux.library(d.model), fmi_version,
                    include=include, defines=extra, libraries=("dl", "pthread"))
        return _archive(root, Path(out) / f"{d.model}.fmu")


def build_native_fmu(source, out: str | Path | None = None, fmi_version: int = 2,
                     platforms: str | list[str] | None = None, drive: bool = False,
                     **parameters) -> Path:
    """Build ``out/<model>.fmu``, the native FMU of the linkage ``source`` (see
    :func:`~linkage_fmu.presets.linkage`), for FMI 2.0 (default ``out``: ``dist/native``)
    or FMI 3.0 (``dist/native3``), and return its path.

    With ``drive``, build ``out/<model>Drive.fmu``, the drive FMU: co-simulation and
    model exchange of the linkage driven by the moment ``tau`` on its crank (inputs
    ``tau`` and the loads; continuous states ``theta`` and ``omega``, from the
    parameters ``theta0`` and ``omega0``; outputs ``alpha``, every output of the
    linkage and ``J_red``), with the friction of its joints (``mu`` and the radii are
    parameters): at rest the crank sticks while tau lies in the friction band, and
    leaves it the way tau crosses it. In co-simulation it integrates its motion over
    each step to the parameter ``tolerance``, stops located inside the step; in model
    exchange the stops and starts are state events (its event indicators and the
    discrete state ``motion``). Its structures are those whose balancing effort is a
    moment on the crank (the six-bar's ``driver`` takes only ``OA``).

    Its binaries are for this machine's platform (``platforms`` None), for ``"all"`` the
    FMI version names (FMI 2.0: ``linux64``, ``win64``, ``darwin64``, this one universal,
    x86_64 and arm64; FMI 3.0 also ``aarch64-linux``, and one folder per Mac), or for the
    platforms named (see :func:`~linkage_fmu.fmi.platforms.select`); any but this
    machine's are built with zig (``pip install "linkage-fmu[cross]"``).

    Its binary holds one kernel per structure: every combination of the branch and
    choice parameters, each traced from the linkage's description, so that those
    parameters stay settable; the real-valued parameters are arguments of the kernels'
    parameter step, run when the FMU takes a parameter set.

    Raises
    ------
    DescriptionError, TypeError, ValueError
        The description or a parameter is invalid, or the linkage assembles at no crank
        angle (one that assembles over part of a revolution is built, as by
        :func:`build_fmu`); an unknown platform, or one FMI 2.0 does not name; with
        ``drive``, a linkage whose balancing effort is not a moment on its crank.
    CompilerError
        No C compiler, or no zig for another platform (nothing is written to ``out``
        then).

    Examples
    --------
    >>> build_native_fmu("four_bar", platforms="x86_64-windows,linux64")
    Traceback (most recent call last):
    ...
    linkage_fmu.errors.InputError:
    unknown platform 'linux64': the platforms are all, x86_64-linux,
    aarch64-linux, x86_64-windows, x86_64-darwin, aarch64-darwin
    """
    _check_version(fmi_version)
    chosen = select(platforms, fmi_version)
    d, mech = _assembling(source, parameters)
    if drive:  # refused before anything is traced or compiled
        writers.table_of(mech, "native", drive)
    mu = d.friction_parameters(("mu",))
    plain = None if not d.friction else (
        lambda **structure: d.build(**structure, **dict.fromkeys(mu, 0.0)), mu)
    model_c, _ = writers.model_source(mech, d.fmu_build, drive, plain)
    model = writers.model_name(mech, drive)
    guid = str(uuid.uuid4())
    out = Path(out or ("dist/native" if fmi_version == 2 else "dist/native3"))
    with tempfile.TemporaryDirectory(prefix="linkage_fmu_native_") as tmp:
        root = Path(tmp) / "fmu"
        sources = root / "sources"
        adapter = _stage_sources(sources, mech, "native", fmi_version, guid, drive=drive)
        (sources / "model.c").write_text(model_c)
        if fmi_version == 3:  # FMI 3.0 lists the sources here, not in the modelDescription
            (sources / "buildDescription.xml").write_bytes(writers.build_description(model))
        (root / "resources").mkdir()
        (root / "resources" / f"{d.model}.toml").write_text(d.to_toml(), encoding="utf-8")
        (root / "modelDescription.xml").write_bytes(writers.model_description(
            mech, "native", fmi_version, guid, (adapter.name,) if fmi_version == 2 else (),
            drive))
        groups = folders(chosen, fmi_version)
        # one compiler process per platform, as many at once as the machine has cores
        with ThreadPoolExecutor(max(1, min(os.cpu_count() or 1, len(chosen)))) as pool:
            thin = {p.name: pool.submit(compile_for, p, [adapter],
                                        Path(tmp) / p.name / p.library(model), fmi_version,
                                        include=[sources])
                    for group in groups.values() for p in group}
            done = {name: job.result() for name, job in thin.items()}
        for folder, group in groups.items():
            (root / "binaries" / folder).mkdir(parents=True)
            library = root / "binaries" / folder / group[0].library(model)
            if len(group) == 1:
                shutil.move(done[group[0].name], library)
            else:  # FMI 2.0's darwin64: every Mac in one file
                binaries.universal([done[p.name] for p in group], library)
        return _archive(root, out / f"{model}.fmu")

"""FMUs built once and kept between test runs, keyed by a hash of everything that goes
into them, so that no test waits for an FMU another test (or another run) has built.

:func:`build_fmu` and :func:`build_native_fmu` take the arguments of
``linkage_fmu.fmi.build_fmu`` and ``build_native_fmu`` (``out`` required) and return
``out/<model>.fmu``: a copy of the FMU built for those arguments, built on the first
call. :func:`entry` keeps any folder a function writes, under a :func:`key` of what it
depends on (the Windows C host of ``test_platforms``, the drive tests' reference).

The key is the SHA-256 of the build's arguments, the linkage's description as the FMU
holds it (``to_toml`` of the description with the parameters as defaults), and of:

- every file of the ``linkage_fmu`` package under test (its Python, C, templates,
  linkages): the generated C, the framework, the writers, the pythonfmu FMU's bundle;
- the C compilers: the path and ``--version`` of the system one, zig's version;
- fmpy's and pythonfmu's versions (the FMI headers, pythonfmu's wrapper), Python's
  version, the machine and operating system.

A change to any of them builds anew; nothing built from other sources is ever used. The
FMUs are kept in ``<cache folder>/test-fmus/<kind>-<key>/`` (the library's cache folder:
``$LINKAGE_FMU_CACHE``, else ``~/.cache/linkage_fmu``; ``$LINKAGE_FMU_TEST_FMUS`` to put
them elsewhere), the most recently used :data:`KEEP` of them and any used in the last
day. Each entry is built under a file lock, into a temporary folder renamed into place
when complete, so that pytest-xdist workers and concurrent runs build each FMU once and
never see half of one. Tests get a copy: what they write next to it stays theirs.
"""

from __future__ import annotations

import functools
import hashlib
import json
import os
import platform
import shutil
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from contextlib import contextmanager
from importlib import metadata
from pathlib import Path

import linkage_fmu
from linkage_fmu.ccompiler import find_compiler, find_cross_compiler
from linkage_fmu.kernels.compiled import cache_folder

#: the package under test (the source tree's, with PYTHONPATH=src)
PACKAGE = Path(linkage_fmu.__file__).parent
#: cache entries kept; the least recently used go beyond this
KEEP = 200


def root() -> Path:
    """The folder of the cached FMUs."""
    chosen = os.environ.get("LINKAGE_FMU_TEST_FMUS")
    return Path(chosen) if chosen else cache_folder() / "test-fmus"


def tree_hash(folder: Path) -> str:
    """SHA-256 of the files under ``folder`` (relative names and contents), bytecode
    caches left out."""
    h = hashlib.sha256()
    for f in sorted(folder.rglob("*")):
        if f.is_file() and "__pycache__" not in f.parts and f.suffix != ".pyc":
            h.update(f.relative_to(folder).as_posix().encode() + b"\0" + f.read_bytes() + b"\0")
    return h.hexdigest()


def _version_of(command: list[str]) -> str:
    try:
        run = subprocess.run(command, capture_output=True, text=True, timeout=60)
        return run.stdout + run.stderr
    except (OSError, subprocess.SubprocessError) as err:
        return f"unavailable: {err}"


def _distribution(name: str) -> str:
    try:
        return metadata.version(name)
    except metadata.PackageNotFoundError:
        return "absent"


@functools.lru_cache(maxsize=1)
def environment() -> dict:
    """Everything besides a build's arguments that its FMU depends on."""
    cc = find_compiler()
    zig = find_cross_compiler()
    return {
        "package": tree_hash(PACKAGE),
        "cc": [cc, _version_of([cc, "--version"]) if cc else None],
        "zig": [zig, _version_of([*zig[:-1], "version"]) if zig else None],
        "fmpy": _distribution("fmpy"), "pythonfmu": _distribution("pythonfmu"),
        "python": sys.version, "machine": platform.machine(), "system": platform.system(),
    }


def key(*parts) -> str:
    """The cache key of a build described by the JSON-able ``parts``."""
    text = json.dumps([environment(), *parts], sort_keys=True, default=repr)
    return hashlib.sha256(text.encode()).hexdigest()[:32]


@contextmanager
def _locked(path: Path):
    """An exclusive lock on ``path`` (created), held across processes; none where the
    system has no ``fcntl`` (the rename into place still keeps entries whole)."""
    try:
        import fcntl
    except ImportError:
        yield
        return
    with open(path, "a") as handle:
        fcntl.flock(handle, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(handle, fcntl.LOCK_UN)


def entry(name: str, make: Callable[[Path], None]) -> Path:
    """The cache folder ``name``, made by ``make(folder)`` into an empty folder on the
    first call; later calls (any process) find it made."""
    base = root()
    base.mkdir(parents=True, exist_ok=True)
    target = base / name
    if not target.is_dir():
        with _locked(base / f"{name}.lock"):
            if not target.is_dir():
                staged = Path(tempfile.mkdtemp(prefix=f".{name}-", dir=base))
                try:
                    make(staged)
                    os.replace(staged, target)
                finally:
                    shutil.rmtree(staged, ignore_errors=True)
                _trim(base)
    try:
        os.utime(target)  # just used: the trimming keeps it
    except OSError:
        pass
    return target


def _trim(base: Path) -> None:
    """Remove the least recently used entries beyond :data:`KEEP`, but none used in the
    last day (another run, of other sources, may be using it)."""
    entries = []
    for folder in base.iterdir():
        if folder.is_dir() and not folder.name.startswith("."):
            try:
                entries.append((folder.stat().st_mtime, folder))
            except OSError:
                pass
    recent = time.time() - 86400.0
    for _, folder in [e for e in sorted(entries, reverse=True)[KEEP:] if e[0] < recent]:
        shutil.rmtree(folder, ignore_errors=True)
        Path(f"{folder}.lock").unlink(missing_ok=True)


def _description(source, parameters: dict) -> str:
    """The linkage's description as its FMU holds it."""
    from linkage_fmu.presets import linkage

    mech = linkage(source, **parameters)
    return mech.description.with_defaults(mech.parameters).to_toml()


def _cached_build(flavour: str, source, out, **arguments) -> Path:
    from linkage_fmu.fmi import build

    builder = build.build_native_fmu if flavour == "native" else build.build_fmu
    parameters = {k: arguments.pop(k) for k in list(arguments)
                  if k not in ("fmi_version", "platforms", "drive")}
    parts = [flavour, _description(source, parameters), sorted(arguments.items())]
    made = entry(f"{flavour}-{key(*parts)}",
                 lambda folder: builder(source, folder, **arguments, **parameters))
    (fmu,) = made.glob("*.fmu")
    Path(out).mkdir(parents=True, exist_ok=True)
    return Path(shutil.copy2(fmu, Path(out) / fmu.name))


def build_native_fmu(source, out, fmi_version: int = 2, platforms=None, drive: bool = False,
                     **parameters) -> Path:
    """``linkage_fmu.fmi.build_native_fmu(source, out, ...)``, built once (see the module)."""
    return _cached_build("native", source, out, fmi_version=fmi_version,
                         platforms=platforms, drive=drive, **parameters)


def build_fmu(source, out, fmi_version: int = 2, **parameters) -> Path:
    """``linkage_fmu.fmi.build_fmu(source, out, ...)``, built once (see the module)."""
    return _cached_build("pythonfmu", source, out, fmi_version=fmi_version, **parameters)


def heavier_coupler(fmu: Path, out: Path) -> Path:
    """A copy of the four-bar's ``fmu`` at ``out`` whose description (its resource
    ``FourBar.toml``) makes the coupler's mass 2.5 kg where the FMU was built with 2.0:
    an FMU that its check against the library must fail."""
    import zipfile

    with zipfile.ZipFile(fmu) as source, zipfile.ZipFile(out, "w") as copy:
        for item in source.infolist():
            data = source.read(item)
            if item.filename == "resources/FourBar.toml":
                text = data.decode()
                assert text.count("m2 = { default = 2.0,") == 1
                data = text.replace("m2 = { default = 2.0,", "m2 = { default = 2.5,").encode()
            copy.writestr(item, data)
    return Path(out)

"""The platforms a native FMU carries binaries for: each one's folder name in FMI 2.0 and
3.0, zig's target for building it from any machine, its library's suffix and format, and
its compiler flags.

A platform is named as FMI 3.0 names it (``x86_64-windows``). FMI 2.0 names three:
``linux64``, ``win64`` and ``darwin64``, and none for aarch64 Linux. Its ``darwin64``
folder serves every Mac, so there the binary holds every macOS architecture built: a
universal (fat) Mach-O of x86_64 and arm64 when both are asked for, as ``lipo`` makes
(see :func:`~linkage_fmu.fmi.binaries.universal`).

Examples
--------
>>> [p.name for p in select("all", 3)]
['x86_64-linux', 'aarch64-linux', 'x86_64-windows', 'x86_64-darwin', 'aarch64-darwin']
>>> {folder: [p.name for p in ps] for folder, ps in folders(select("all", 2), 2).items()}
{'linux64': ['x86_64-linux'], 'win64': ['x86_64-windows'], 'darwin64': ['x86_64-darwin',
'aarch64-darwin']}
>>> PLATFORMS["x86_64-windows"].library("FourBar")
'FourBar.dll'
"""

from __future__ import annotations

import platform as pyplatform
from collections.abc import Iterable
from dataclasses import dataclass

from ..errors import InputError

#: flags of every build by zig: no debug information (nor a .pdb beside a DLL), no
#: run-time checks of undefined behaviour (zig's own defaults trap on it), and no
#: warning for the adapters' ``"fmi3" #Name + 3`` (a pointer into a string literal, as
#: meant: clang's -Wstring-plus-int warns of it, gcc does not)
ZIG_FLAGS = ("-s", "-fno-sanitize=undefined", "-Wno-string-plus-int")


@dataclass(frozen=True)
class Platform:
    """One platform of a native FMU's binaries.

    Attributes
    ----------
    name : str
        FMI 3.0's name, which is also the name given to ``--platforms``.
    fmi2 : str or None
        FMI 2.0's folder name; None where FMI 2.0 names no platform.
    zig : str
        zig's ``-target`` (glibc 2.17 on Linux, macOS 11 on the Mac: old enough for the
        machines in use, so the binary loads on them).
    format : str
        The library's file format: ``"elf"``, ``"pe"`` or ``"macho"``.
    machine : str
        The processor: ``"x86_64"`` or ``"aarch64"``.
    suffix : str
        The library's suffix.
    flags : tuple of str
        Compiler flags of this platform.
    libraries : tuple of str
        Libraries linked (``-l``).
    """

    name: str
    fmi2: str | None
    zig: str
    format: str
    machine: str
    suffix: str
    flags: tuple[str, ...]
    libraries: tuple[str, ...]

    def folder(self, fmi_version: int) -> str:
        """The name of this platform's folder under ``binaries/`` in an FMU of
        ``fmi_version``.

        Raises
        ------
        ValueError
            FMI 2.0 has no name for this platform.

        Examples
        --------
        >>> PLATFORMS["aarch64-darwin"].folder(2), PLATFORMS["aarch64-darwin"].folder(3)
        ('darwin64', 'aarch64-darwin')
        """
        if fmi_version == 3:
            return self.name
        if self.fmi2 is None:
            raise InputError(
                f"FMI 2.0 has no platform name for {self.name} (its platforms: "
                f"{', '.join(sorted({p.fmi2 for p in PLATFORMS.values() if p.fmi2}))}); "
                "build an FMI 3.0 FMU (--fmi 3) for it")
        return self.fmi2

    def library(self, model: str) -> str:
        """The file name of ``model``'s library on this platform."""
        return model + self.suffix


def _platforms() -> dict[str, Platform]:
    pic = ("-fPIC",)
    return {p.name: p for p in (
        Platform("x86_64-linux", "linux64", "x86_64-linux-gnu.2.17", "elf", "x86_64", ".so",
                 pic, ("m",)),
        Platform("aarch64-linux", None, "aarch64-linux-gnu.2.17", "elf", "aarch64", ".so",
                 pic, ("m",)),
        # MinGW-style, linked to the Universal C Runtime (Windows 10 and later have it);
        # the FMI headers declare each function __declspec(dllexport) on _WIN32, and a
        # DLL with such declarations exports nothing else
        Platform("x86_64-windows", "win64", "x86_64-windows-gnu", "pe", "x86_64", ".dll",
                 (), ()),
        Platform("x86_64-darwin", "darwin64", "x86_64-macos.11.0", "macho", "x86_64",
                 ".dylib", pic, ()),
        Platform("aarch64-darwin", "darwin64", "aarch64-macos.11.0", "macho", "aarch64",
                 ".dylib", pic, ()),
    )}


#: every platform a native FMU can carry, by name, in a fixed order
PLATFORMS = _platforms()


def host() -> Platform | None:
    """This machine's platform, or None if it is none of :data:`PLATFORMS`.

    Examples
    --------
    >>> host() is None or host().name in PLATFORMS
    True
    """
    system = {"Linux": "linux", "Windows": "windows", "Darwin": "darwin"}.get(pyplatform.system())
    machine = {"amd64": "x86_64", "x86_64": "x86_64", "arm64": "aarch64",
               "aarch64": "aarch64"}.get(pyplatform.machine().lower())
    return PLATFORMS.get(f"{machine}-{system}")


def select(spec: str | Iterable[str] | None, fmi_version: int) -> tuple[Platform, ...]:
    """The platforms that ``spec`` asks for, in the order of :data:`PLATFORMS`.

    Parameters
    ----------
    spec : str, iterable of str or None
        None: this machine's platform; ``"all"``: every platform FMI ``fmi_version``
        has a name for; else names, as a list or one comma-separated string.
    fmi_version : int
        2 or 3.

    Raises
    ------
    ValueError
        An unknown name (the message lists the valid ones), a platform FMI 2.0 does not
        name, nothing asked for, or (spec None) a machine that is none of the platforms.

    Examples
    --------
    >>> [p.name for p in select("x86_64-windows, aarch64-linux", 3)]
    ['aarch64-linux', 'x86_64-windows']
    >>> select("win32", 3)
    Traceback (most recent call last):
    ...
    linkage_fmu.errors.InputError:
    unknown platform 'win32': the platforms are all, x86_64-linux, aarch64-linux,
    x86_64-windows, x86_64-darwin, aarch64-darwin
    """
    if spec is None:
        this = host()
        if this is None:
            raise InputError(f"this machine ({pyplatform.system()} on {pyplatform.machine()}) is "
                             f"none of the platforms {', '.join(PLATFORMS)}")
        this.folder(fmi_version)
        return (this,)
    names = [n.strip() for n in (spec.split(",") if isinstance(spec, str) else spec)]
    names = [n for n in names if n]
    if "all" in names:
        return tuple(p for p in PLATFORMS.values() if fmi_version == 3 or p.fmi2)
    for name in names:
        if name not in PLATFORMS:
            raise InputError(f"unknown platform {name!r}: the platforms are all, "
                             f"{', '.join(PLATFORMS)}")
    if not names:
        raise InputError("no platform named: give 'all' or names among "
                         f"{', '.join(PLATFORMS)}")
    chosen = tuple(p for p in PLATFORMS.values() if p.name in names)
    for p in chosen:
        p.folder(fmi_version)
    return chosen


def folders(chosen: Iterable[Platform], fmi_version: int) -> dict[str, list[Platform]]:
    """The folders under ``binaries/`` of an FMU of ``fmi_version`` with ``chosen``
    platforms, each with the platforms whose code it holds: one each, but for FMI 2.0's
    ``darwin64``, which holds every Mac platform chosen (one universal binary).

    Examples
    --------
    >>> folders(select("aarch64-darwin,x86_64-windows", 3), 3)["aarch64-darwin"][0].zig
    'aarch64-macos.11.0'
    """
    out: dict[str, list[Platform]] = {}
    for p in chosen:
        out.setdefault(p.folder(fmi_version), []).append(p)
    return out

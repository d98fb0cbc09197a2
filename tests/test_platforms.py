"""Native FMUs for every platform (``linkage_fmu.fmi.platforms``), built here with zig:
the platforms asked for and only those, each binary a library of its platform's format
and processor exporting the FMI functions and nothing else, and every binary that can
run on this machine run over a revolution by the C host (``tests/c_host/host.c``)
against the direct solver (1e-12): x86_64 Linux natively, win64 / x86_64-windows under
wine, aarch64-linux under qemu-user. The macOS binaries are checked for format,
processor and exports only. Tests that need zig, wine or qemu skip, saying which, where
it is missing."""

from __future__ import annotations

import inspect
import os
import shutil
import subprocess
import zipfile
from pathlib import Path

import pytest

import fmu_cache
from linkage_fmu.ccompiler import CompilerError, find_cross_compiler
from linkage_fmu.cli import main
from linkage_fmu.fmi import binaries, build_native_fmu
from linkage_fmu.fmi.build import REQUIRED
from linkage_fmu.fmi.platforms import PLATFORMS, folders, host, select
from test_c_host import HOST_SOURCE, compile_host, error_against_direct, model_outputs

STEPS, OMEGA, LOAD = 72, 10.0, 5.0
TOLERANCE = 1e-12
#: qemu-user runs an aarch64 program whose libraries come from this sysroot
#: (Debian: libc6-arm64-cross)
AARCH64_SYSROOT = Path("/usr/aarch64-linux-gnu")

needs_zig = pytest.mark.skipif(
    find_cross_compiler() is None,
    reason='zig is not installed (pip install "linkage-fmu[cross]"): cannot build for '
           'other platforms')


def wine() -> str | None:
    """wine's 64-bit loader: on PATH, or where Debian's wine64 package puts it without
    the wine package's wrapper."""
    for candidate in (shutil.which("wine64"), shutil.which("wine"), "/usr/lib/wine/wine64"):
        if candidate and Path(candidate).is_file():
            return candidate
    return None


def qemu_aarch64() -> str | None:
    """qemu-user for aarch64 (Debian: qemu-user-static), if it and the sysroot are here."""
    qemu = shutil.which("qemu-aarch64-static") or shutil.which("qemu-aarch64")
    return qemu if qemu and (AARCH64_SYSROOT / "lib" / "ld-linux-aarch64.so.1").is_file() \
        else None


# -- choosing platforms -----------------------------------------------------------------

def test_all_means_every_platform_the_fmi_version_names():
    """FMI 3.0: all five; FMI 2.0: no aarch64 Linux, and one darwin64 for both Macs."""
    assert [p.name for p in select("all", 3)] == list(PLATFORMS)
    assert {f: [p.name for p in ps] for f, ps in folders(select("all", 2), 2).items()} == {
        "linux64": ["x86_64-linux"], "win64": ["x86_64-windows"],
        "darwin64": ["x86_64-darwin", "aarch64-darwin"]}
    assert list(folders(select("all", 3), 3)) == list(PLATFORMS)


def test_names_are_checked_and_the_errors_list_the_valid_ones():
    assert [p.name for p in select(["aarch64-darwin", " x86_64-linux"], 3)] == [
        "x86_64-linux", "aarch64-darwin"]
    with pytest.raises(ValueError, match="unknown platform 'win64': the platforms are all, "
                                         "x86_64-linux, aarch64-linux, x86_64-windows"):
        select("x86_64-linux,win64", 2)
    with pytest.raises(ValueError, match="FMI 2.0 has no platform name for aarch64-linux .*"
                                         "--fmi 3"):
        select("aarch64-linux", 2)
    with pytest.raises(ValueError, match="no platform named"):
        select(" , ", 3)


def test_the_default_is_this_machine():
    this = host()
    if this is None:
        pytest.skip("this machine is none of the platforms")
    assert select(None, 3) == (this,)


def test_the_cli_names_a_bad_platform_and_the_missing_extra(tmp_path, monkeypatch, capsys):
    """An unknown name, --platforms without --native, and no zig: exit status 2, one line
    saying why (the last naming the extra to install), no traceback, nothing written."""
    out = str(tmp_path)
    assert main(["build", "--native", "--platforms", "win32", "four_bar", "--out", out]) == 2
    assert "unknown platform 'win32': the platforms are all, x86_64-linux" in \
        capsys.readouterr().err
    assert main(["build", "--platforms", "all", "four_bar", "--out", out]) == 2
    assert "--platforms is for native FMUs (--native)" in capsys.readouterr().err
    monkeypatch.setattr("linkage_fmu.ccompiler.find_cross_compiler", lambda: None)
    assert main(["build", "--native", "--platforms", "x86_64-windows", "four_bar", "--out",
                 out]) == 2
    err = capsys.readouterr().err
    assert "needs zig's C compiler" in err and 'pip install "linkage-fmu[cross]"' in err
    assert "Traceback" not in err and not list(tmp_path.iterdir())
    with pytest.raises(CompilerError, match="linkage-fmu\\[cross\\]"):
        build_native_fmu("four_bar", tmp_path, platforms="x86_64-windows")


# -- the FMUs of every platform ---------------------------------------------------------

@pytest.fixture(scope="module")
def every_platform(tmp_path_factory) -> dict[int, Path]:
    """FourBar's native FMUs of FMI 2.0 and 3.0 with the binaries of every platform,
    unzipped: {FMI version: folder}."""
    if find_cross_compiler() is None:
        pytest.skip('zig is not installed (pip install "linkage-fmu[cross]")')
    out = tmp_path_factory.mktemp("every_platform")
    folders_ = {}
    for version in (2, 3):
        fmu = fmu_cache.build_native_fmu("four_bar", out / f"fmi{version}", version,
                                         platforms="all")
        folders_[version] = out / f"FourBar{version}"
        with zipfile.ZipFile(fmu) as archive:
            archive.extractall(folders_[version])
    return folders_


@needs_zig
@pytest.mark.parametrize("version", (2, 3))
def test_each_binary_is_a_library_of_its_platform_exporting_only_fmi(every_platform,
                                                                      version):
    """binaries/ holds one folder per platform the FMI version names; each library is of
    its platform's format and processor (darwin64: universal, x86_64 then arm64) and
    exports the FMI functions, nothing else (Mach-O: but the linker's two symbols)."""
    root = every_platform[version] / "binaries"
    expected = folders(select("all", version), version)
    assert sorted(p.name for p in root.iterdir()) == sorted(expected)
    for folder, group in expected.items():
        library = root / folder / group[0].library("FourBar")
        assert [p.name for p in (root / folder).iterdir()] == [library.name]
        assert binaries.problems(library, group[0].format, [p.machine for p in group],
                                 f"fmi{version}", REQUIRED[version]) == [], folder
        exported = binaries.read(library)[0].exports - binaries.LINKER_MADE
        assert len(exported) >= 30 and all(n.startswith(f"fmi{version}") for n in exported)


def run_host(command: list[str], env: dict, outputs: dict[str, int]) -> dict[str, float]:
    """Run the host (``command`` ends before its step count) over a revolution; the
    errors of its outputs against the direct solver."""
    run = subprocess.run([*command, str(STEPS), repr(OMEGA), repr(LOAD),
                          *map(str, outputs.values())], env=env, capture_output=True,
                         text=True, timeout=300)
    assert run.returncode == 0, f"host exited with {run.returncode}:\n{run.stderr[-3000:]}"
    return error_against_direct(run.stdout, outputs, STEPS, OMEGA, LOAD)


def host_arguments(folder: Path, version: int) -> tuple[list[str], dict[str, int]]:
    model, token, outputs = model_outputs(folder / "modelDescription.xml")
    return [*(["-3"] if version == 3 else []), str(folder), model, token], outputs


@needs_zig
@pytest.mark.skipif(shutil.which("gcc") is None or host() != PLATFORMS["x86_64-linux"],
                    reason="needs gcc on x86_64 Linux")
@pytest.mark.parametrize("version", (2, 3))
def test_this_machines_binary_in_the_c_host(every_platform, tmp_path, version):
    """The x86_64-linux (linux64) binary of the FMU that carries every platform, in the C
    host (FMI 2.0, and FMI 3.0 with -3) with no Python in the process: every output of
    a revolution equals the direct solver's to 1e-12 of its largest magnitude."""
    arguments, outputs = host_arguments(every_platform[version], version)
    errors = run_host([str(compile_host(tmp_path)), *arguments], {"PATH": "/usr/bin:/bin"},
                      outputs)
    assert max(errors.values()) <= TOLERANCE, errors


@pytest.fixture(scope="module")
def wine_run(tmp_path_factory):
    """(command prefix, environment) running a Windows program under wine in a prefix of
    this module's own; wine's server for that prefix is stopped afterwards."""
    loader = wine()
    if loader is None:
        pytest.skip("wine is not installed (Debian: apt-get install wine64): the win64 "
                    "binaries are checked for format only")
    env = {**os.environ, "WINEPREFIX": str(tmp_path_factory.mktemp("wineprefix")),
           "WINEDEBUG": "-all", "WINEDLLOVERRIDES": "mscoree,mshtml="}  # no Mono, no Gecko
    yield [loader], env
    server = shutil.which("wineserver") or str(Path(loader).with_name("wineserver"))
    if Path(server).is_file():
        subprocess.run([server, "-k"], env=env, capture_output=True, timeout=60)


@pytest.fixture(scope="module")
def windows_host() -> Path:
    """The C host built for Windows (zig, MinGW, UCRT), once for its source and build
    (``fmu_cache``)."""
    target = PLATFORMS["x86_64-windows"].zig
    made = fmu_cache.entry(
        "host-" + fmu_cache.key("host", target, HOST_SOURCE.read_text(),
                                inspect.getsource(compile_host)),
        lambda folder: compile_host(folder, target))
    return made / "host.exe"


def windows_arguments(folder: Path, version: int) -> tuple[list[str], dict[str, int]]:
    """The host's arguments for the FMU unzipped in ``folder``, its path as Windows
    sees it under wine (drive Z: is the root of this file system)."""
    arguments, outputs = host_arguments(folder, version)
    arguments[-3] = "Z:" + arguments[-3].replace("/", "\\")
    return arguments, outputs


@pytest.mark.slow
@needs_zig
@pytest.mark.parametrize("version", (2, 3))
def test_the_windows_binary_under_wine(every_platform, wine_run, windows_host, version):
    """The win64 (FMI 2.0) and x86_64-windows (3.0) DLLs, loaded with LoadLibrary by the C
    host built for Windows and run under wine: every output of a revolution equals the
    direct solver's to 1e-12 of its largest magnitude."""
    prefix, env = wine_run
    arguments, outputs = windows_arguments(every_platform[version], version)
    errors = run_host([*prefix, str(windows_host), *arguments], env, outputs)
    assert max(errors.values()) <= TOLERANCE, errors


@pytest.mark.slow
@needs_zig
def test_the_windows_binary_logs_an_error_in_full_under_wine(every_platform, wine_run,
                                                              windows_host):
    """A foreign GUID: the win64 DLL's fmi2Instantiate returns NULL and logs the reason
    with both GUIDs (formatted by the Windows C runtime), and the host carries on to its
    own exit status 1."""
    prefix, env = wine_run
    arguments, outputs = windows_arguments(every_platform[2], 2)
    guid = arguments[-1]
    arguments[-1] = "not-the-guid"
    run = subprocess.run([*prefix, str(windows_host), *arguments, "4", "1.0", "0.0",
                          str(outputs["Mb"])], env=env, capture_output=True, text=True,
                         timeout=300)
    assert run.returncode == 1, run.stderr
    assert "fmi2Instantiate failed" in run.stderr
    assert (f"fmi2Instantiate: the GUID not-the-guid does not match this FMU's {guid}"
            in run.stderr), run.stderr


@pytest.mark.slow
@needs_zig
def test_the_aarch64_linux_binary_under_qemu(every_platform, tmp_path):
    """The aarch64-linux binary (FMI 3.0 only), loaded with dlopen by the C host built for
    aarch64 Linux (zig, glibc) and run under qemu-user with Debian's aarch64 glibc as
    its sysroot: every output of a revolution equals the direct solver's to 1e-12 of
    its largest magnitude."""
    qemu = qemu_aarch64()
    if qemu is None:
        pytest.skip("qemu-user or the aarch64 sysroot is not installed (Debian: apt-get "
                    "install qemu-user-static libc6-arm64-cross): the aarch64-linux binary "
                    "is checked for format only")
    exe = compile_host(tmp_path, PLATFORMS["aarch64-linux"].zig)
    assert binaries.read(exe)[0].machine == "aarch64"
    arguments, outputs = host_arguments(every_platform[3], 3)
    errors = run_host([qemu, "-L", str(AARCH64_SYSROOT), str(exe), *arguments],
                      {"PATH": "/usr/bin:/bin"}, outputs)
    assert max(errors.values()) <= TOLERANCE, errors

"""Run the FourBar FMU from a plain C program (``tests/c_host/host.c``) through the FMI 2.0 C API.

The FMU binary is a pythonfmu wrapper that embeds Python, so the host needs this
interpreter's libpython preloaded, its home in ``PYTHONHOME`` and its site-packages (numpy)
on ``PYTHONPATH``: the FMUs page's commands for them are run and the host given nothing else
but ``PATH``. The helpers here (compiling the host for this machine or, with zig, for
another platform; reading a modelDescription; comparing a run with the direct solver)
serve the native FMUs' tests too (``test_native.py``, ``test_platforms.py``).
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
import sysconfig
import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path

import numpy as np
import pytest

from linkage_fmu import presets

pytestmark = pytest.mark.skipif(shutil.which("gcc") is None,
                                reason="gcc is not on PATH: cannot compile the C host")

ROOT = Path(__file__).parents[1]
HOST_SOURCE = Path(__file__).parent / "c_host" / "host.c"
STEPS, OMEGA, LOAD = 72, 10.0, 5.0
TOLERANCE = 1e-9


@pytest.fixture(scope="module")
def fmu(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """FourBar.fmu freshly built from the working tree (no fmpy check)."""
    out = tmp_path_factory.mktemp("fmu")
    build = subprocess.run([sys.executable, "build_fmu.py", "--no-check", "--preset", "four_bar",
                            "--platforms", "host", "--out", str(out)], cwd=ROOT,
                           capture_output=True, text=True)
    assert build.returncode == 0, build.stdout + build.stderr
    return out / "FourBar.fmu"


def compile_host(out: Path, zig_target: str | None = None) -> Path:
    """Compile host.c against the FMI headers shipped with fmpy, with gcc for this
    machine, or with zig's compiler for ``zig_target`` (``x86_64-windows-gnu``, ...);
    return the executable."""
    import fmpy

    from linkage_fmu.ccompiler import require_cross_compiler

    windows = zig_target is not None and "windows" in zig_target
    exe = out / ("host.exe" if windows else "host")
    compiler = (["gcc"] if zig_target is None else
                [*require_cross_compiler("the C host"), "-target", zig_target])
    command = [*compiler, "-std=c99", "-O2", "-Wall", "-Wextra", "-Werror", "-o", str(exe),
               str(HOST_SOURCE), "-I", str(Path(fmpy.__file__).parent / "c-code"),
               *(() if windows else ("-ldl",))]
    run = subprocess.run(command, capture_output=True, text=True)
    assert run.returncode == 0 and not run.stderr.strip(), run.stderr
    return exe


def host_environment() -> dict[str, str]:
    """Environment for the host: this interpreter's libpython and site-packages."""
    libdir = sysconfig.get_config_var("LIBDIR")
    soname = sysconfig.get_config_var("INSTSONAME") or sysconfig.get_config_var("LDLIBRARY")
    libpython = Path(libdir) / soname
    assert libpython.is_file(), f"no shared libpython at {libpython}"
    return {**os.environ, "LD_PRELOAD": str(libpython),
            "PYTHONPATH": sysconfig.get_paths()["purelib"]}


def model_outputs(model_description: Path) -> tuple[str, str, dict[str, int]]:
    """Model identifier, GUID (FMI 3.0: instantiation token) and ``{output name:
    valueReference}`` of a modelDescription.xml of FMI 2.0 or 3.0."""
    root = ET.parse(model_description).getroot()
    variables = (root.iter("ScalarVariable") if root.get("fmiVersion") == "2.0" else
                 root.find("ModelVariables"))
    outputs = {v.get("name"): int(v.get("valueReference"))
               for v in variables if v.get("causality") == "output"}
    token = root.get("guid") or root.get("instantiationToken")
    return root.find("CoSimulation").get("modelIdentifier"), token, outputs


def error_against_direct(stdout: str, outputs: dict[str, int], steps: int, omega: float,
                         load: float, preset: str = "four_bar") -> dict[str, float]:
    """The host's table (its ``stdout``) against ``presets.get(preset).solve(...,
    method="direct")``: the largest error of each output, relative to that output's
    largest magnitude over the revolution; the angles must be the host's exactly."""
    table = np.loadtxt(stdout.splitlines(), delimiter=",", ndmin=2)
    assert table.shape == (steps, 1 + len(outputs))
    theta = table[:, 0]
    np.testing.assert_allclose(theta, 2 * np.pi * np.arange(steps) / steps, rtol=0, atol=1e-15)
    expected = presets.get(preset).solve(theta, omega=omega, alpha=0.0, load=load,
                                         method="direct")
    return {name: float(np.max(np.abs(table[:, column] - expected[name]))
                        / max(np.max(np.abs(expected[name])), 1e-300))
            for column, name in enumerate(outputs, start=1)}


def readme_environment() -> dict[str, str]:
    """The variables the ``sh`` block of the FMUs' page (docs/guide/fmus.md) exports for
    a non-Python host, each command run with this interpreter."""
    page = (ROOT / "docs" / "guide" / "fmus.md").read_text()
    block = next(b for b in re.findall(r"```sh\n(.*?)```", page, flags=re.S)
                 if "LD_PRELOAD" in b)
    block = block.replace("\\\n", "")  # a line continued inside quotes, as bash joins it
    env = {}
    for name, command in re.findall(r"^export (\w+)=\$\((.*)\)$", block, flags=re.M):
        command = re.sub(r"^(python3|\.venv/bin/python) ", f"{sys.executable} ", command)
        env[name] = subprocess.run(["bash", "-c", command], cwd=ROOT, capture_output=True,
                                   text=True, check=True).stdout.strip()
    return env


def test_c_host_matches_direct_solver(fmu: Path, tmp_path: Path) -> None:
    """Every output of one revolution (omega = 10 rad/s, load = 5 N.m) computed by the FMU
    under a C host matches ``presets.get("four_bar").solve(..., method="direct")``, the
    assembled-LU reference, to 1e-9 relative to each output's largest magnitude."""
    check_revolution(fmu, tmp_path, host_environment())


def test_the_readme_environment_is_all_a_clean_host_needs(fmu: Path, tmp_path: Path) -> None:
    """The host with only ``PATH`` and what the FMUs page's commands export (LD_PRELOAD,
    PYTHONHOME, PYTHONPATH), as ``env -i`` would give it, computes the same revolution."""
    env = readme_environment()
    assert set(env) == {"LD_PRELOAD", "PYTHONHOME", "PYTHONPATH"}
    check_revolution(fmu, tmp_path, {"PATH": "/usr/local/bin:/usr/bin:/bin", **env})


def check_revolution(fmu: Path, tmp_path: Path, env: dict[str, str]) -> None:
    unzipped = tmp_path / "FourBar"
    with zipfile.ZipFile(fmu) as archive:
        archive.extractall(unzipped)
    model, guid, outputs = model_outputs(unzipped / "modelDescription.xml")
    host = compile_host(tmp_path)

    command = [str(host), str(unzipped), model, guid, str(STEPS), repr(OMEGA), repr(LOAD),
               *map(str, outputs.values())]
    run = subprocess.run(command, cwd=tmp_path, env=env, capture_output=True, text=True,
                         timeout=120)
    assert run.returncode == 0, f"host exited with {run.returncode}:\n{run.stderr}"

    table = np.loadtxt(run.stdout.splitlines(), delimiter=",", ndmin=2)
    assert table.shape == (STEPS, 1 + len(outputs))
    theta = table[:, 0]
    np.testing.assert_allclose(theta, 2 * np.pi * np.arange(STEPS) / STEPS, rtol=0, atol=1e-15)

    expected = presets.get("four_bar").solve(theta, omega=OMEGA, alpha=0.0, load=LOAD,
                                             method="direct")
    for column, name in enumerate(outputs, start=1):
        scale = np.max(np.abs(expected[name]))
        np.testing.assert_allclose(table[:, column], expected[name], rtol=0,
                                   atol=TOLERANCE * scale, err_msg=name)


@pytest.mark.parametrize("env, message", [
    ({"PYTHONHOME": "/nonexistent/python"}, "cannot start Python"),
    ({"LD_PRELOAD": ""}, "it needs libpython"),
])
def test_a_host_without_a_working_python_gets_an_error_not_an_exit(fmu, tmp_path, env,
                                                                    message):
    """A bad PYTHONHOME (Python's own start-up would exit the process) or no libpython in
    the process: fmi2Instantiate returns NULL and logs why; the host carries on (here it
    reports the failure and exits with its own status 1)."""
    unzipped = tmp_path / "FourBar"
    with zipfile.ZipFile(fmu) as archive:
        archive.extractall(unzipped)
    model, guid, outputs = model_outputs(unzipped / "modelDescription.xml")
    host = compile_host(tmp_path)
    run = subprocess.run([str(host), str(unzipped), model, guid, "4", "1.0", "0.0",
                          str(outputs["Mb"])], cwd=tmp_path,
                         env={**host_environment(), **env}, capture_output=True, text=True,
                         timeout=120)
    assert run.returncode == 1, run.stderr
    assert "fmi2Instantiate failed" in run.stderr and message in run.stderr, run.stderr

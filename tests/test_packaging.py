"""The package as released: the wheel (built from the sdist, as ``python -m build`` does)
holds every file the package reads at run time, and installed from that wheel into a
fresh environment, away from the source tree, it builds FMUs that pass ``linkage-fmu
check`` (the FMU against the installed package's direct solver).

The builds run without a network: no build isolation (the test extra brings setuptools),
and the fresh environment takes its dependencies from this one's site-packages.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import sysconfig
import zipfile
from pathlib import Path

import pytest

import linkage_fmu
from linkage_fmu import presets
from linkage_fmu.fmi import build

ROOT = Path(__file__).resolve().parents[1]
#: what the package reads beside its Python at run time, named as the code names them:
#: the FMUs' C sources (fmi/build.py), their templates (fmi/writers.py), the kernels'
#: extension module (kernels/compiled.py)
RUNTIME = (
    [f"linkage_fmu/fmi/{name}" for name in ("fmi2.c", "fmi3.c", *build.FRAMEWORK,
                                            "backend_native.c", "backend_pythonfmu.c")]
    + [f"linkage_fmu/fmi/templates/{name}" for name in (
        "modelDescription2.xml", "modelDescription3.xml", "buildDescription.xml", "config.h",
        "model.c", "slave.py.in")]
    + ["linkage_fmu/kernels/pykernel.c"]
)


def _without_source_path() -> dict:
    """This process's environment without PYTHONPATH (which points at the source tree)."""
    return {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}


def _run(command: list, **options) -> subprocess.CompletedProcess:
    """Run ``command``; its output is the assertion's message where it fails."""
    done = subprocess.run([str(c) for c in command], capture_output=True, text=True, **options)
    assert done.returncode == 0, (command, done.stdout[-2000:], done.stderr[-2000:])
    return done


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> Path:
    """The wheel, built from the sdist of a copy of the project (nothing is written into
    the source tree)."""
    project = tmp_path_factory.mktemp("project")
    for name in ("pyproject.toml", "README.md", "LICENSE"):
        shutil.copy(ROOT / name, project / name)
    shutil.copytree(ROOT / "src", project / "src",
                    ignore=shutil.ignore_patterns("__pycache__", "*.pyc", "*.egg-info"))
    out = tmp_path_factory.mktemp("packages")
    _run([sys.executable, "-m", "build", "--no-isolation", "--outdir", out, project],
         env=_without_source_path())
    (found,) = out.glob("*.whl")
    return found


def test_the_wheel_holds_what_the_package_reads_at_run_time(wheel):
    """Every C source and template the FMU builders and kernels open, each preset's
    description, every file of the source package, the licence, and the version of
    ``linkage_fmu.__version__``."""
    names = set(zipfile.ZipFile(wheel).namelist())
    needed = set(RUNTIME) | {f"linkage_fmu/linkages/{name}.toml" for name in presets.names()}
    assert needed <= names, sorted(needed - names)
    package = Path(linkage_fmu.__file__).parent
    tracked = {f"linkage_fmu/{p.relative_to(package).as_posix()}" for p in package.rglob("*")
               if p.is_file() and "__pycache__" not in p.parts}
    assert tracked <= names, sorted(tracked - names)
    assert f"linkage_fmu-{linkage_fmu.__version__}.dist-info/licenses/LICENSE" in names
    assert wheel.name.startswith(f"linkage_fmu-{linkage_fmu.__version__}-")


def test_the_installed_wheel_builds_fmus_that_pass_the_check(wheel, tmp_path):
    """A fresh venv with only the wheel installed (its dependencies from this
    environment's site-packages), run from a folder outside the source tree: it imports
    its own copy of the package, and its pythonfmu and native FMUs of four_bar pass
    ``linkage-fmu check``."""
    venv = tmp_path / "venv"
    _run([sys.executable, "-m", "venv", "--without-pip", venv])
    python = venv / "bin" / "python"
    site = Path(_run([python, "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"])
                .stdout.strip())
    # a path line only: the .pth files of this environment (an editable install of the
    # source tree) are not processed, and the venv's own site-packages comes first
    deps = {sysconfig.get_paths()["purelib"], sysconfig.get_paths()["platlib"]}
    (site / "linkage_fmu_test_dependencies.pth").write_text("\n".join(sorted(deps)) + "\n")
    env = _without_source_path()
    _run([sys.executable, "-m", "pip", "--python", python, "install", "--no-deps", "--no-index",
          "-q", wheel], env=env)
    work = tmp_path / "work"
    work.mkdir()
    where = _run([python, "-c", "import linkage_fmu; print(linkage_fmu.__file__)"], cwd=work,
                 env=env)
    assert Path(where.stdout.strip()).is_relative_to(site), where.stdout
    command = venv / "bin" / "linkage-fmu"
    for flavour, options in (("pythonfmu", []), ("native", ["--native"])):
        out = work / flavour
        _run([command, "build", *options, "four_bar", "--out", out], cwd=work, env=env)
        fmu = out / "FourBar.fmu"
        assert fmu.is_file(), flavour
        checked = _run([command, "check", "--json", fmu], cwd=work, env=env)
        result = json.loads(checked.stdout.splitlines()[-1])
        assert result["model"] == "FourBar" and result["mismatched"] == 0, result

"""The native FMUs as source FMUs: an importer that builds the binary itself from
``sources/`` gets the same FMU. fmpy's compile step (``fmpy compile``:
:func:`fmpy.build.build_platform_binary`, a CMake project of its own) reads the source
files from the modelDescription's ``SourceFiles`` (FMI 2.0) or from
``sources/buildDescription.xml`` (FMI 3.0) and builds them with the system's C compiler.

fmpy's CMake project ignores the build description's ``<Library name="m">``, so the
binary it links does not name libm; it loads in a host that has libm already (Python,
any C program linked with -lm), as here.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
from fmpy import extract
from fmpy.build import build_platform_binary
from fmpy.util import create_zip_archive

from conftest import MODELS
from fmu_cache import build_native_fmu
from linkage_fmu.fmi import check_fmu
from linkage_fmu.fmi.platforms import host

ROOT = Path(__file__).resolve().parents[1]
#: every native FMU that build_fmu.py builds
NATIVE_MODELS = (*MODELS.values(), "CouplerFourBar", "Engine")

pytestmark = pytest.mark.skipif(shutil.which("cmake") is None,
                                reason="fmpy's compile step needs cmake on PATH")


@pytest.fixture(scope="module")
def engine3(tmp_path_factory) -> Path:
    """The native FMI 3.0 FMU of the README's engine (not among the ``native3`` ones)."""
    return build_native_fmu(ROOT / "examples" / "engine.toml",
                            tmp_path_factory.mktemp("engine3"), fmi_version=3)


def rebuilt(fmu: Path, fmi_version: int, tmp_path: Path) -> Path:
    """``fmu`` with its binary deleted and built again from its ``sources/`` by fmpy's
    compile step, as ``fmpy compile`` does."""
    unzipped = tmp_path / "unzipped"
    extract(str(fmu), unzipdir=str(unzipped))
    binary = unzipped / "binaries" / host().folder(fmi_version) / host().library(fmu.stem)
    binary.unlink()
    build = tmp_path / "build"
    build.mkdir()
    build_platform_binary(unzipped.resolve(), build_dir=build.resolve())
    assert binary.is_file()
    out = tmp_path / fmu.name
    create_zip_archive(out, unzipped)
    return out


@pytest.mark.parametrize("model", [
    pytest.param(m, marks=pytest.mark.slow) if m == "SixBar" else m  # 3.6 MB of C
    for m in NATIVE_MODELS])
@pytest.mark.parametrize("fmi_version", [2, 3])
def test_built_from_its_sources_by_fmpy_equals_the_direct_solver(
        request, dist, tmp_path, fmi_version, model):
    """The FMU rebuilt by fmpy from the sources it ships (no file changed, nothing added)
    runs a revolution (two for the engine) with varying speed and loads through fmpy,
    each row the outputs of its own inputs, every output within 1e-12 of the direct
    solver relative to its largest magnitude; no step is discarded."""
    if fmi_version == 2:
        fmu = dist / "native" / f"{model}.fmu"
    elif model == "Engine":
        fmu = request.getfixturevalue("engine3")
    else:
        fmu = request.getfixturevalue("native3") / f"{model}.fmu"
    result = check_fmu(rebuilt(fmu, fmi_version, tmp_path))
    assert result.steps == (720 if model == "Engine" else 360)
    assert result.passed(1e-12) and result.unsolved_deg == (), result

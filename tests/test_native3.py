"""The native FMUs as FMI 3.0 co-simulation FMUs (``build_native_fmu(..., fmi_version=3)``):
the same kernels and backend behind ``fmi3.c``. fmpy validates them, they match the
direct solver over a revolution (1e-12), and from a fresh process they answer bad calls,
unsolvable inputs and FMU states as the FMI 2.0 ones do (``fmu3_host.py``)."""

from __future__ import annotations

import subprocess
import sys
import zipfile
from pathlib import Path

import pytest
from fmpy.validation import validate_fmu

from conftest import MODELS
from linkage_fmu.fmi import check_fmu

ROOT = Path(__file__).resolve().parents[1]
SOURCES = (*MODELS, ROOT / "examples" / "coupler_four_bar.toml")


@pytest.mark.parametrize("model", (*MODELS.values(), "CouplerFourBar"))
def test_valid_and_equal_to_the_direct_solver(native3, model):
    """``fmpy validate`` finds nothing (FMI 3.0 schema and rules); a revolution with varying
    speed and loads through ``simulate_fmu`` matches the direct solver to 1e-12 of each
    output's largest value; the binary is for x86_64-linux and the sources come with a
    buildDescription.xml."""
    fmu = native3 / f"{model}.fmu"
    assert validate_fmu(str(fmu)) == []
    result = check_fmu(fmu)
    assert result.steps == 360 and result.passed(1e-12), result
    with zipfile.ZipFile(fmu) as archive:
        names = set(archive.namelist())
        xml = archive.read("modelDescription.xml").decode()
    assert 'fmiVersion="3.0"' in xml and 'causality="independent"' in xml
    assert {"sources/fmi3.c", "sources/buildDescription.xml",
            f"binaries/x86_64-linux/{model}.so"} <= names


def test_calls_discards_and_states_from_a_fresh_process(native3):
    """``fmu3_host.py`` in a new process: parameters in initialisation mode against the
    direct solver (1e-12), 16 kinds of bad call each an error naming itself, the discard
    of an unassemblable angle and the right next step, bit-exact state round trips, a
    corrupted state, a wrong token and event mode refused."""
    run = subprocess.run([sys.executable, str(Path(__file__).with_name("fmu3_host.py")),
                          str(native3 / "FourBar.fmu")], capture_output=True, text=True,
                         timeout=300)
    assert run.returncode == 0, run.stdout[-4000:] + run.stderr[-2000:]
    assert run.stdout.count("PASS ") >= 30 and "FAIL" not in run.stdout


def test_run_fmu_names_the_discarded_step(native3):
    """fmpy's FMI 3.0 path raises at a discarded step; ``run_fmu`` turns that into the same
    ``FMURunError`` as for FMI 2.0: the first unassemblable input row and the reason."""
    import numpy as np

    from linkage_fmu import presets
    from linkage_fmu.fmi.run import FMURunError, revolution, run_fmu

    mech = presets.get("four_bar", l_AB=0.3)
    u = revolution(mech, 72)
    valid = mech.solve(*(u[n] for n in mech.input_names), method="direct").valid
    first = int(np.argmin(valid))
    with pytest.raises(FMURunError, match=f"ended at step {first} of 72") as err:
        run_fmu(native3 / "FourBar.fmu", u, start_values={"l_AB": 0.3})
    assert "cannot be assembled" in str(err.value)
    rows = run_fmu(native3 / "FourBar.fmu", revolution(presets.get("four_bar"), 36))
    ref = presets.get("four_bar").solve(*(rows[n].to_numpy() for n in mech.input_names),
                                        method="direct")
    assert np.max(np.abs(rows["Mb"].to_numpy() - ref["Mb"])) <= 1e-12 * np.max(np.abs(ref["Mb"]))

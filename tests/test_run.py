"""``linkage_fmu.fmi.run.run_fmu``: rows pair each input with the outputs it gives, and a
run that stops early raises naming the step and the reason."""

from __future__ import annotations

import math

import numpy as np
import pytest

from linkage_fmu import presets
from linkage_fmu.fmi.run import FMURunError, revolution, run_fmu


@pytest.mark.parametrize("flavour", ["pythonfmu", "native"])
def test_rows_pair_inputs_with_their_outputs(dist, native_dist, flavour):
    """Every output of every row equals the direct solver at that row's own inputs
    (1e-12 of each output's largest value); 72 rows for 72 steps."""
    fmu = (native_dist if flavour == "native" else dist) / "FourBar.fmu"
    rows = run_fmu(fmu, steps=72)
    mech = presets.get("four_bar")
    assert len(rows) == 72
    ref = mech.solve(*(rows[n].to_numpy() for n in mech.input_names), method="direct")
    for name in mech.output_names:
        scale = np.max(np.abs(ref[name]))
        assert np.max(np.abs(rows[name].to_numpy() - ref[name])) <= 1e-12 * scale, name


@pytest.mark.parametrize("flavour", ["pythonfmu", "native"])
def test_a_discarded_step_raises_naming_it(dist, native_dist, flavour):
    """FourBar with l_AB = 0.3 cannot be assembled near theta = pi: both flavours discard
    that step, and the run raises at the first such input row, with the FMU's reason."""
    fmu = (native_dist if flavour == "native" else dist) / "FourBar.fmu"
    mech = presets.get("four_bar", l_AB=0.3)
    u = revolution(mech, 72)
    valid = mech.solve(*(u[n] for n in mech.input_names), method="direct").valid
    first = int(np.argmin(valid))
    with pytest.raises(FMURunError, match=f"ended at step {first} of 72") as err:
        run_fmu(fmu, u, start_values={"l_AB": 0.3})
    assert err.value.step == first and math.isclose(err.value.time, float(u["time"][first]))
    assert "the linkage cannot be assembled: the dyad B-C-D cannot close" in str(err.value)


@pytest.mark.parametrize("flavour", ["pythonfmu", "native", "native3"])
def test_a_linkage_that_turns_part_of_a_revolution_is_checked_where_it_assembles(
        tmp_path, flavour):
    """FourBar built with l_AB = 0.3 assembles where cos(theta) >= -0.71875: check_fmu
    compares every other step with the direct solver (to 1e-12) and reports the angles
    of the discarded steps, exactly the run's angles beyond that limit; run_fmu with
    strict=False gives NaN rows there and the solver's numbers elsewhere."""
    from fmu_cache import build_fmu, build_native_fmu
    from linkage_fmu.fmi import check_fmu

    if flavour == "pythonfmu":
        fmu = build_fmu("four_bar", tmp_path, l_AB=0.3)
    else:
        fmu = build_native_fmu("four_bar", tmp_path, 3 if flavour == "native3" else 2,
                               l_AB=0.3)
    result = check_fmu(fmu, steps=72)
    mech = presets.get("four_bar", l_AB=0.3)
    u = revolution(mech, 72)[:-1]
    bad = np.cos(u["theta"]) < -0.71875
    assert result.passed(1e-12) and result.mismatched == 0 and result.steps == 72
    assert len(result.unsolved_deg) == 1
    first, last = result.unsolved_deg[0]
    assert first == np.degrees(u["theta"][bad][0]) and last == np.degrees(u["theta"][bad][-1])
    rows = run_fmu(fmu, steps=72, strict=False)
    assert rows["solved"].to_numpy().tolist() == (~bad).tolist()
    assert rows["Mb"][bad].isna().all()
    ref = mech.solve(*(u[n] for n in mech.input_names), method="direct")
    np.testing.assert_allclose(rows["Mb"][~bad], ref["Mb"][~bad], rtol=1e-12,
                               atol=1e-12 * np.nanmax(np.abs(ref["Mb"])))


def test_an_fmu_with_fmpys_default_logger_logs_safely_after_a_run(native_dist, tmp_path):
    """run_fmu registers its own logger with fmpy's logger proxy, which forwards every
    FMI 2.0 instance's messages in the process to the last logger registered; after the
    run the proxy is fmpy's printing logger again. A fresh process runs the FMU, then
    makes an instance with fmpy's default callbacks and a call it refuses with a log:
    before, that log called the run's freed logger and the process died (SIGSEGV)."""
    import subprocess
    import sys

    fmu = native_dist / "FourBar.fmu"
    script = f"""
from fmpy import extract, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Slave
from linkage_fmu.fmi.run import run_fmu
import gc
run_fmu({str(fmu)!r}, steps=8)
gc.collect()
md = read_model_description({str(fmu)!r})
s = FMU2Slave(guid=md.guid, modelIdentifier="FourBar", unzipDirectory=extract({str(fmu)!r}))
s.instantiate(loggingOn=True)
try:
    s.doStep(0.0, 0.1)  # not initialised: refused with an Error, and a log
except FMICallException as err:
    print("refused", err.status)
s.freeInstance()
"""
    run = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                         cwd=tmp_path, timeout=120)
    assert run.returncode == 0, run.stderr[-2000:]
    assert "refused 3" in run.stdout and "fmi2DoStep is not allowed in state" in run.stdout

"""FMU states restore the whole instance, and a serialized state is taken whole or refused
whole: the four-bar's FMU in both flavours, FMI 2.0 and 3.0, each driven from a fresh
process (``state_host.py``) so that a crash fails the test.

- Restore into a fresh instance (fmusim's ``--initial-fmu-state-file`` flow: instantiate,
  deserialize, set, read, step): the instance is in the mode the state was taken in, and
  its outputs, then a step's, equal the direct solver's (``method="direct"``) at the
  state's parameters and inputs to 1e-12 of max(1, |value|).
- Forged payloads with valid CRC-32s, one field out of range each: the frame (magic,
  format, lengths and text of the model and GUID), the mode, the time, every parameter
  (non-finite, breaking its rule), the integer and string parameters (values not
  allowed, bad lengths, not UTF-8, a NUL), bytes too many or too few. Each is Error with a
  log naming the call, and every variable reads as before; a live state the payload was
  to overwrite is left as it was. Forged payloads that are states this FMU could have
  made are taken, and read as the direct solver says.
- State pointers that are not live states of the instance (NULL, freed, another
  instance's, garbage, an odd address) are Error in every state call, never a crash.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from conftest import run_host
from fmu_cache import build_fmu, build_native_fmu
from linkage_fmu import presets
from linkage_fmu.fmi.variables import variables

HOST = Path(__file__).with_name("state_host.py")
FMUS = {"native-fmi2": ("native", 2), "native-fmi3": ("native", 3),
        "pythonfmu-fmi2": ("pythonfmu", 2), "pythonfmu-fmi3": ("pythonfmu", 3)}
TOLERANCE = 1e-12
MECH = presets.get("four_bar")
OK, ERROR = 0, 3


@pytest.fixture(scope="module")
def fourbar(tmp_path_factory):
    """The four-bar's FMU of each flavour and FMI version, by FMUS key."""
    out = tmp_path_factory.mktemp("states")
    built = {}
    for key, (flavour, version) in FMUS.items():
        build = build_native_fmu if flavour == "native" else build_fmu
        built[key] = build("four_bar", out / key, fmi_version=version)
    return built


def host(job: dict, tmp_path: Path) -> dict:
    return run_host(HOST, job, tmp_path, timeout=600)


def table(flavour):
    return {v.name: (vr, v) for vr, v in enumerate(variables(MECH, flavour))}


def parameters(flavour, **values):
    """The job's parameters by value reference: ``values``, and the direct solver for
    the pythonfmu FMU (the native FMU computes the closed form)."""
    t = table(flavour)
    if flavour == "pythonfmu":
        values.setdefault("method", "direct")
    return {t[name][0]: value for name, value in values.items()}


def inputs(flavour, *rows):
    t = table(flavour)
    return [{t[name][0]: value for name, value in zip(("theta", "omega", "alpha", "load"), row)}
            for row in rows]


def direct(params: dict, row) -> dict:
    """The direct solver's outputs at ``params`` (by name) and the inputs ``row``."""
    mech = presets.get("four_bar", **{k: v for k, v in params.items() if k != "method"})
    sol = mech.solve(*row, method="direct")
    return {name: float(np.asarray(sol[name])) for name in mech.output_names +
            mech.diagnostic_names}


def assert_outputs(flavour, values, params, row):
    outs = [v.name for v in variables(MECH, flavour) if v.causality == "output"]
    ref = direct(params, row)
    for name, value in zip(outs, values):
        assert abs(value - ref[name]) <= TOLERANCE * max(1.0, abs(ref[name])), (name, value,
                                                                                 ref[name])


# -- restore into a fresh instance ------------------------------------------------------
ROWS = [(0.9, 7.0, 1.0, 2.0), (1.3, 6.0, -2.0, 0.5), (2.0, 8.0, 0.0, -1.0), (4.0, 5.0, 3.0, 1.0)]


@pytest.mark.parametrize("key", FMUS)
@pytest.mark.parametrize("mode", ["step", "initialization"])
def test_a_state_restored_into_a_fresh_instance_reads_and_steps(fourbar, key, mode, tmp_path):
    """instantiate -> deserialize -> set -> read -> step: the restored instance is in the
    state's mode (step mode: read and stepped at once; initialisation mode: exited first),
    and every output equals the direct solver's."""
    flavour, version = FMUS[key]
    params = {"l_AB": 0.11, "m2": 2.5}
    out = host({"job": "fresh", "fmu": str(fourbar[key]), "mode": mode,
                "parameters": parameters(flavour, **params),
                "inputs": inputs(flavour, *ROWS)}, tmp_path)
    assert out["errors"] == []
    if mode == "step":
        assert out["restored"] == out["taken"]  # bit for bit
        assert_outputs(flavour, out["restored"], params, ROWS[0])
    for values, row in zip(out["rows"], ROWS[1:]):
        assert_outputs(flavour, values, params, row)
    if version == 3:
        assert out["time"] == pytest.approx(0.1 * len(ROWS), abs=1e-15)


# -- forged payloads -----------------------------------------------------------------------
def forgeries(flavour: str, version: int) -> tuple[list, list]:
    """Edits of a step-mode state that must be refused, and ones that must be taken."""
    bad = [{"key": "magic", "value": b"LKFMUSX\0".hex(), "hex": True},
           {"key": "format", "value": 1}, {"key": "format", "value": 3},
           {"key": "format", "value": 2**32 - 1},
           {"key": "nid", "value": 0}, {"key": "nid", "value": 8},
           {"key": "nid", "value": 2**32 - 1},
           {"key": "id", "value": "FourBaR"}, {"key": "id", "value": "FourBa"},
           {"key": "nguid", "value": 0}, {"key": "nguid", "value": 2**31},
           {"key": "guid", "value": "{not-the-guid-of-this-build-0000000000}"},
           {"key": "mode", "value": 4},  # event mode: this instance does not use it
           {"key": "mode", "value": 5}, {"key": "mode", "value": 6},
           {"key": "mode", "value": 2**32 - 1},
           {"key": "time", "value": math.nan}, {"key": "time", "value": math.inf},
           {"key": "time", "value": -math.inf},
           {"tail": "00"}, {"tail": "0000000000000000"}, {"cut": 1}, {"cut": 4}, {"cut": 40}]
    for _, (vr, v) in table(flavour).items():
        key = f"value {vr}"
        if v.causality == "parameter" and v.type == "Real":
            values = [math.nan, math.inf, -math.inf]
            values += {"> 0": [0.0, -1.0, -5e-324], ">= 0": [-1.0, -5e-324]}.get(v.rule, [])
            values += [v.minimum - 1.0] if math.isfinite(v.minimum) else []
            values += [v.maximum + 1.0] if math.isfinite(v.maximum) else []
            bad += [{"key": key, "value": x} for x in values]
        elif v.type == "Integer":
            bad += [{"key": key, "value": x} for x in (0, 2, -2, 2**31 - 1, -2**31)]
        elif v.type == "String":
            length = f"length {vr}"
            bad += [{"key": key, "value": x} for x in ("", "bogus", "closed_form ")]
            bad += [{"key": key, "value": x, "hex": True}
                    for x in ("ff", "636c6f7365645f666f726d00", "c0af")]  # not UTF-8, NUL
            bad += [{"key": length, "value": x} for x in (0, 10, 12, 2**31, 2**32 - 1)]
            if flavour == "native":
                bad.append({"key": key, "value": "direct"})  # the pythonfmu FMU's, not ours
    t = table(flavour)
    good = [{"key": f"value {t['theta'][0]}", "value": 0.7},
            {"key": f"value {t['l_AB'][0]}", "value": 0.12},
            {"key": f"value {t['g'][0]}", "value": 0.0}]
    return bad, good


@pytest.mark.parametrize("key", FMUS)
def test_forged_payloads_are_refused_whole(fourbar, key, tmp_path):
    """Every forged payload (valid CRC, one field out of range) is Error, logged with the
    call's name; every variable reads as before, and so does a live state it was to
    overwrite; the instance steps on. The payloads that are states this FMU could have
    made are taken, and their outputs are the direct solver's."""
    flavour, version = FMUS[key]
    bad, good = forgeries(flavour, version)
    bad += [dict(edit, reuse=True) for edit in bad[::7]]
    params = {"l_AB": 0.11}
    out = host({"job": "forge", "fmu": str(fourbar[key]),
                "parameters": parameters(flavour, **params),
                "inputs": inputs(flavour, ROWS[0], ROWS[1]), "edits": bad + good}, tmp_path)
    results = out["results"]
    call = "fmi3DeserializeFMUState" if version == 3 else "fmi2DeSerializeFMUstate"
    refused = [r for r in results[:len(bad)] if r["status"] == ERROR and r["unchanged"]
               and r["said"].startswith(call)]
    assert len(refused) == len(bad), [r for r in results[:len(bad)] if r not in refused][:3]
    assert len(bad) >= 90
    assert out["kept_state_intact"] and out["step_after"] == 0
    t = {vr: name for name, (vr, _) in table(flavour).items()}
    for r in results[len(bad):]:
        assert r["status"] == 0 and r["unchanged"], r
        changed = {**params, "method": "direct"} if flavour == "pythonfmu" else dict(params)
        row = list(ROWS[0])
        name = t[int(r["edit"]["key"].split()[1])]
        if name == "theta":
            row[0] = r["edit"]["value"]
        else:
            changed[name] = r["edit"]["value"]
        outs = [v.name for v in variables(MECH, flavour) if v.causality == "output"]
        vr_of = {n: vr for vr, n in t.items()}
        assert_outputs(flavour, [r["read"][str(vr_of[n])] for n in outs], changed, row)


@pytest.mark.parametrize("key", FMUS)
def test_state_pointers_that_are_not_live_states_are_errors(fourbar, key, tmp_path):
    """SetFMUState, SerializedFMUStateSize, FreeFMUState and GetFMUState (update in place)
    with NULL, a freed state, another instance's state, a pointer to other memory and an
    odd address: Error each, with a log, and the instance still steps. DeserializeFMUState
    given such a pointer makes a new state (OK, and it can be freed): the standards leave
    what the pointer holds on entry undefined, and it is never read."""
    flavour, version = FMUS[key]
    out = host({"job": "pointers", "fmu": str(fourbar[key]),
                "parameters": parameters(flavour, l_AB=0.11)}, tmp_path)
    for name, r in out["results"].items():
        assert set(r["statuses"]) == {ERROR}, (name, r)
        assert len(r["said"]) == len(r["statuses"]), (name, r)
        assert r.get("deserialized", [0, 0]) == [0, 0], (name, r)
    # FreeFMUState given the state itself (fmusim 0.0.39's call): freed (OK, the mistake
    # logged as a warning), so that setting it afterwards is an Error
    assert out["by_value"][:2] == [OK, ERROR]
    assert "given the FMU state itself" in out["by_value"][2]
    assert out["step_after"] == 0

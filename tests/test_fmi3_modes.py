"""FMI 3.0: event mode for an importer that uses it, and the variables' dependencies at
run time, for the native and the pythonfmu FMUs, each driven from a fresh process
(``state_host.py``).

- ``fmi3InstantiateCoSimulation`` with ``eventModeUsed = true`` instantiates (the
  modelDescription says ``hasEventMode="true"``, which FMI 3.0 requires for it):
  ExitInitializationMode enters event mode, UpdateDiscreteStates asks for nothing, steps
  never ask for an event, and outputs read in event mode and after each step equal the
  direct solver's to 1e-12 of max(1, |value|).
- ``fmi3GetNumberOfVariableDependencies``/``fmi3GetVariableDependencies`` answer what the
  modelDescription's ``<ModelStructure>`` (parsed by fmpy) declares: an output's
  ``InitialUnknown`` dependencies before ExitInitializationMode, its ``Output`` ones after,
  kind ``dependent``; nothing for inputs, parameters and ``time``.
- Every typed get and set (Float32 to Clock) with nValueReferences = nValues = 2**31 over
  an array of four references whose first is unknown answers Error naming entry 0, and
  reads nothing past it: the host (a fresh process) lives, and a valid read after them
  answers OK with the direct solver's value to 1e-12.
"""

from __future__ import annotations

import pytest
from fmpy import read_model_description

from fmu_cache import build_fmu, build_native_fmu
from test_fmu_states import assert_outputs, direct, host, inputs, parameters

FMUS = {"native-four_bar": ("native", "four_bar"), "native-six_bar": ("native", "six_bar"),
        "pythonfmu-four_bar": ("pythonfmu", "four_bar")}
DEPENDENT = 5  # fmi3Dependent
ROWS = [(0.5, 10.0, 0.0, 0.0), (1.1, 7.0, 2.0, 3.0), (2.9, 5.0, -1.0, -2.0)]


@pytest.fixture(scope="module")
def fmus(tmp_path_factory):
    out = tmp_path_factory.mktemp("fmi3")
    return {key: (build_native_fmu if flavour == "native" else build_fmu)(
        preset, out / key, fmi_version=3) for key, (flavour, preset) in FMUS.items()}


@pytest.mark.parametrize("key", FMUS)
def test_dependencies_are_the_model_structure(fmus, key, tmp_path):
    flavour, preset = FMUS[key]
    md = read_model_description(str(fmus[key]))
    out = host({"job": "structure", "fmu": str(fmus[key]), "parameters": {},
                "inputs": []}, tmp_path)
    assert out["errors"] == []
    declared = {u.variable.valueReference: sorted(d.valueReference for d in u.dependencies)
                for u in md.outputs}
    initial = {u.variable.valueReference: sorted(d.valueReference for d in u.dependencies)
               for u in md.initialUnknowns}
    assert set(declared) == set(initial) and declared
    for v in md.modelVariables:
        vr = v.valueReference
        for phase, expected in (("before", initial), ("during", initial), ("after", declared)):
            deps, kinds = out[phase][str(vr)]
            assert deps == expected.get(vr, []), (phase, v.name)
            assert kinds == [DEPENDENT] * len(deps)
    assert all(u.dependenciesKind == ["dependent"] * len(u.dependencies) for u in md.outputs)


@pytest.mark.parametrize("key", ["native-four_bar", "pythonfmu-four_bar"])
def test_event_mode_where_the_importer_uses_it(fmus, key, tmp_path):
    flavour, preset = FMUS[key]
    md = read_model_description(str(fmus[key]))
    assert md.coSimulation.hasEventMode
    params = {"l_AB": 0.12}
    out = host({"job": "structure", "fmu": str(fmus[key]),
                "parameters": parameters(flavour, **params),
                "inputs": inputs(flavour, *ROWS)}, tmp_path)
    assert out["errors"] == []
    assert all(not any(flags[:5]) for flags in out["flags"])
    for k, (r, row) in enumerate(zip(out["rows"], ROWS)):
        assert r["flags"] == [False, False, False]
        assert r["last"] == pytest.approx(0.1 * (k + 1), abs=1e-15)
        assert_outputs(flavour, r["event"], params, row)
        assert_outputs(flavour, r["step"], params, row)


@pytest.fixture(scope="module")
def four_bars(tmp_path_factory):
    out = tmp_path_factory.mktemp("fmi3-four_bar")
    return {flavour: (build_native_fmu if flavour == "native" else build_fmu)(
        "four_bar", out / flavour, fmi_version=3) for flavour in ("native", "pythonfmu")}


TYPES3 = ("Float32", "Float64", "Int8", "UInt8", "Int16", "UInt16", "Int32", "UInt32", "Int64",
          "UInt64", "Boolean", "String", "Binary", "Clock")


@pytest.mark.parametrize("flavour", ["native", "pythonfmu"])
def test_a_count_past_the_array_stops_at_its_first_unknown_reference(four_bars, flavour,
                                                                      tmp_path):
    md = read_model_description(str(four_bars[flavour]))
    unknown = max(v.valueReference for v in md.modelVariables) + 1000
    out = host({"job": "huge", "fmu": str(four_bars[flavour])}, tmp_path)
    calls = [f"fmi3{verb}{t}" for t in TYPES3 for verb in ("Get", "Set")]
    assert sorted(out["results"]) == sorted(calls)
    for call in calls:
        assert out["results"][call] == [3, f"{call}: value reference {unknown} (entry 0) is "
                                        "not a variable of FourBar"], call
    typed = {f"fmi3{verb}{v.type}" for v in md.modelVariables for verb in ("Get", "Set")}
    assert sorted(out["null"]) == sorted(typed & set(calls)) and "fmi3GetFloat64" in typed
    for call, answer in out["null"].items():
        assert answer == [3, f"{call}: the value array is NULL with {2 ** 31} value "
                          "references"], call
    first = next(v.name for v in md.modelVariables if v.causality == "output")
    start = {v.name: float(v.start) for v in md.modelVariables if v.causality == "input"}
    expected = direct({}, [start[n] for n in ("theta", "omega", "alpha", "load")])[first]
    assert out["after"][0] == 0
    assert out["after"][1] == pytest.approx(expected, rel=1e-12, abs=1e-12)

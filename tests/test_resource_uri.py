"""The pythonfmu FMU's resource location: every valid form of its own resources folder is
taken, anything else is a NULL instance with a log naming the location and the reason,
never a crash (pythonfmu's wrapper, behind our layer, only cuts ``file://`` and decodes
``%20``: our layer decodes the URI and hands it a plain absolute path).

The FMU is unpacked into a folder whose path holds a space. FMI 2.0 (``fmu_raw_host.py``):
``file:///`` with ``%20``, ``file:/``, ``file://localhost/``, other characters
percent-encoded (upper and lower case), a trailing slash, and the space left raw (not a
valid URI, but some importers pass it) each instantiate and compute the direct solver's
outputs to 1e-12 of max(1, |value|); another host, a relative reference, a scheme other
than ``file``, bad or NUL escapes, a query, and a folder that is not its resources each
give NULL. FMI 3.0 (a plain path): the folder with and without its trailing slash is
taken; a relative path, a URI, and another folder are refused.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path
from urllib.parse import quote

import pytest

from fmu_cache import build_fmu
from linkage_fmu import presets
from test_fmu_protocol import ERROR, OK, raw, start, variables

INPUTS = [0.8, 6.0, 1.0, 2.0]


@pytest.fixture(scope="module")
def fourbar(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("uri")
    build_fmu("four_bar", out)
    build_fmu("four_bar", out / "fmi3", fmi_version=3)
    return out


def forms(resources: Path) -> tuple[list, list]:
    path = str(resources)
    encoded = quote(path)
    valid = [resources.as_uri(), resources.as_uri() + "/", "file:" + encoded,
             "file://localhost" + encoded, "file://localhost" + encoded + "/",
             "file://" + encoded.replace("FourBar", "%46our%42ar"),
             "file://" + encoded.replace("FourBar", "F%6fur%42ar"),
             "file://" + path]
    invalid = ["file://otherhost" + encoded, "resources", "./resources", "file:resources",
               "file://" + encoded[1:], "http://localhost" + encoded,
               "ftp://" + encoded, "file://" + encoded + "%2", "file://" + encoded + "%zz",
               "file://" + encoded.replace("FourBar", "%00ourBar"),
               "file://" + encoded + "?x=1", "file://" + encoded + "#top",
               resources.parent.as_uri(), Path("/tmp").as_uri(), "", "file:", "file://"]
    return valid, invalid


def test_every_valid_form_is_taken_and_anything_else_refused(fourbar, tmp_path):
    unzip = tmp_path / "with space" / "FourBar"
    resources = unzip / "resources"
    valid, invalid = forms(resources)
    v = variables(fourbar, "FourBar")
    outs = [vr for vr, _, c in v.values() if c == "output"]
    ops = []
    for k, uri in enumerate(valid):
        begin = start(f"v{k}", params={"method": "direct"}, dist=fourbar)
        begin[0] = [f"v{k}", "new", "FourBar", None, True, uri]
        ops += begin + [[f"v{k}", "setReal", [0, 1, 2, 3], INPUTS], [f"v{k}", "doStep", 0.0, 0.1],
                [f"v{k}", "getReal", outs], [f"v{k}", "free"]]
    first_invalid = len(ops)
    ops += [[f"x{k}", "new", "FourBar", None, True, uri] for k, uri in enumerate(invalid)]
    out = raw(fourbar, ops, tmp_path, unzip={"FourBar": str(unzip)})
    r = out["results"]
    mech = presets.get("four_bar")
    ref = mech.solve(*INPUTS, method="direct")
    names = list(mech.output_names + mech.diagnostic_names)
    reads = [res for op, res in zip(ops, r) if op[1] == "getReal"]
    assert len(reads) == len(valid)
    assert all(s == OK for s, _ in r[:first_invalid]), [s for s, _ in r[:first_invalid]]
    for values in (values for _, values in reads):
        for name, value in zip(names, values):
            assert abs(value - ref[name]) <= 1e-12 * max(1.0, abs(ref[name])), name
    assert [s for s, _ in r[first_invalid:]] == [ERROR] * len(invalid)
    errors = out["log"]["3"]
    for uri in invalid:  # FMI 2.0's logger takes a format: '%' comes doubled
        assert any(f"resource location {uri.replace('%', '%%')} " in m for m in errors), uri


def test_fmi3_resource_path_is_a_plain_absolute_path(fourbar, tmp_path):
    unzip = tmp_path / "with space" / "FourBar3"
    resources = unzip / "resources"
    job = {"job": "resources", "fmu": str(fourbar / "fmi3" / "FourBar.fmu"),
           "unzip": str(unzip),
           "paths": [str(resources) + "/", str(resources), "resources/", resources.as_uri(),
                     str(unzip) + "/", str(resources / "nothing") + "/"],
           "inputs": [{"0": INPUTS[0], "1": INPUTS[1], "2": INPUTS[2], "3": INPUTS[3]}]}
    path = tmp_path / "job.json"
    path.write_text(json.dumps(job))
    run = subprocess.run([sys.executable, str(Path(__file__).with_name("state_host.py")),
                          str(path)], capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr[-3000:]
    out = json.loads(run.stdout.splitlines()[-1])
    assert [r["made"] for r in out["results"]] == [True, True, False, False, False, False]
    for r, given in zip(out["results"][2:], job["paths"][2:]):
        assert f"resource location {given} " in r["said"], r
    mech = presets.get("four_bar")
    ref = mech.solve(*INPUTS, method="closed_form")
    names = list(mech.output_names + mech.diagnostic_names)
    for r in out["results"][:2]:
        for name, value in zip(names, r["outputs"]):
            assert abs(value - ref[name]) <= 1e-12 * max(1.0, abs(ref[name])), name

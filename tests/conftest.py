"""Shared fixtures: the presets in every variant, the FMUs, and reference helpers.

FMUs: a test that needs an FMU takes a fixture (``dist``, ``native_dist``, ``native3``,
``dist3``, ``fmu2``) or builds one with ``fmu_cache.build_native_fmu`` or
``fmu_cache.build_fmu`` (the arguments of ``linkage_fmu.fmi``'s, ``out`` required)::

    import fmu_cache
    fmu = fmu_cache.build_native_fmu("four_bar", tmp_path, fmi_version=3, l_AB=0.3)

Each FMU is built once, whatever the test, file or pytest-xdist worker asks for it, and
kept between runs under a hash of all that goes into it (the package's files, the
compilers, fmpy, pythonfmu, Python; see ``tests/fmu_cache.py``); the test gets its own
copy. Call ``linkage_fmu.fmi.build_*`` directly only to test the building itself.
"""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import mpmath
import pytest

import fmu_cache
from linkage_fmu import groups, presets
from linkage_fmu.precise import MP  # noqa: F401  (re-exported for the tests)

#: (preset, parameters) covering every preset and every six-bar driver
VARIANTS = [
    ("scotch_yoke", {}),
    ("scotch_yoke", {"m1": 1.5, "J1": 0.01, "J3": 0.2, "g": 9.81}),
    ("four_bar", {}),
    ("four_bar", {"branch": -1, "beta2": 0.4, "beta3": -0.3, "l_AS1": 0.03, "J1": 0.001}),
    ("slider_crank", {}),
    ("slider_crank", {"e": 0.02, "gamma": 0.7, "m1": 0.5, "J1": 1e-3, "l_OS1": 0.02}),
    ("six_bar", {"driver": "OA"}),
    ("six_bar", {"driver": "AB"}),
    ("six_bar", {"driver": "O1B"}),
    ("six_bar", {"driver": "KD"}),
    ("six_bar", {"driver": "D"}),
    ("slotted_lever", {}),
    ("slotted_lever", {"l_AB": 0.55, "l_AC": 0.25, "l_CS3": -0.1}),  # Whitworth: turns fully
    ("crank_shaper", {}),
    ("crank_shaper", {"branch": -1, "l_AB": 0.2, "h_E": 0.35, "g": 0.0}),
]
IDS = [f"{n}-{'-'.join(f'{k}={v}' for k, v in p.items()) or 'defaults'}" for n, p in VARIANTS]

#: the scalar formulas are evaluated at 40 digits in the tests that use MP
mpmath.mp.dps = 40


@pytest.fixture
def registry():
    """The group types; those a test defines are forgotten after it."""
    saved = dict(groups.Group.registry)
    yield groups.Group.registry
    groups.Group.registry.clear()
    groups.Group.registry.update(saved)


@pytest.fixture(params=VARIANTS, ids=IDS)
def mech(request):
    name, params = request.param
    return presets.get(name, **params)


def effort_name(mech) -> str:
    return mech.effort.name


def power_residual(mech, sol, theta, omega, alpha, load):
    """Mb*omega (or Pb*v) + power of loads and weights - dT/dt, and a scale for it: the
    largest product of magnitudes (|F| |v|, m |a| |v|, ...) among the terms, so that a
    term that is zero by geometry (e.g. a = v x const) does not set the scale."""
    st = mech.kinematics(theta, order=2)
    terms, sizes = [], []
    e = mech.effort
    if e.direction is None:
        terms.append(sol[e.name] * st.w1[e.body] * omega)
    else:
        vx, vy = st.velocity(e.point, omega)
        terms.append(sol[e.name] * (e.direction[0] * vx + e.direction[1] * vy))
    sizes.append(abs(terms[0]))
    for b in mech.bodies:
        vx, vy = st.velocity(b.cg, omega)
        ax, ay = st.acceleration(b.cg, omega, alpha)
        w = st.w1[b.name] * omega
        eps = st.w2[b.name] * omega ** 2 + st.w1[b.name] * alpha
        v = math.hypot(vx, vy)
        terms += [-b.mass * mech.g * vy, -(b.mass * (ax * vx + ay * vy) + b.inertia * eps * w)]
        sizes += [b.mass * mech.g * v, b.mass * math.hypot(ax, ay) * v + abs(b.inertia * eps * w)]
    loads = load if isinstance(load, (tuple, list)) else (load,)
    for spec, value in zip(mech.loads, loads):
        w = st.w1[spec.body] * omega
        if spec.kind == "moment":
            terms.append(value * w)
            sizes.append(abs(value * w))
            continue
        ux, uy = spec.direction
        if spec.fixed_in == "link":
            c, s = st.u[spec.body]
            ux, uy = c * ux - s * uy, s * ux + c * uy
        vx, vy = st.velocity(spec.at, omega)
        terms.append(value * (ux * vx + uy * vy))
        sizes.append(abs(value) * math.hypot(vx, vy))
    return sum(terms), max(sizes)


ROOT = Path(__file__).resolve().parents[1]
#: the description file of the README's FMU, built besides the presets
EXAMPLE = ROOT / "examples" / "coupler_four_bar.toml"


def _build_script():
    """``build_fmu.py`` as a module: its list of linkages and flavours."""
    import importlib.util

    spec = importlib.util.spec_from_file_location("build_fmu_script", ROOT / "build_fmu.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="session")
def dist(tmp_path_factory) -> Path:
    """What ``build_fmu.py --no-check --platforms host`` writes (every preset and example
    description, pythonfmu FMUs in the folder, native ones in ``native/``), with the
    presets' cross-check files; each FMU built once (``fmu_cache``)."""
    from linkage_fmu.fmi import write_crosscheck

    out = tmp_path_factory.mktemp("dist")
    script = _build_script()
    for source in (*presets.names(), *map(str, script.EXAMPLES)):
        fmu_cache.build_fmu(source, out)
        fmu_cache.build_native_fmu(source, out / script.FLAVOURS["native"])
    for preset in presets.names():
        write_crosscheck(out, presets.get(preset), steps=90)
    return out


@pytest.fixture(scope="session")
def native_dist(tmp_path_factory) -> Path:
    """The native FMUs of the presets and of the README's description file (no check),
    with their cross-check files; built once (``fmu_cache``)."""
    from linkage_fmu.fmi import fmu_linkage, write_crosscheck

    out = tmp_path_factory.mktemp("native")
    for source in (*presets.names(), EXAMPLE):
        fmu = fmu_cache.build_native_fmu(source, out)
        write_crosscheck(out, fmu_linkage(fmu), steps=90)
    return out


@pytest.fixture(scope="session")
def native3(tmp_path_factory) -> Path:
    """The native FMI 3.0 FMUs of the presets and of the README's description file."""
    out = tmp_path_factory.mktemp("native3")
    for source in (*presets.names(), EXAMPLE):
        fmu_cache.build_native_fmu(source, out, fmi_version=3)
    return out


@pytest.fixture(scope="session")
def dist3(tmp_path_factory) -> Path:
    """The pythonfmu FMI 3.0 FMU of the four-bar."""
    out = tmp_path_factory.mktemp("dist3")
    fmu_cache.build_fmu("four_bar", out, fmi_version=3)
    return out


#: the FMI 2.0 FMUs of both flavours: the same framework, the same answers
FLAVOURS = ("pythonfmu", "native")


@pytest.fixture(params=FLAVOURS)
def fmu2(request) -> Path:
    """The folder of the FMI 2.0 FMUs of one flavour (the test runs once per flavour)."""
    return request.getfixturevalue("dist" if request.param == "pythonfmu" else "native_dist")


#: preset -> model identifier of its FMU
MODELS = {name: presets.preset(name).model for name in presets.names()}


def run_host(script: Path, job: dict, tmp_path: Path, timeout: float = 600) -> dict:
    """Run the host ``script`` on ``job`` (written as JSON) in a fresh process, so that a
    crash of an FMU fails the test instead of ending pytest; its last line of output,
    parsed (NaN and infinities as floats)."""
    import json

    path = tmp_path / "job.json"
    path.write_text(json.dumps(job))
    run = subprocess.run([sys.executable, str(script), str(path)], capture_output=True,
                         text=True, timeout=timeout)
    assert run.returncode == 0, f"host exited with {run.returncode}:\n{run.stderr[-3000:]}"
    return json.loads(run.stdout.splitlines()[-1], parse_constant=float)

"""The motion of linkages driven by several actuators under given efforts
(linkage_fmu.driven_motion): the energy balance against the independent reference
(tests/multibody.py), a held pose, and each bad input refused with its reason."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import linkage_fmu
import multibody
from linkage_fmu.descriptions import Description
from linkage_fmu.errors import InputError

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
#: example -> (constant efforts, start coordinates, start speeds, its load, where it acts
#: and its direction, the load's body)
RUNS = {
    "excavator": ([170000.0, -32000.0, -14000.0], [0.0, 0.0, 0.0], [0.05, -0.1, 0.1],
                  {"F_T": 5000.0}, ("bucket", "T", (0.0, -1.0))),
    "five_bar": ([-0.68, 0.73], [1.9, 1.2], [1.0, -0.5], {"P": 2.0},
                 ("2", "C", (0.0, -1.0))),
    "dump_body": ([60000.0], [0.0], [0.02], {"W": 8000.0}, ("body", "G", (0.0, -1.0))),
}


@pytest.mark.parametrize("name", RUNS)
def test_the_efforts_work_is_the_kinetic_energy_gained_and_the_loads_work(name):
    """Constant efforts do work ``u . (q1 - q0)``, a constant load ``F . (r1 - r0)`` and
    gravity ``-(V1 - V0)``; their sum equals ``T1 - T0``, both energies the reference's
    (from its own kinematics), to 1e-6 of the work."""
    efforts, q0, v0, loads, (body, at, direction) = RUNS[name]
    mech, ref = linkage_fmu.load(EXAMPLES / f"{name}.toml"), multibody.read(
        EXAMPLES / f"{name}.toml")
    run = mech.simulate(efforts, np.linspace(0.0, 0.4, 9), q0, v0, **loads)
    coords = [[d.inputs[0] for d in mech.drivers], [d.inputs[1] for d in mech.drivers]]
    q1, v1 = (run[c].iloc[-1].to_numpy() for c in coords)
    assert np.max(np.abs(q1 - q0)) > 1e-3  # it moves
    (T0, V0), (T1, V1) = ref.energy(q0, v0), ref.energy(q1, v1)
    r0, r1 = ref.point(body, at, ref.positions(q0)), ref.point(body, at, ref.positions(q1))
    load = next(iter(loads.values())) * np.asarray(direction)
    work = [float(np.dot(efforts, q1 - np.asarray(q0))), float(load @ (r1 - r0)), V0 - V1]
    assert sum(work) == pytest.approx(T1 - T0, abs=1e-6 * sum(map(abs, work)))
    for d, u in zip(mech.drivers, efforts):  # the solve along it takes the efforts applied
        assert run[d.effort].to_numpy() == pytest.approx(u, rel=1e-9)


def test_a_pose_held_by_its_static_efforts_stays():
    five = linkage_fmu.load(EXAMPLES / "five_bar.toml")
    held = five.solve(theta_A=1.8, theta_E=1.3, omega_A=0.0, P=3.0)
    run = five.simulate({"Mb_E": held["Mb_E"], "Mb_A": held["Mb_A"]}, [0.0, 1.0],
                        [1.8, 1.3], [0.0, 0.0], P=3.0)
    assert run["theta_A"].to_numpy() == pytest.approx(1.8, abs=1e-9)
    assert run["theta_E"].to_numpy() == pytest.approx(1.3, abs=1e-9)


@pytest.mark.parametrize("efforts, q0, v0, options, message", [
    ([1.0], None, None, {}, "five_bar: efforts must be one per driver (Mb_A, Mb_E): a "
                            "sequence of 2 or a dict by name, got [1.0]"),
    ({"Mb_A": 1.0, "Mb_B": 2.0}, None, None, {},
     "five_bar: efforts must give each driver's, Mb_A, Mb_E; unknown: Mb_B; missing: Mb_E"),
    ([1.0, 2.0], [1.9], None, {}, "q0 must give each driver's coordinate (theta_A, "
                                  "theta_E), got [1.9]"),
    ([1.0, [1.0, 2.0, 3.0]], None, None, {}, "Mb_E must be a number, a callable or one "
                                             "value per time: 2 values, got shape (3,)"),
    ([1.0, float("nan")], None, None, {}, "Mb_E"),
    ([1.0, 2.0], None, None, {"flywheel": 1.0}, "five_bar: a flywheel is on a crank "
                                                "driven alone; this linkage is driven by time"),
])
def test_bad_input_is_refused_naming_it(efforts, q0, v0, options, message):
    five = linkage_fmu.load(EXAMPLES / "five_bar.toml")
    with pytest.raises(InputError) as err:
        five.simulate(efforts, [0.0, 0.1], q0, v0, **options)
    assert message in str(err.value)


def test_a_pose_the_motion_cannot_reach_is_an_error_naming_the_time():
    dump = linkage_fmu.load(EXAMPLES / "dump_body.toml")
    with pytest.raises(linkage_fmu.AssemblyError, match=r"reached at t = "):
        dump.simulate([2e6], np.linspace(0.0, 2.0, 3), [0.0], [0.0])


def test_friction_is_refused_with_the_reason():
    text = (EXAMPLES / "dump_body.toml").read_text() + "\n[friction.P]\nmu = 0.1\n"
    dump = Description.from_toml(text, "dump_body.toml").build()
    with pytest.raises(InputError, match="dump_body: simulate moves a linkage driven by "
                                         "time without friction, so far"):
        dump.simulate([60000.0], [0.0, 0.1], [0.0], [0.02])

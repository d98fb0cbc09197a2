"""The function files of the equilibrium equations (linkage_fmu.equation_files): the
scotch yoke's MATLAB file, run in GNU Octave, against its worked example's printed
values (F(x) at 60, 150 and 220 deg, four decimals); every preset's and example's file,
in Octave and in Python, against ``solve`` at random states (1e-12 of the largest
unknown). The worked example's FR12x carries the opposite sign (its x axis points the
other way): its FR12x is our -Fx_B.
"""

from __future__ import annotations

import math
import shutil
import subprocess

import numpy as np
import pytest

from linkage_fmu import presets
from linkage_fmu.equation_files import function_inputs, function_name
from linkage_fmu.equations import equations
from linkage_fmu.errors import InputError
from test_equations import H2, LINKAGES, WORKED, random_states

OCTAVE = shutil.which("octave")
needs_octave = pytest.mark.skipif(OCTAVE is None, reason="GNU Octave is not installed "
                                  "(Debian's octave; .ci/run installs it where it can)")


def octave(directory, calls: list[str]) -> list[np.ndarray]:
    """Each call's result (a column vector) from one Octave run in ``directory``."""
    script = "".join(f"x = {c}; fprintf('%.17g ', x); fprintf('\\n');\n" for c in calls)
    (directory / "run_all.m").write_text(script)
    done = subprocess.run([OCTAVE, "--no-gui", "--quiet", "--no-window-system",
                           "--eval", "run_all"], cwd=directory, capture_output=True,
                          text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    return [np.array([float(v) for v in line.split()]) for line in done.stdout.splitlines()]


def call(mech, state: dict) -> str:
    values = function_inputs(mech, state).values()
    return f"{function_name(mech)}({', '.join(repr(v) for v in values)})"


@needs_octave
def test_the_scotch_yoke_s_matlab_file_gives_the_worked_example_s_values(tmp_path):
    yoke = presets.get("scotch_yoke")
    eq = equations(yoke, math.radians(60), 10.0, load=400.0)
    (tmp_path / "scotch_yoke.m").write_text(eq.to("matlab"))
    got = octave(tmp_path, [f"scotch_yoke({math.radians(d)!r}, 10, 0, 400)" for d in WORKED])
    for x, (FR23, FR4, FR12x, FR12y, Mb) in zip(got, WORKED.values()):
        u = dict(zip(eq.unknowns, x))
        assert (round(u["N_slot"], 4), round(-u["M_guide"] / H2, 4), round(-u["Fx_B"], 4),
                round(u["Fy_B"], 4), round(u["Mb"], 4)) == (FR23, FR4, FR12x, FR12y, Mb)


@needs_octave
def test_every_linkage_s_matlab_file_is_solve_s(tmp_path):
    """One Octave run over every preset's and example's file, three states each, the
    file traced at the first."""
    calls, want = [], []
    for name, make in LINKAGES:
        mech = make()
        states = list(random_states(mech, 3, seed=11))
        eq = equations(mech, **states[0][0])
        (tmp_path / f"{function_name(mech)}.m").write_text(eq.to("matlab"))
        for state, _ in states:
            calls.append(call(mech, state))
            want.append((name, equations(mech, **state)))
    for x, (name, eq) in zip(octave(tmp_path, calls), want):
        ref = np.array(list(eq.solution.values()))
        assert np.max(np.abs(x - ref)) <= 1e-12 * np.max(np.abs(ref)), name


@pytest.mark.parametrize("name, make", LINKAGES, ids=[n for n, _ in LINKAGES])
def test_every_linkage_s_python_file_is_solve_s(name, make):
    """The Python file at three states; its effort against ``solve``'s too."""
    mech = make()
    states = list(random_states(mech, 3, seed=11))
    namespace = {}
    exec(equations(mech, **states[0][0]).to("python"), namespace)  # our own generated code
    function = namespace[function_name(mech)]
    for state, sol in states:
        x = function(*function_inputs(mech, state).values())
        eq = equations(mech, **state)
        ref = np.array(list(eq.solution.values()))
        assert np.max(np.abs(x - ref)) <= 1e-12 * np.max(np.abs(ref))
        for k, e in enumerate(mech.efforts):
            assert x[len(ref) - len(mech.efforts) + k] == pytest.approx(sol[e.name], rel=1e-12,
                                                                      abs=1e-12 * np.max(
                                                                          np.abs(ref)))


def test_a_state_the_file_was_not_written_for_stops_with_the_reason():
    """The four-bar's file with a coupler too short to close the loop stops with the
    solver's reason; an unknown format is refused."""
    four = presets.get("four_bar")
    text = equations(four, 0.3, 10.0).to("python")
    namespace = {}
    exec(text.replace("l_BC = 0.35", "l_BC = 0.001"), namespace)  # our own generated code
    with pytest.raises(ValueError, match="cannot be assembled"):
        namespace["four_bar"](0.3, 10.0, 0.0, 0.0)
    with pytest.raises(InputError, match="format 'fortran'"):
        equations(four, 0.3, 10.0).to("fortran")

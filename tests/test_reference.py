"""docs/description.md is what the code writes, and what the code writes lists what the
code declares: every table and key, every parameter kind, every group type with every
field (one registered in a test too), every load key, every output kind, the outputs
every linkage has, the expression functions and the units; its TOML is valid."""

from __future__ import annotations

import difflib
import inspect
import math
import os
import re
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

from linkage_fmu import expressions, groups, parameters, presets, units
from linkage_fmu.descriptions import Description, schema, topology
from linkage_fmu.manual import reference
from linkage_fmu.outputs import SHAKING

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "description.md"
REGENERATE = ("regenerate it: linkage-fmu reference -o docs/description.md (or python -m "
              "linkage_fmu.manual.reference > docs/description.md)")


@pytest.fixture(scope="module")
def text() -> str:
    return reference.markdown()


def section(text: str, heading: str) -> str:
    """The section under the heading line ``heading`` (``## ...`` or ``### ...``), up to
    the next heading of its level or above."""
    lines = text.splitlines()
    fenced, levels = False, []
    for line in lines:  # the heading level of each line, 0 for text and code
        fenced ^= line.startswith("```")
        mark = line.split(" ")[0]
        levels.append(len(mark) if not fenced and mark and set(mark) == {"#"} else 0)
    assert heading in lines, f"no heading {heading!r}"
    start = lines.index(heading) + 1
    level = levels[start - 1]
    end = next((k for k in range(start, len(lines)) if 0 < levels[k] <= level), len(lines))
    return "\n".join(lines[start:end])


def keys_listed(part: str) -> list[str]:
    """The keys in the first column of the tables of ``part``, in order."""
    return re.findall(r"^\| `([^`]+)` \|", part, flags=re.M)


def test_the_committed_reference_is_what_the_code_writes(text):
    written = DOC.read_text(encoding="utf-8")
    if written != text:
        diff = difflib.unified_diff(written.splitlines(), text.splitlines(),
                                    "docs/description.md", "reference.markdown()", n=1,
                                    lineterm="")
        pytest.fail(f"docs/description.md is not what the code writes; {REGENERATE}\n"
                    + "\n".join(list(diff)[:40]))


def test_the_script_prints_the_reference(text):
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(
        [str(ROOT / "src")] + [p for p in [os.environ.get("PYTHONPATH")] if p])}
    run = subprocess.run([sys.executable, "-m", "linkage_fmu.manual.reference"], env=env,
                         capture_output=True, text=True, encoding="utf-8")
    assert run.returncode == 0, run.stderr
    assert run.stdout == text
    assert run.stderr == ""  # the angle it warns about is caught, shown in the text


def test_it_says_angles_are_radians_and_lists_the_units(text):
    units_part = section(text, "## Units and angles")
    assert ("**Everything is SI, and angles are radians unless a unit says otherwise.**"
            in units_part)
    for example in ("240 mm", "1800 rpm", "30 deg", "8 bar * pi * bore**2 / 4"):
        assert f'`"{example}"`' in units_part
    # checked against the kind, in the checker's words; a plain angle beyond 2 pi warns
    assert ("`l_AB = '1800 rpm' must be a length (m), but it is an angular speed (rad/s)`"
            in units_part)
    assert "with `bore` = 0.086 m is a force of 4647.0 N" in units_part
    assert ("[bodies.1] cg angle = 90 is taken in radians (5156.62 deg); write \"90 deg\" "
            "for degrees" in units_part)
    names = section(text, "## Unit names")
    assert keys_listed(names) == list(units.PINT)
    for unit, pint in units.PINT.items():
        assert f"| `{unit}` | {units.NAMES[unit]} | `{pint}` |" in names


def test_every_table_and_its_keys(text):
    tables = section(text, "## The tables")
    assert [f"`{h}`" for h, _ in schema.TABLES.values()] + [
        f"`{h}`" for h, _ in topology.TABLES.values()] == re.findall(
        r"^\| (`[^`]+`) \|", tables, flags=re.M)
    for header, holds in schema.TABLES.values():
        assert f"| `{header}` | {holds} |" in tables
    for heading, keys in [("### `[joints]`", topology.JOINT_KEYS),
                          ("### `[[links]]`", topology.LINK_KEYS),
                          ("### The frame's entry in `[[links]]`", topology.FRAME_KEYS),
                          ("### `[crank]`", topology.CRANK_KEYS)]:
        part = section(text, heading)
        assert keys_listed(part) == list(keys), heading
        for key, meaning in keys.items():
            assert f"| `{key}` | {meaning} |" in part
    for heading, keys in [("## `[linkage]`", schema.LINKAGE_KEYS),
                          ("## `[bodies.L]`", {**schema.BODY_KEYS,
                                               **schema.CG_KEYS}),
                          ("## `[effort]`", {**schema.EFFORT_KEYS,
                                             **schema.EFFORT_CHOICE_KEYS})]:
        part = section(text, heading)
        assert keys_listed(part) == list(keys), heading
        for key, meaning in keys.items():
            assert f"| `{key}` | {meaning} |" in part
    assert "| `mass` | mass of the link, kg (default 0) |" in text
    assert "moment of inertia about its centre of mass, kg.m2" in text


def test_every_parameter_kind_with_its_unit_and_rule(text):
    part = section(text, "## `[parameters]`")
    assert keys_listed(part) == list(schema.PARAMETER_KEYS) + list(parameters.KINDS)
    assert "| `length` | `m` | a length | > 0 |" in part
    assert "| `inertia` | `kg.m2` | a moment of inertia | >= 0 |" in part
    assert "| `branch` |  |  | +1 or -1 |" in part
    for kind in parameters.KINDS:
        unit, rule = parameters.unit_and_rule(kind)
        assert re.search(rf"^\| `{kind}` \| {re.escape(f'`{unit}`' if unit else '')} \|.*"
                         rf"\| {re.escape(rule)} \|$", part, flags=re.M), kind


def test_every_group_type_and_every_field_in_its_section(text):
    part = section(text, "## `[[groups]]`")
    assert "driver (`crank` or `cylinder`)" in part
    assert keys_listed(part.split("The group types:")[0]) == list(groups.ROLES)
    assert set(groups.ROLE_MEANINGS) == set(groups.ROLES)
    assert part.index("### `crank`") < part.index("### `RRR`")  # the driver first
    for kind, cls in groups.Group.registry.items():
        own = section(text, f"### `{kind}`")
        assert keys_listed(own) == list(cls.FIELDS), kind
        for key, f in cls.FIELDS.items():
            optional = "yes" if key in cls.OPTIONAL else ""
            unit = f"`{f.unit}`" if f.unit else ""
            assert f"| `{key}` | {f.role} | {unit} | {optional} | {f.description} |" in own
        assert ("It drives the linkage" in own) == cls.DRIVER
    # the docstring's first paragraph is the summary, in Markdown
    rrr = section(text, "### `RRR`")
    assert rrr.startswith("\nDyad of two links joined at `middle` (the argument `C`)")
    assert "| `branch` | branch |  |  | +1: middle to the left of the line end1 -> end2" in rrr
    assert "| `angle` | angle | `rad` | yes | direction from 'from'" in text
    assert "In the shipped linkages `four_bar`, `six_bar`." in rrr


def test_a_group_type_defined_elsewhere_is_in_the_reference(registry, text):
    """A type registered here, with no change to the reference's code, has its section:
    summary, driver, every field with role, unit and whether it is optional."""

    class Motor(groups.Crank):
        """A crank driven through a gearbox: ``link`` turns ``ratio`` times the motor's
        angle about ``pivot``.

        Nothing of this paragraph is the summary.
        """

        kind = "geared_motor"
        FIELDS = {**groups.Crank.FIELDS,
                  "ratio": groups.Field("coordinate", "turns of link per turn of the motor"),
                  "offset": groups.Field("angle", "the link's angle at the motor's zero")}
        OPTIONAL = ("ratio", "offset")
        DRIVER = True

    new = reference.markdown()
    assert new != text
    own = section(new, "### `geared_motor`")
    assert own.startswith("\nA crank driven through a gearbox: `link` turns `ratio` times "
                          "the motor's angle about `pivot`.\n\nIt drives the linkage")
    assert "Nothing of this paragraph" not in new
    assert "| `ratio` | coordinate | `m` | yes | turns of link per turn of the motor |" in own
    assert "| `offset` | angle | `rad` | yes | the link's angle at the motor's zero |" in own
    assert "| `pivot` | point |  |  | the placed point the crank turns about |" in own
    assert "In the shipped linkages" not in own
    assert "driver (`crank` or `cylinder` or `geared_motor`)" in new
    # the new type's section is the only change
    assert new.replace("### `geared_motor`\n" + own + "\n", "").replace(
        "(`crank` or `cylinder` or `geared_motor`)", "(`crank` or `cylinder`)") == text


def test_every_load_key_with_its_default(text):
    part = section(text, "## `[[loads]]`")
    assert keys_listed(part) == list(schema.LOAD_KEYS)
    assert "| `period_deg` | `360.0` | the table's period, degrees of crank angle" in part
    assert "| `fixed_in` | `\"frame\"` |" in part
    assert "| `start` | `0.0` |" in part
    assert "| `value` |  | a load over the cycle: an expression of theta (rad)" in part
    for words in ('`value = "EXPR"`', "the positions `x_P`, `y_P` (m)", '`table = "FILE.csv"`',
                  "the columns `theta_deg` and `value`", "relative to the",
                  "`table = [[theta_deg, value], ...]`", "default 360 degrees",
                  "`table_unit`", "`scale`"):
        assert words in part, words


def test_every_output_kind_and_key(text):
    part = section(text, "## `[[outputs]]`")
    assert set(schema.OUTPUT_KINDS) == set(schema.OUTPUT_KEYS)
    assert keys_listed(part.split("### ")[0]) == list(schema.OUTPUT_KEYS)
    for kind, keys in schema.OUTPUT_KEYS.items():
        assert f"| `{kind}` | {schema.OUTPUT_KINDS[kind]} |" in part
        own = section(text, f'### `kind = "{kind}"`')
        assert keys_listed(own) == list(keys), kind


def test_the_outputs_every_linkage_has_with_the_codes_descriptions(text):
    part = section(text, "### The outputs every linkage has")
    assert keys_listed(part) == [*SHAKING, "gamma_<joint>", "cond", "J_red", "dJ_red"]
    info = presets.get("four_bar").output_info
    for name in (*SHAKING, "cond", "J_red", "dJ_red"):
        unit, meaning = info[name]
        assert f"| `{name}` | `{unit}` | {meaning} |" in part
    assert ("| `gamma_<joint>` | `rad` | transmission angle of the group at \\<joint> (0 or pi: "
            "toggle) |") in part
    assert info["gamma_C"] == ("rad", "transmission angle of the group at C (0 or pi: toggle)")
    assert "moment about the crank pivot" in info["shake_M"][1]


def test_the_friction_tables_their_keys_and_outputs(text):
    """[friction.J]: every key of the checker's, the outputs a linkage with friction
    adds with the descriptions the code gives them (each pair's naming its two links,
    from a built preset), the sign conventions and eta's definition."""
    part = section(text, "## `[friction.J]`")
    assert keys_listed(part)[:len(schema.FRICTION_KEYS)] == list(schema.FRICTION_KEYS)
    for key, meaning in schema.FRICTION_KEYS.items():
        assert f"| `{key}` | {meaning.replace('|', chr(92) + '|')} |" in part
    mech = presets.get("slider_crank")
    for name in ("Mf_A", "Ff_guide", "P_loss", "eta"):
        unit, meaning = mech.output_info[name]
        assert f"| `{name}` | `{unit}` | {meaning} |" in part, name
    assert mech.output_info["Mf_A"][1].startswith("friction moment in the pin A of link 1 on "
                                                  "link 2, counter-clockwise positive")
    assert "positive along the pair's sliding direction `t = (n_y, -n_x)`" in part
    assert "`eta = 1 - P_loss / P_in`" in part and "NaN where\nnone enters" in part
    assert "[friction.A]\nmu = \"mu_A\"\nradius = \"r_A\"" in part


def test_the_inputs_and_expressions(text):
    part = section(text, "## `[inputs]`")
    assert keys_listed(part) == list(schema.INPUT_UNITS)
    assert "| `theta` | `rad` | `0.0` | crank angle from +x, counter-clockwise |" in part
    assert "| `omega` | `rad/s` | `0.0` | crank angular speed |" in part
    assert "| `alpha` | `rad/s2` | `0.0` | crank angular acceleration |" in part
    part = section(text, "## Expressions")
    assert "the operators `+` `-` `*` `/` `**`, the signs `-` `+`" in part
    assert "the constant `pi`" in part
    assert ("functions " + ", ".join(f"`{n}`" for n in sorted(expressions.FUNCTIONS))
            in part)
    assert "| a load's `value` | `theta` (rad), the parameters, `x_P` and `y_P` (m)" in part
    assert "`\"1 m + 1 s\"` is refused,\n`l_AB = '1 m + 1 s': its units do not agree`." in part


def example_text() -> str:
    return reference.EXAMPLE.read_text(encoding="utf-8")


def test_every_toml_block_is_a_description_or_part_of_one(text):
    """The example is the file as it is; each [[loads]] or [[outputs]] block, added to
    the example, reads, builds and gives its output or load; a block quoted from a
    shipped linkage is what its file says."""
    blocks = re.findall(r"```toml\n(.*?)```", text, flags=re.S)
    assert blocks[-1] == example_text()
    assert text.endswith(f"```toml\n{example_text()}```\n")
    shipped = {name: tomllib.loads(presets.path(name).read_text()) for name in presets.names()}
    added = []
    for block in blocks[:-1]:
        data = tomllib.loads(block)
        if block.startswith(("[[loads]]", "[[outputs]]")):
            d = Description.from_toml(example_text() + "\n" + block, str(reference.EXAMPLE))
            sol = d.build().solve(0.7)
            (kind,) = data
            name = data[kind][0]["name"]
            if kind == "outputs":
                assert sol[name] > 0.0
            else:
                load = next(ld for ld in d.build().loads if ld.name == name)
                assert load.computed
            added.append(name)
        elif "joints" in data:  # a linkage drawn as joints and links, whole
            d = Description.from_toml(block, "drawn_four_bar.toml")
            assert [g["type"] for g in d.groups] == ["crank", "RRR"]
            assert d.build().output_names[:9] == (
                "F01x", "F01y", "F12x", "F12y", "F23x", "F23y", "F03x", "F03y", "Mb")
        else:  # a quotation: the tables of one shipped linkage
            assert any(all(table in file and (table != "effort" or data[table] == file[table])
                           for table in data) for file in shipped.values()), block
    assert added == ["F_spring", "T_cam", "F_gas", "F_C"]


def test_the_loads_over_the_cycle_are_what_they_say():
    d = Description.read(reference.EXAMPLE)
    for block in reference.CYCLE_LOADS:
        d = Description.from_toml(d.to_toml() + "\n" + block, str(reference.EXAMPLE))
    mech = d.build()
    st = mech.kinematics(0.7)
    loads = {ld.name: ld for ld in mech.loads}
    # a spring: 20 N plus 400 N/m per metre C is above 100 mm
    assert loads["F_spring"].at_state(st) == pytest.approx(20 + 400 * (st.p["C"][1] - 0.1))
    assert loads["T_cam"].at_state(st) == pytest.approx(5 * math.sin(1.4))
    # 6 bar at 90 degrees on a 40 mm bore
    st90 = mech.kinematics(math.pi / 2)
    assert loads["F_gas"].at_state(st90) == pytest.approx(6e5 * math.pi * 0.02 ** 2)


def test_the_reference_is_the_same_at_every_call(text):
    assert reference.markdown() == text
    assert inspect.getdoc(reference.markdown).startswith("The reference of the description")

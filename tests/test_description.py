"""Description files and the builder: every problem of a bad file reported at once, with
its table and key; the file is the builder's serialisation; expressions are evaluated
safely; group types fail loudly when incomplete; loads are inputs by name."""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np
import pytest

import linkage_fmu
from conftest import power_residual
from linkage_fmu import Description, DescriptionError, groups, presets
from linkage_fmu.descriptions import Expression

EXAMPLE = Path(__file__).parents[1] / "examples" / "coupler_four_bar.toml"

BAD = '''
[linkage]
name = "broken"
model = "1nvalid"
colour = "red"

[parameters]
L = { default = -1.0, kind = "length", description = "a length" }
m = { default = 1.0, kind = "weight" }

[points]
A = [0, 0]

[[groups]]
type = "crank"
link = "1"
pivot = "A"
tip = "B"
length = "L"

[[groups]]
type = "RRR"
link1 = "2"
link2 = "3"
end1 = "B"
middle = "C"
end2 = "D"
length1 = "L * 2"
length2 = "__import__('os').system('echo hi')"
branch = 1

[[groups]]
type = "RRRR"

[bodies.1]
mass = "mass_of_crank"
cg = { from = "A" }

[bodies.2]
cg = { from = "B", along = 0.1, distance = 0.2 }

[bodies.9]
cg = { from = "A" }

[[loads]]
name = "omega"
body = "2"
kind = "push"

[effort]
name = "Mb"
body = "7"

[[outputs]]
kind = "force"
name = "F12"
by = "1"
on = "2"

[[outputs]]
kind = "force"
name = "F12"
by = "1"
on = "2"
'''


def test_a_malformed_file_lists_every_problem(tmp_path):
    """Each problem names the file, the table (and entry) and key, and why."""
    path = tmp_path / "broken.toml"
    path.write_text(BAD)
    with pytest.raises(DescriptionError) as info:
        linkage_fmu.load(path)
    err = info.value
    text = str(err)
    assert text.startswith(f"{path}: ")
    expected = [
        "[linkage] colour: unknown key",
        "[linkage] model: '1nvalid' must be a C identifier",
        "[parameters] L: default: L must be > 0 (a length), got -1.0",
        "[parameters] m: kind 'weight' is unknown",
        "[[groups]] #2 (RRR) end2: point 'D' is not placed before this group",
        "[[groups]] #2 (RRR) length2: \"__import__('os').system\" is not a function an "
        "expression may call",
        "[[groups]] #3 type: 'RRRR' is not a group type",
        "[bodies.3]: missing: link '3'",
        "[bodies.1] mass: 'mass_of_crank' uses 'mass_of_crank', which is not a parameter",
        "[bodies.2] cg: give along/across or distance/angle, not both",
        "[bodies.9]: no group adds a link '9': a body without a link",
        "[[loads]] #1 (omega) name: 'omega' is already an input or parameter name",
        "[[loads]] #1 (omega) kind: 'push' must be 'force' or 'moment'",
        "[effort] body: '7' is not a moving link",
        "[[outputs]] #2 (F12): output name 'F12x' is used twice",
    ]
    for line in expected:
        assert any(p.startswith(line) for p in err.problems), (line, err.problems)
    assert len(err.problems) == len(expected) + 1  # and F12y used twice
    assert all(line in text for line in expected)


def test_the_file_is_the_builders_serialisation():
    """The README's coupler four-bar composed with the builder equals the file, and both
    give the same numbers."""
    d = (Description("coupler_four_bar", "Four-bar with a coupler-point force and a rocker "
                     "torque", model="CouplerFourBar", frame="0", gravity="g")
         .parameter("l_AB", 0.10, "length", "crank AB")
         .parameter("l_BC", 0.35, "length", "coupler BC")
         .parameter("l_CD", 0.30, "length", "rocker CD")
         .parameter("l_AD", 0.40, "length", "frame AD, D on the +x axis")
         .parameter("P_along", 0.20, "coordinate", "coupler point P from B along BC")
         .parameter("P_across", 0.05, "coordinate", "coupler point P to the left of BC")
         .parameter("m2", 2.0, "mass", "coupler mass", max=100.0)
         .parameter("J2", 0.02, "inertia", "coupler inertia about its centre of mass")
         .parameter("m3", 1.5, "mass", "rocker mass")
         .parameter("J3", 0.012, "inertia", "rocker inertia about its centre of mass")
         .parameter("g", 9.81, "gravity", "gravity along -y")
         .point("A", 0, 0).point("D", "l_AD", 0)
         .group("crank", link="1", pivot="A", tip="B", length="l_AB")
         .group("RRR", link1="2", link2="3", end1="B", middle="C", end2="D",
                length1="l_BC", length2="l_CD", branch=1)
         .group("point", link="2", **{"from": "B"}, name="P", along="P_along",
                across="P_across")
         .body("1", cg={"from": "A"})
         .body("2", mass="m2", inertia="J2", cg={"from": "B", "along": "l_BC / 2"})
         .body("3", mass="m3", inertia="J3", cg={"from": "D", "along": "l_CD / 2"})
         .load("F_P", body="2", kind="force", at="P", direction=[0, -1],
               description="process force at the coupler point P", start=80.0)
         .load("T4", body="3", kind="moment",
               description="torque on the rocker, counter-clockwise positive", start=120.0)
         .effort("Mb", body="1")
         .output("force", name="F12", by="1", on="2", magnitude="F12_abs")
         .output("force", name="F23", by="2", on="3")
         .output("force", name="F03", by="0", on="3", magnitude=True)
         .output("effort", name="Mb")
         .start(omega=25.0))
    from_file = Description.read(EXAMPLE)
    assert d == from_file
    a = d.build().solve(0.6, 25.0, -40.0, F_P=80.0, T4=120.0)
    b = linkage_fmu.load(EXAMPLE).solve(0.6, 25.0, -40.0, 80.0, 120.0)
    assert dict(a) == dict(b)


def test_loads_are_inputs_by_name_and_balance_the_power():
    """solve(..., F_P=..., T4=...) and positionally; the power balance holds with both
    loads (1e-12 of the largest power term); a magnitude is the hypot of its components."""
    mech = linkage_fmu.load(EXAMPLE)
    assert mech.input_names == ("theta", "omega", "alpha", "F_P", "T4")
    theta, omega, alpha = 0.6, 25.0, -40.0
    sol = mech.solve(theta, omega, alpha, F_P=80.0, T4=120.0)
    res, size = power_residual(mech, sol, theta, omega, alpha, (80.0, 120.0))
    assert abs(res) <= 1e-12 * size
    assert sol["F12_abs"] == pytest.approx(math.hypot(sol["F12x"], sol["F12y"]), rel=1e-15)
    with pytest.raises(TypeError, match="has no input 'F_Q'; its inputs are: theta, omega, "
                                        "alpha, F_P, T4"):
        mech.solve(theta, F_Q=1.0)
    with pytest.raises(ValueError, match="T4 must be a finite number, got nan"):
        mech.solve(theta, T4=math.nan)
    with pytest.raises(ValueError, match="m2 must be <= 100.0"):
        linkage_fmu.load(EXAMPLE, m2=1e3)
    arrays = mech.solve(np.array([0.6, 1.0]), omega, alpha, T4=np.array([120.0, 0.0]))
    assert arrays["Mb"].shape == (2,)


@pytest.mark.parametrize("text", [
    "l.__class__", "(lambda: 1)()", "[x for x in l]", "l if l else 1", "'a' * 3", "l[0]",
    "open('f')", "True", "l < 1",
])
def test_expressions_take_numbers_names_and_arithmetic_only(text):
    with pytest.raises(ValueError):
        Expression(text)


def test_expressions_evaluate_over_parameters():
    assert Expression("-l_AS1 * sin(beta1) + 2 ** 3")({"l_AS1": 2.0, "beta1": math.pi / 2}) == 6.0
    assert Expression(0.25)({}) == 0.25
    with pytest.raises(ValueError, match="unknown name 'q'"):
        Expression("q + 1")({})


def test_a_group_subclass_works_and_an_incomplete_group_fails_loudly():
    """A subclass of RRR with no changes solves like RRR (it used to return Mb = -0.0 and
    then KeyError); a group class that misses a method cannot be instantiated; a
    linkage refuses an object that is not a group."""
    class MyRRR(groups.RRR):
        pass

    base = presets.get("four_bar")
    mine = linkage_fmu.Mechanism(
        "mine", base.frame, base.frame_points,
        [base.groups[0], MyRRR("2", "3", "B", "C", "D", 0.35, 0.30, 1)], base.bodies,
        base.effort, [linkage_fmu.outputs.EffortOutput("Mb")], base.loads, base.g)
    assert mine.solve(0.3, 10.0)["Mb"] == base.solve(0.3, 10.0)["Mb"]

    class Half(groups.Group):
        def position(self, st):
            pass

    with pytest.raises(TypeError, match="abstract"):
        Half()
    with pytest.raises(TypeError, match="is not a group"):
        linkage_fmu.Mechanism("x", "0", {"A": (0, 0)}, [base.groups[0], object()], [],
                              base.effort, [], [], 0.0)


def test_a_group_type_without_its_fields_is_refused(registry):
    """A class with a kind but no FIELDS of Field fails when it is defined, naming the
    class and what it misses, and is not a type of description files."""
    with pytest.raises(TypeError, match=r"NoFields \(kind 'no_fields'\) must declare FIELDS, a "
                                        "dict of field name -> Field; it has none$"):
        class NoFields(groups.Group):
            kind = "no_fields"
    with pytest.raises(TypeError, match=r"Motor \(kind 'motor'\) must declare FIELDS"
                                        r".* of its own \(FIELDS = Crank.FIELDS keeps its"):
        class Motor(groups.Crank):
            kind = "motor"
    with pytest.raises(TypeError, match=r"Roles \(kind 'roles'\) FIELDS\['link'\] = 'new link':"
                                        r" FIELDS must map field names to Field"):
        class Roles(groups.Crank):
            kind = "roles"
            FIELDS = {"link": "new link"}
    with pytest.raises(TypeError, match=r"Optional \(kind 'optional'\) OPTIONAL = \('size',\) "
                                        "must be a tuple of names in its FIELDS"):
        class Optional(groups.Crank):
            kind = "optional"
            FIELDS = groups.Crank.FIELDS
            OPTIONAL = ("size",)
    assert not {"no_fields", "motor", "roles", "optional"} & set(registry)


def define_knee() -> type:
    """Define (and so register) the group type ``knee``: under the ``registry``
    fixture only, or every later message listing the types would name it."""

    class Knee(groups.RRR):
        """A new group type, one class: an RRR dyad with its own field names, which also
        places the middle ``mark`` of its upper link (a point of that link, no joint)."""

        kind = "knee"
        FIELDS = {
            "upper": groups.Field("new link", "the link from hip to knee"),
            "lower": groups.Field("new link", "the link from foot to knee"),
            "hip": groups.Field("point", "end of upper, a placed point"),
            "knee": groups.Field("new point", "joint of upper and lower"),
            "foot": groups.Field("point", "end of lower, a placed point"),
            "thigh": groups.Field("length", "length of upper, from hip to knee"),
            "shin": groups.Field("length", "length of lower, from foot to knee"),
            "bend": groups.Field("branch", "+1: knee left of the line hip -> foot, -1: right"),
            "mark": groups.Field("new point", "the middle of upper"),
        }
        OPTIONAL = ("bend",)

        def __init__(self, upper, lower, hip, knee, foot, thigh, shin, bend, mark):
            super().__init__(upper, lower, hip, knee, foot, thigh, shin, bend)
            self.mark = mark
            self.places = (knee, mark)
            self.owners = {mark: upper}

        @classmethod
        def from_spec(cls, spec, value):
            return cls(spec["upper"], spec["lower"], spec["hip"], spec["knee"], spec["foot"],
                       value("thigh"), value("shin"), value("bend") if "bend" in spec else 1,
                       spec["mark"])

        @classmethod
        def pairs(cls, spec, placed=None):
            return tuple(p for p in super().pairs(spec, placed) if p != spec.get("mark"))

        def _middle(self, d):
            (x1, y1), (x2, y2) = d[self.E1], d[self.C]
            d[self.mark] = (0.5 * (x1 + x2), 0.5 * (y1 + y2))

        def position(self, st):
            super().position(st)
            self._middle(st.p)

        def first(self, st):
            super().first(st)
            self._middle(st.d1)

        def second(self, st):
            super().second(st)
            self._middle(st.d2)

    return Knee


def reread(d: Description) -> Description:
    """``d`` written to a description file and read back (and so checked)."""
    return Description.from_toml(d.to_toml(), "test.toml")


def knee_four_bar() -> Description:
    d = presets.preset("four_bar").copy()
    d.groups[1] = {"type": "knee", "upper": "2", "lower": "3", "hip": "B", "knee": "C",
                   "foot": "D", "thigh": "l_BC", "shin": "l_CD", "bend": "branch", "mark": "M"}
    return d


def test_a_new_group_type_is_one_class(registry):
    """Defined here and nowhere else, a type is read from a description file, checked
    through its FIELDS and pairs, built and solved: the four-bar with its dyad written
    as a knee gives the four-bar's numbers."""
    define_knee()
    d = reread(knee_four_bar())
    assert d.groups[1]["type"] == "knee"
    theta, omega, alpha, load = 0.7, 3.0, 1.0, 20.0
    assert dict(d.build().solve(theta, omega, alpha, load)) == dict(
        presets.get("four_bar").solve(theta, omega, alpha, load))
    st = d.build().kinematics(theta)
    assert st.p["M"] == pytest.approx(np.add(st.p["B"], st.p["C"]) / 2, abs=1e-15)

    # its fields are checked by role, its pairs with every other group's
    bad = knee_four_bar()
    bad.groups[1].update(thigh="l_BCD", shoe=1)
    del bad.groups[1]["foot"]
    bad.group("knee", upper="5", lower="6", hip="C", knee="B", foot="A", thigh=0.3,
              shin=0.3, mark="N")
    with pytest.raises(DescriptionError) as info:
        reread(bad)
    problems = info.value.problems
    for line in [
        "[[groups]] #2 (knee) shoe: unknown field; a knee has upper, lower, hip, knee, foot, "
        "thigh, shin, bend, mark",
        "[[groups]] #2 (knee) foot: missing",
        "[[groups]] #2 (knee) thigh: 'l_BCD' uses 'l_BCD', which is not a parameter",
        "[[groups]] #3 (knee) knee: point 'B' is already placed by [[groups]] #1 (crank)",
        "[[groups]] #3 (knee): joint 'C' is already a pair of [[groups]] #2 (knee): a point "
        "may join two links only; name the points apart",
        "[[groups]] #3 (knee): joint 'A' is already a pair of [[groups]] #1 (crank): a point "
        "may join two links only; name the points apart",
    ]:
        assert line in problems, (line, problems)

    # the mark joins nothing (pairs leaves it out), so a later group may hinge there
    d = knee_four_bar()
    d.point("F", 0.6, 0.3).group("RRR", link1="5", link2="6", end1="M", middle="E", end2="F",
                                 length1=0.3, length2=0.3, branch=1)
    d.body("5", cg={"from": "M"}).body("6", cg={"from": "F"})
    assert sorted(j.name for j in reread(d).build().joints) == ["A", "B", "C", "D", "E", "F", "M"]


def several_drivers(*efforts: str) -> str:
    """Why an [effort] is refused beside several drivers, in the checker's words."""
    return (f"[effort]: the linkage is driven by {len(efforts)} driver(s), each with its own "
            f"effort ({', '.join(efforts)}): it takes no [effort]")


def test_the_first_group_is_a_driver_and_later_drivers_take_no_effort(registry):
    """The rule follows DRIVER, not the name of a kind: a second driver type is a
    driver too, and a linkage of several drivers takes each one's effort, not an
    [effort]."""
    d = presets.preset("four_bar").copy()
    d.groups.reverse()
    with pytest.raises(DescriptionError) as info:
        reread(d)
    assert "[[groups]] #1 (RRR): the first group must be the crank or cylinder" in \
        info.value.problems
    assert several_drivers("Mb_A") not in info.value.problems  # one driver: its [effort]

    class Motor(groups.Crank):
        kind = "motor"
        FIELDS = groups.Crank.FIELDS

    d = presets.preset("four_bar").copy()
    d.groups[0]["type"] = "motor"
    four_bar = presets.get("four_bar")
    assert reread(d).build().solve(0.3, 10.0)["Mb"] == four_bar.solve(0.3, 10.0)["Mb"]
    d.groups.insert(1, dict(d.groups[0], type="crank", link="7", tip="T"))
    d.groups[0], d.groups[2] = d.groups[2], d.groups[0]
    with pytest.raises(DescriptionError) as info:
        reread(d)
    problems = info.value.problems
    assert "[[groups]] #1 (RRR): the first group must be the crank or cylinder or motor" in \
        problems
    assert "[[groups]] #3 (motor): the pair A is driven twice (also by [[groups]] #2): a " \
        "pair has one driver" in problems
    d.groups[2]["pivot"] = "D"
    with pytest.raises(DescriptionError) as info:
        reread(d)
    assert several_drivers("Mb_A", "Mb_D") in info.value.problems
    with pytest.raises(DescriptionError, match="there are none; the first must be the crank or "
                                               "cylinder or motor"):
        Description("empty", model="Empty").point("A", 0, 0).check()


def test_a_plain_angle_beyond_two_pi_is_noted_and_units_are_checked(tmp_path):
    """``angle = 30`` is 30 rad (a warning says so, with the degrees it is); ``"30 deg"``
    is pi / 6; a centre-of-mass distance given in kg is a problem naming its key."""
    d = presets.preset("four_bar").copy()
    d.bodies["2"]["cg"]["angle"] = 30
    with pytest.warns(UserWarning, match=r"\[bodies.2\] cg angle = 30 is taken in radians "
                                         r"\(1718.87 deg\); write \"30 deg\" for degrees"):
        d._changed().check()
    d.bodies["2"]["cg"]["angle"] = "30 deg"
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        mech = d._changed().build()
    sol = mech.solve(0.4)
    d.bodies["2"]["cg"]["angle"] = math.pi / 6
    assert d._changed().build().solve(0.4)["Mb"] == pytest.approx(sol["Mb"], rel=1e-15)
    d.bodies["2"]["cg"]["distance"] = "0.2 kg"
    with pytest.raises(DescriptionError, match=r"\[bodies.2\] cg distance = '0.2 kg' must be "
                                               r"a length \(m\), but it is a mass \(kg\)"):
        d._changed().check()


def test_a_value_the_builder_refuses_is_one_line_naming_the_file_and_the_key(tmp_path):
    """Each on one line: the file, the table and key, the value (once: ``mu = -0.1 =
    -0.1`` before; an expression's value after it) and what is wrong; an output force
    between bodies that share no joint names its ``[[outputs]]`` entry (it lacked the
    file); a file that cannot be read is one line too."""
    text = EXAMPLE.read_text()
    cases = {
        "mu.toml": (text + '\n[friction.C]\nmu = -0.1\nradius = 0.01\n',
                    "[friction.C] mu = -0.1 must be >= 0"),
        "expr.toml": (text + '\n[friction.C]\nmu = "-0.1 * 2"\nradius = 0.01\n',
                      "[friction.C] mu = '-0.1 * 2' = -0.2 must be >= 0"),
        "radius.toml": (text + '\n[friction.C]\nmu = 0.1\nradius = "-l_AB"\n',
                        "[friction.C] radius = '-l_AB' = -0.1 must be >= 0"),
        "unjoined.toml": (text.replace('name = "F03"\nby = "0"\non = "3"',
                                       'name = "F03"\nby = "0"\non = "2"'),
                          "[[outputs]] #3 (F03): no joint between bodies '0' and '2'"),
        "direction.toml": (text.replace("direction = [0, -1]", "direction = [0, 0]"),
                           "[[loads]] F_P: direction (0.0, 0.0) has no length"),
    }
    for name, (source, message) in cases.items():
        (tmp_path / name).write_text(source)
        with pytest.raises(ValueError) as info:
            linkage_fmu.load(str(tmp_path / name))
        assert str(info.value) == f"{tmp_path / name}: {message}", name
    with pytest.raises(DescriptionError) as info:
        linkage_fmu.load(str(tmp_path / "none.toml"))
    assert str(info.value) == f"{tmp_path / 'none.toml'}: cannot read it: No such file or directory"


def test_a_parameter_named_as_an_output_is_refused():
    # an FMU has one variable per name: a parameter named as the four-bar's transmission
    # angle would be two variables
    text = (presets.FOLDER / "four_bar.toml").read_text()
    clash = text.replace("mu_C = {", "gamma_C = {").replace('mu = "mu_C"', 'mu = "gamma_C"')
    with pytest.raises(ValueError, match=r"^four\.toml: the name 'gamma_C' is both a "
                                         r"parameter and a diagnostic output$"):
        Description.from_toml(clash, "four.toml").build()


def test_an_empty_or_missing_model_is_refused():
    """The reference says the model identifier is required, a C identifier: ``model =
    ""`` and a file without the key are refused, naming the file and the key; a file
    written as joints and links without the key takes its name, as the reference says,
    and ``model = ""`` there is refused too (it was taken for the name)."""
    text = EXAMPLE.read_text()
    missing = ("[linkage] model: missing or empty: the model identifier of the linkage's "
               'FMUs is required, a C identifier such as "FourBar" (letters, digits and _, '
               "not a digit first)")
    for source in (text.replace('model = "CouplerFourBar"', 'model = ""'),
                   text.replace('model = "CouplerFourBar"\n', "")):
        with pytest.raises(DescriptionError) as info:
            Description.from_toml(source, "coupler.toml")
        assert str(info.value) == f"coupler.toml: {missing}"
    drawn = (Path(__file__).parents[1] / "examples" / "joints" / "four_bar.toml").read_text()
    assert 'model = "FourBar"\n' in drawn
    assert Description.from_toml(drawn.replace('model = "FourBar"\n', ""),
                                 "drawn.toml").model == "four_bar"
    with pytest.raises(DescriptionError) as info:
        Description.from_toml(drawn.replace('model = "FourBar"', 'model = ""'), "drawn.toml")
    assert info.value.problems == [
        missing + "; written as joints and links, a file without the key takes its name "
                  "where that is one"]


@pytest.mark.parametrize("kind, unit, message", [
    ("expression", "ZZ", "'ZZ' is not a unit (pint knows no 'ZZ'); the units of an output "
                         "are rad, rad/s, rad/s2, m, m/s, m/s2, kg, kg/m, kg.m2, N, N.m, W, J, Pa, "
                         "m2, s, 1"),
    ("expression", "kN", "'kN' is not SI, and the output is computed in SI: write 'N'"),
    ("effort", "ZZ", "'ZZ' is not a unit (pint knows no 'ZZ'); the units of an output "
                     "are rad, rad/s, rad/s2, m, m/s, m/s2, kg, kg/m, kg.m2, N, N.m, W, J, Pa, "
                     "m2, s, 1"),
    ("effort", "N", "'N': Mb is a moment, in N.m"),
])
def test_an_output_unit_is_one_the_package_computes_in(kind, unit, message):
    """An output's ``unit`` that pint does not know (``"ZZ"``, taken before and written
    into the FMU), that is not SI (the output is computed in SI: ``"kN"`` would label
    newtons as kilonewtons), or an effort's that is not its effort's, is refused, naming
    the file, the output's table and the key; ``"N"`` for an expression and ``"N.m"``
    for the moment Mb are taken."""
    text = EXAMPLE.read_text()
    extra = ('\n[[outputs]]\nkind = "expression"\nname = "Q"\nexpression = "2 * Mb"\n'
             f'unit = "{unit}"\n' if kind == "expression" else None)
    source = (text + extra if extra else
              text.replace('kind = "effort"\nname = "Mb"\n',
                           f'kind = "effort"\nname = "Mb"\nunit = "{unit}"\n'))
    where = "[[outputs]] #5 (Q)" if kind == "expression" else "[[outputs]] #4 (Mb)"
    with pytest.raises(DescriptionError) as info:
        Description.from_toml(source, "units.toml")
    assert str(info.value) == f"units.toml: {where} unit: {message}"
    good = (text + extra.replace(unit, "N.m") if extra else
            text.replace('kind = "effort"\nname = "Mb"\n', 'kind = "effort"\nname = "Mb"\n'
                                                           'unit = "N.m"\n'))
    assert Description.from_toml(good, "units.toml").build().output_info["Mb"][0] == "N.m"


def test_the_effort_is_reported_where_no_output_names_it():
    """The coupler four-bar without its ``[[outputs]] kind = "effort"`` table still
    reports Mb (after its other outputs), the same number as with the table: every
    linkage reports its balancing effort (one table more used to drop it)."""
    text = EXAMPLE.read_text()
    assert text.count('[[outputs]]\nkind = "effort"\nname = "Mb"\n') == 1
    without = Description.from_toml(
        text.replace('[[outputs]]\nkind = "effort"\nname = "Mb"\n', ""), "no_mb.toml").build()
    full = Description.from_toml(text, "full.toml").build()
    assert without.output_names == full.output_names
    assert without.output_info["Mb"] == full.output_info["Mb"]
    assert without.solve(0.7, 20.0)["Mb"] == full.solve(0.7, 20.0)["Mb"]


@pytest.mark.parametrize("value, message", [
    ("false", "[linkage] default_outputs: a description written as groups has no default "
              "outputs: its [[outputs]] tables are its outputs (and each effort); the key is "
              "for one written as joints and links"),
    ('"no"', "[linkage] default_outputs: 'no' must be true or false"),
])
def test_default_outputs_is_true_or_false_and_for_joints_and_links(value, message):
    text = EXAMPLE.read_text().replace('frame = "0"\n',
                                       f'frame = "0"\ndefault_outputs = {value}\n', 1)
    with pytest.raises(DescriptionError) as info:
        Description.from_toml(text, "keys.toml")
    assert info.value.problems == [message]

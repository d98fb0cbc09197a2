"""Reading a linkage written as joints and links: each bad input is refused with a
message that names the file, the table and the problem (spec/topology.py, and the
reading of the form in spec/description.py)."""

from __future__ import annotations

import math

import pytest

from linkage_fmu.descriptions import Description, DescriptionError
from linkage_fmu.descriptions.topology import Drive, Joint, Link, Topology

#: a four-bar drawn at theta = 0: crank 1 = AB, coupler 2 = BC, rocker 3 = CD
FOUR_BAR = """
[linkage]
name = "drawn"

[parameters]
l = { default = 0.1, kind = "length", description = "crank length" }

[joints]
A = [0, 0]
B = ["l", 0]
C = [0.3, 0.2]
D = [0.4, 0]

[[links]]
name = "1"
joints = ["A", "B"]

[[links]]
name = "2"
joints = ["B", "C"]
mass = 1.0
cg = [0.2, 0.1]

[[links]]
name = "3"
joints = ["C", "D"]

[crank]
link = "1"
pivot = "A"
"""


def problems(text: str) -> list[str]:
    with pytest.raises(DescriptionError) as err:
        Description.from_toml(text, "drawn.toml")
    assert str(err.value).startswith("drawn.toml: ")
    return err.value.problems


def test_the_four_bar_reads_and_its_defaults_follow_the_form():
    """No [[outputs]], [effort] or model: the force of each pair as F<by><on>, by the
    body placed first (the frame "0" first), the effort Mb on the crank, the model its
    name."""
    d = Description.from_toml(FOUR_BAR, "drawn.toml")
    assert d.model == "drawn" and d.efforts == {None: {"name": "Mb", "body": "1"}}
    assert [(o["name"], o.get("by"), o.get("on")) for o in d.outputs] == [
        ("F01", "0", "1"), ("F12", "1", "2"), ("F23", "2", "3"), ("F03", "0", "3"),
        ("Mb", None, None)]


def test_mobility_not_one_gives_the_count():
    # D on link 2 as well: a compound joint at C is not it; a fourth link from C to the
    # frame makes a structure (mobility 0)
    text = FOUR_BAR + '\n[[links]]\nname = "4"\njoints = ["C", "E"]\n'
    text = text.replace("D = [0.4, 0]", "D = [0.4, 0]\nE = [0.5, 0.3]")
    assert problems(text) == [
        "[[links]]: the linkage's mobility is 0, not 1: 3 x 4 moving links - 2 x 6 pairs "
        "(Gruebler's count; a joint on one link is a pair with the frame, a joint on k "
        "links k - 1 pairs)"]


def test_a_joint_on_no_link():
    text = FOUR_BAR.replace("D = [0.4, 0]", "D = [0.4, 0]\nE = [0.5, 0.3]")
    assert problems(text) == ["[joints] E: a joint on no link: no [[links]] table lists it"]


def test_a_link_with_fewer_than_two_joints():
    text = FOUR_BAR.replace('joints = ["C", "D"]', 'joints = ["C"]')
    assert "[[links]] #3 (3) joints: a link with fewer than two joints (1: C); a link " \
           "carries two joints or more" in problems(text)


def test_a_crank_pivot_not_on_the_frame():
    text = FOUR_BAR.replace('pivot = "A"', 'pivot = "B"')
    assert problems(text) == [
        "[crank] pivot: the crank pivot B is not on the frame: it joins link 1 to 2; the "
        "pivot is a revolute joint that only the crank lists, or one the frame's entry in "
        "[[links]] lists"]


def test_unknown_joint_names():
    text = FOUR_BAR.replace('joints = ["B", "C"]', 'joints = ["B", "X"]')
    assert problems(text)[0] == (
        "[[links]] #2 (2) joints: 'X' is no joint of [joints]; the joints are A, B, C, D")


def test_a_mass_is_named_by_its_links_table():
    assert problems(FOUR_BAR.replace("mass = 1.0", 'mass = "3 m"')) == [
        "[[links]] #2 (2) mass = '3 m' must be a mass (kg), but it is a length (m)"]


def test_coordinates_with_units_are_taken_in_si():
    """C drawn at ("300 mm", "l + 100 mm"): the coupler's length is |BC| = hypot(0.2, 0.2)
    and the rocker's hypot(0.1, 0.2), as plain numbers draw it."""
    d = Description.from_toml(FOUR_BAR.replace("C = [0.3, 0.2]", 'C = ["300 mm", "l + 100 mm"]'),
                              "drawn.toml")
    assert d.groups[1]["length1"] == "hypot(0.3 - l, l + 0.1)"
    mech = d.build()
    assert mech.groups[1].L1 == pytest.approx(math.hypot(0.2, 0.2), abs=1e-16)
    assert mech.groups[1].L2 == pytest.approx(math.hypot(0.1, 0.2), abs=1e-16)


def test_a_crank_that_is_no_link():
    assert problems(FOUR_BAR.replace('link = "1"', 'link = "9"')) == [
        "[crank] link: '9' is not a link of [[links]]"]


@pytest.mark.parametrize("vector, message", [
    ("[0.3]", "[joints] C: must be [x, y], got [0.3]"),
    ('[0.3, "h"]', "[joints] C y = 'h': unknown name 'h' in 'h'"),
    ('[0.3, "sqrt(l - 1)"]', "[joints] C y = 'sqrt(l - 1)': math domain error"),
    ('[0.3, "2 s"]', "[joints] C y = '2 s' must be a length (m), but it is a time (s)"),
    ('[0.3, "0.2 +"]', "[joints] C y: '0.2 +' is not an expression: invalid syntax"),
])
def test_bad_vectors(vector, message):
    assert problems(FOUR_BAR.replace("C = [0.3, 0.2]", f"C = {vector}")) == [message]


def test_a_slide_of_zero_length():
    text = FOUR_BAR.replace("D = [0.4, 0]", "D = { at = [0.4, 0], slide = [0, 0] }")
    assert problems(text) == [
        "[joints] D slide: [0, 0] has no length: the direction of the guide must not be zero"]


def test_a_prismatic_pair_of_two_links_needs_its_guide():
    text = FOUR_BAR.replace("C = [0.3, 0.2]", "C = { at = [0.3, 0.2], slide = [1, 0] }")
    assert problems(text) == [
        "[joints] C guide: two links list this prismatic pair (2, 3): say which carries "
        "the guide, guide = \"2\" or \"3\""]


def test_a_drawn_position_that_uses_itself():
    text = FOUR_BAR.replace("C = [0.3, 0.2]", 'C = ["x_D - 0.1", "y_D"]')
    text = text.replace("D = [0.4, 0]", 'D = [0.4, "y_C + 0.2"]')
    assert problems(text)[0] == (
        "[joints] C y: the drawn position of C uses itself (C -> D -> C)")


def test_both_forms_mixed():
    text = FOUR_BAR + "\n[points]\nA = [0, 0]\n"
    assert problems(text) == [
        "[points]: a description is written either as groups ([points], [[groups]], "
        "[bodies]) or as joints and links ([joints], [[links]], [crank]), not both"]


def test_gruebler_counts_a_compound_joint_as_k_minus_one_pairs():
    """Three links on one pin are two pairs: a Watt-like chain with C on 2, 3 and 4."""
    joints = {n: Joint(n, (0, 0)) for n in "ABCDE"}
    links = {"1": Link("1", ("A", "B")), "2": Link("2", ("B", "C")),
             "3": Link("3", ("C", "D")), "4": Link("4", ("C", "E"))}
    t = Topology("0", joints, links, (Drive("A", "angle", "0", "1"),))
    # pairs: A, B, C (two), D, E = 6; 3 x 4 - 2 x 6 = 0
    assert (t.on("C"), t.pair_count(), t.mobility()) == (("2", "3", "4"), 6, 0)


def test_it_starts_where_it_is_drawn():
    """B drawn at 0.7 rad from A: theta starts there, unless [inputs] says otherwise."""
    text = FOUR_BAR.replace('B = ["l", 0]', 'B = ["l * cos(0.7)", "l * sin(0.7)"]')
    assert Description.from_toml(text, "drawn.toml").build().start["theta"] == \
        pytest.approx(0.7, abs=1e-15)
    text += "\n[inputs]\ntheta = 0.1\n"
    assert Description.from_toml(text, "drawn.toml").build().start["theta"] == 0.1


#: FOUR_BAR with the frame's entry in [[links]] first, listing its pins A and D
WITH_FRAME = FOUR_BAR.replace('[[links]]\nname = "1"',
                              '[[links]]\nname = "0"\njoints = ["A", "D"]\n\n'
                              '[[links]]\nname = "1"', 1)


def test_the_frames_entry_reads_as_the_plain_file():
    """Listing the frame pins A and D in the frame's entry changes nothing: the same
    groups and pairs; the moving links keep their [[links]] numbers in messages."""
    plain, listed = (Description.from_toml(t, "drawn.toml") for t in (FOUR_BAR, WITH_FRAME))
    assert listed.groups == plain.groups and listed.drawn.pairs == plain.drawn.pairs
    assert problems(WITH_FRAME.replace("mass = 1.0", 'mass = "3 m"')) == [
        "[[links]] #3 (2) mass = '3 m' must be a mass (kg), but it is a length (m)"]


def test_a_frame_entry_with_a_mass():
    text = WITH_FRAME.replace('joints = ["A", "D"]', 'joints = ["A", "D"]\nmass = 2.0')
    assert problems(text) == [
        "[[links]] #1 (0): the frame's entry gives mass; it lists the frame's joints only "
        "(name, joints): the frame has no mass, inertia, cg or points"]


def test_a_frame_joint_that_joins_nothing():
    text = WITH_FRAME.replace('joints = ["A", "D"]', 'joints = ["A", "D", "E"]')
    text = text.replace("D = [0.4, 0]", "D = [0.4, 0]\nE = [0.5, 0.3]")
    assert problems(text) == [
        "[[links]] #1 (0) joints: E is on the frame only: no moving link lists it, so it "
        "joins nothing"]


def test_one_bad_joint_is_one_problem_not_one_per_expression_that_uses_it():
    """A joint given in kg (``D = ["200 kg", 0]``) is reported once: the centres of mass
    drawn at the joints (``x_C``, ``x_D``, ...) are not also reported as using unknown
    names (each did: ``unknown name 'x_B'``, for every joint), a link listing D is not
    told D is no joint, and a problem of its own elsewhere (a cg using a name that is
    nothing) is still reported."""
    text = FOUR_BAR.replace("D = [0.4, 0]", 'D = ["200 kg", 0]').replace(
        "cg = [0.2, 0.1]", 'cg = ["(x_B + x_C) / 2", "(y_B + y_C) / 2"]')
    text = text.replace('joints = ["C", "D"]', 'joints = ["C", "D"]\ncg = ["x_D", "y_D"]')
    assert problems(text) == ["[joints] D x = '200 kg' must be a length (m), but it is a "
                              "mass (kg)"]
    text = text.replace('joints = ["A", "B"]', 'joints = ["A", "B"]\ncg = ["q", 0]')
    assert problems(text) == [
        "[joints] D x = '200 kg' must be a length (m), but it is a mass (kg)",
        "[[links]] #1 (1) cg x = 'q': unknown name 'q' in 'q'"]


def test_a_loop_of_drawn_positions_is_one_problem():
    """C drawn from D and D from C: the loop is said once, at its first joint, and the
    centre of mass drawn at C (``x_C``) is not reported as using an unknown name."""
    text = FOUR_BAR.replace("C = [0.3, 0.2]", 'C = ["x_D - 0.1", 0.2]').replace(
        "D = [0.4, 0]", 'D = ["x_C + 0.1", 0]').replace(
        "cg = [0.2, 0.1]", 'cg = ["(x_B + x_C) / 2", "(y_B + y_C) / 2"]')
    assert problems(text) == ["[joints] C x: the drawn position of C uses itself (C -> D -> C)"]


@pytest.mark.parametrize("key, value, unit", [("inertia", "-0.006", "kg.m2"),
                                              ("mass", "-0.8", "kg")])
def test_a_negative_mass_or_inertia_names_its_links_table(key, value, unit):
    """A negative inertia or mass of a link is a DescriptionError (it was a plain
    ValueError) naming the link's own table, ``[[links]] #4 (3)`` with the frame's entry
    first (it named ``[bodies.3]``, a table the file does not have); a parameter that
    makes it negative at build time is a ValueError naming the same table."""
    framed = FOUR_BAR.replace('[[links]]\nname = "1"',
                              '[[links]]\nname = "0"\njoints = ["A", "D"]\n\n[[links]]\n'
                              'name = "1"', 1)
    text = framed.replace('joints = ["C", "D"]', f'joints = ["C", "D"]\n{key} = {value}')
    assert problems(text) == [f"[[links]] #4 (3) {key}: {value} must be a finite number >= 0 "
                              f"({unit})"]
    text = framed.replace('joints = ["C", "D"]', f'joints = ["C", "D"]\n{key} = "l * 10 - 0.5"')
    d = Description.from_toml(text, "drawn.toml")  # >= 0 at l = 0.1, not at l = 0.02
    with pytest.raises(ValueError, match=rf"^drawn\.toml: \[\[links\]\] #4 \(3\): {key} of "
                                         r"body '3' must be a finite number >= 0, got "
                                         r"-0\.3\d*$"):
        d.build(l=0.02)


#: a five-bar (two cranks on the frame at A and E) drawn as joints and links
FIVE_BAR = """
[linkage]
name = "drawn"

[joints]
A = [0, 0]
B = [0.1, 0.1]
C = [0.2, 0.3]
D = [0.3, 0.1]
E = [0.4, 0]

[[links]]
name = "1"
joints = ["A", "B"]

[[links]]
name = "2"
joints = ["B", "C"]

[[links]]
name = "3"
joints = ["C", "D"]

[[links]]
name = "4"
joints = ["D", "E"]
"""
DRIVERS = '[[drivers]]\njoint = "A"\n\n[[drivers]]\njoint = "E"\n'


def test_the_drivers_name_the_inputs_and_efforts_and_start_where_drawn():
    d = Description.from_toml(FIVE_BAR + DRIVERS, "drawn.toml")
    assert d.inputs["theta_A"] == pytest.approx(math.pi / 4, abs=1e-15)
    assert d.inputs["theta_E"] == pytest.approx(math.atan2(0.1, -0.1), abs=1e-15)
    assert [o["name"] for o in d.outputs][-2:] == ["Mb_A", "Mb_E"]
    assert d.build().input_names == ("theta_A", "omega_A", "alpha_A", "theta_E", "omega_E",
                                     "alpha_E")


def test_a_mobility_other_than_the_number_of_drivers_gives_both_counts():
    assert problems(FIVE_BAR + '[[drivers]]\njoint = "A"\n') == [
        "[[links]]: the linkage's mobility is 2, not 1, the number of its drivers: 3 x 4 "
        "moving links - 2 x 5 pairs (Gruebler's count; a joint on one link is a pair with "
        "the frame, a joint on k links k - 1 pairs)"]


@pytest.mark.parametrize("extra, message", [
    ('[[drivers]]\njoint = "A"\n\n[[drivers]]\njoint = "Q"\n',
     "[[drivers]] #2 joint: 'Q' is no joint of [joints]; the joints are A, B, C, D, E"),
    ('[[drivers]]\njoint = "A"\n\n[[drivers]]\njoint = "A"\n',
     "[[drivers]] #2 (A): the pair A is driven twice (first by [[drivers]] #1 (A)); a pair "
     "takes one driver"),
    ('[crank]\nlink = "1"\npivot = "A"\n\n[[drivers]]\njoint = "E"\n',
     "[crank], [[drivers]]: a linkage is driven either by [crank] (its one crank) or by "
     "[[drivers]] (each driven pair), not both"),
    ('[[drivers]]\njoint = "A"\nlinks = ["1", "3"]\n\n[[drivers]]\njoint = "E"\n',
     "[[drivers]] #1 (A) links: ['1', '3'] are not the links of the pair A, which joins "
     "0, 1"),
    ('[[drivers]]\njoint = "A"\nlinks = ["1", "0"]\n\n[[drivers]]\njoint = "E"\n',
     "[[drivers]] #1 (A) links: the frame is first: a crank's angle is the link's on the "
     "frame, links = ['0', '1']"),
    ('[[drivers]]\njoint = "A"\nangle = 1\n\n[[drivers]]\njoint = "E"\n',
     "[[drivers]] #1: unknown key(s) angle; the keys are joint, links"),
    ("[drivers]\njoint = \"A\"\n",
     "[[drivers]]: must be a list of tables, one per driven pair, { joint = \"A\" }"),
])
def test_a_bad_driver_is_named_with_the_reason(extra, message):
    assert message in problems(FIVE_BAR + extra)


def test_without_a_driver_the_message_names_both_forms():
    assert problems(FIVE_BAR)[0] == (
        "[crank]: missing: the driven link and its pivot, { link = \"1\", pivot = \"A\" } "
        "(or [[drivers]], each driven pair)")


def test_an_effort_or_a_crank_s_inputs_beside_drivers_are_refused():
    found = problems(FIVE_BAR + DRIVERS + '\n[inputs]\ntheta = 0.3\ns_A = 0.1\n')
    names = "theta_A, omega_A, alpha_A, theta_E, omega_E, alpha_E"
    assert found == [f"[inputs] theta: no input of this linkage; its drivers' inputs are {names}",
                     f"[inputs] s_A: no input of this linkage; its drivers' inputs are {names}"]
    found = problems(FIVE_BAR + DRIVERS + '\n[effort]\nname = "T"\nbody = "1"\n')
    assert any("[effort]" in p and "Mb_A, Mb_E" in p for p in found), found


CYLINDER = """
[linkage]
name = "drawn"

[joints]
O = [0, 0]
E = [1.0, -0.5]
D = [1.2, 0.9]
P = { at = [1.2, 0.9], slide = [0.2, 1.4], guide = "barrel" }

[[links]]
name = "body"
joints = ["O", "D"]

[[links]]
name = "barrel"
joints = ["E", "P"]

[[links]]
name = "rod"
joints = ["P", "D"]

[[drivers]]
joint = "P"
"""


def test_a_cylinder_is_a_barrel_and_a_rod_each_pinned_at_one_end():
    d = Description.from_toml(CYLINDER, "drawn.toml")
    assert [g["type"] for g in d.groups] == ["cylinder"]
    assert d.inputs["s_P"] == 0.0 and d.groups[0]["length0"] == pytest.approx(
        math.hypot(0.2, 1.4), abs=1e-15)
    text = CYLINDER.replace('joints = ["P", "D"]', 'joints = ["P", "D", "O"]')
    assert ("[[drivers]] #1 (P): the cylinder's rod rod is pinned at one end: it lists P and "
            "one revolute joint, not P, D, O") in problems(text)
    text = CYLINDER.replace('links = ', 'x = ').replace('joint = "P"',
                                                         'joint = "P"\nlinks = ["rod", "barrel"]')
    assert ("[[drivers]] #1 (P) links: a cylinder's first link is its barrel, the guide "
            "'barrel': links = ['barrel', 'rod']") in problems(text)


def test_a_cylinder_drawn_against_its_slide_is_refused():
    text = CYLINDER.replace("slide = [0.2, 1.4]", "slide = [-0.2, -1.4]")
    assert problems(text) == [
        "[joints] P slide: a cylinder's slide points from its barrel's pin E to its rod's "
        "pin D (its travel is positive along it); it is drawn the other way"]


def test_a_driven_slider_on_a_frame_guide_is_refused_with_the_way_to_draw_it():
    text = FOUR_BAR.replace("D = [0.4, 0]", 'D = { at = [0.4, 0], slide = [1, 0] }').replace(
        '[crank]\nlink = "1"\npivot = "A"', '[[drivers]]\njoint = "D"')
    assert ("[[drivers]] #1 (D): a driven prismatic pair is a cylinder between two links, "
            "its barrel and its rod; D joins link 3 to the frame (a driven slider on a frame "
            "guide is not one yet: draw the actuator as a cylinder, barrel and rod, pinned to "
            "the frame and to the slider)") in problems(text)

"""The decomposition of a joints-and-links linkage into groups (spec/assur.py): which
groups, in which order, with which fields; and each problem it reports, by its message."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import fmu_cache
from linkage_fmu import groups
from linkage_fmu.descriptions import Description, DescriptionError
from linkage_fmu.descriptions.assur import decompose, outline, recognisers
from linkage_fmu.descriptions.topology import read
from linkage_fmu.manual import reference
from test_topology import FIVE_BAR

ROOT = Path(__file__).resolve().parents[1]

HEAD = """
[linkage]
name = "drawn"

[parameters]
h = { default = 0.2, kind = "coordinate", description = "height of C where drawn" }
"""


def tables(text: str) -> dict:
    import tomllib

    return tomllib.loads(text)


def problems(text: str) -> list[str]:
    with pytest.raises(DescriptionError) as err:
        Description.from_toml(text, "drawn.toml")
    assert str(err.value).startswith("drawn.toml: ")
    return err.value.problems


# -- a class III group: the decomposition, without building (the closure group type is
# not the library's yet) -----------------------------------------------------------------
#: a six-bar whose ternary coupler 5 (E, F, G) is held by three binary rods: 2 pinned to
#: the crank at A, 3 and 4 to the frame at P and Q
CLASS_III = {
    "joints": {"O": [0, 0], "A": [0.1, 0], "P": [0.5, -0.1], "Q": [0.3, -0.3],
               "E": [0.25, 0.3], "F": [0.55, 0.25], "G": [0.4, 0.05]},
    "links": [{"name": "1", "joints": ["O", "A"]}, {"name": "2", "joints": ["A", "E"]},
              {"name": "3", "joints": ["P", "F"]}, {"name": "4", "joints": ["Q", "G"]},
              {"name": "5", "joints": ["E", "F", "G"], "mass": 2.0, "cg": [0.4, 0.2]}],
    "crank": {"link": "1", "pivot": "O"},
}


def test_a_class_iii_group_is_one_closure_after_the_crank():
    t, found = read(CLASS_III, {})
    assert found == [] and t.mobility() == 1
    dec = decompose(t, {})
    assert outline(dec.groups) == [
        ("crank", "crank", ("1",), ("O", "A")),
        ("III", "closure", ("2", "3", "4", "5"), ("A", "E", "P", "F", "Q", "G")),
    ]
    closure = dec.groups[1]
    # each link's joints, its direction from the first to the second; every joint where
    # drawn; the drawn crank angle (A on the +x axis)
    assert closure["links"] == {"2": ["A", "E"], "3": ["P", "F"], "4": ["Q", "G"],
                                "5": ["E", "F", "G"]}
    assert closure["pose"] == {p: [float(v) for v in xy]
                               for p, xy in CLASS_III["joints"].items() if p != "O"}
    assert closure["theta"] == 0.0
    # pairs: each rod to what holds it, the coupler's three pins; the frame first
    assert dec.pairs == [("O", "0", "1"), ("A", "1", "2"), ("P", "0", "3"),
                         ("Q", "0", "4"), ("E", "2", "5"), ("F", "3", "5"), ("G", "4", "5")]
    # the coupler's centre of mass in its own frame: from E along E -> F
    e, f = (np.array(CLASS_III["joints"][p]) for p in "EF")
    s = np.array([0.4, 0.2])
    u = (f - e) / np.linalg.norm(f - e)
    cg = dec.bodies["5"]["cg"]
    assert cg["from"] == "E"
    assert cg["along"] == pytest.approx(np.dot(s - e, u), abs=1e-15)
    assert cg["across"] == pytest.approx(u[0] * (s - e)[1] - u[1] * (s - e)[0], abs=1e-15)


# -- a compound joint ---------------------------------------------------------------------
COMPOUND = HEAD + """
[joints]
A = [0, 0]
B = [0.1, 0]
C = [0.3, "h"]
D = [0.4, 0]
E = [0.55, 0.3]
F = [0.7, 0.1]

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

[[links]]
name = "4"
joints = ["C", "E"]
mass = 0.5
cg = [0.45, 0.25]

[[links]]
name = "5"
joints = ["E", "F"]

[crank]
link = "1"
pivot = "A"
"""


def test_a_compound_joint_is_two_pairs_the_third_link_pinned_to_the_first():
    """C joins 2, 3 and 4: the pair C joins 2 and 3 (the RRR that places C), the pair
    C_4 joins 4 to 2, on 2's point C_4 where C is."""
    d = Description.from_toml(COMPOUND, "drawn.toml")
    assert [row[:2] for row in outline(d.groups)] == [
        ("crank", "crank"), ("II", "RRR"), ("point", "point"), ("II", "RRR")]
    assert d.groups[2] == {"type": "point", "link": "2", "from": "C", "name": "C_4"}
    assert (d.groups[3]["end1"], d.groups[3]["link1"]) == ("C_4", "4")
    assert [o["name"] for o in d.outputs] == ["F01", "F12", "F23", "F03", "F24", "F45",
                                              "F05", "Mb"]
    mech = d.build()
    # the drawn pose at the drawn angle; at another, the links keep their drawn lengths
    # (the reference: distances between the drawn joints) and C_4 stays on C
    drawn = {"B": (0.1, 0), "C": (0.3, 0.2), "D": (0.4, 0), "E": (0.55, 0.3), "F": (0.7, 0.1)}
    st = mech.kinematics(0.0, order=0)
    for p, xy in drawn.items():
        assert math.dist(st.p[p], xy) <= 1e-15
    st = mech.kinematics(0.4, order=0)
    for a, b in ("BC", "CD", "CE", "EF"):
        assert math.dist(st.p[a], st.p[b]) == pytest.approx(math.dist(drawn[a], drawn[b]),
                                                            abs=1e-15)
    assert math.dist(st.p["C_4"], st.p["C"]) <= 1e-15


# -- the problems -------------------------------------------------------------------------
def test_a_joint_named_as_a_pair_the_decomposition_makes():
    """E renamed C_4: the name of the pair that pins link 4 to the compound joint C."""
    text = COMPOUND.replace("E = [", "C_4 = [").replace('["C", "E"]', '["C", "C_4"]').replace(
        '["E", "F"]', '["C_4", "F"]')
    assert problems(text) == [
        "[joints] C_4: the decomposition names the pin of link 4 at the compound joint C "
        "C_4; name the joint otherwise"]


def test_a_drawn_pose_the_parameters_move_across_a_toggle_keeps_the_mode_they_draw():
    """C drawn below the line B -> D (h < 0) while the defaults draw it above: the RRR
    takes the mode the parameters draw (its branch is the sign of the drawn pose), so
    the drawn pose is reproduced at the drawn angle, to 1e-15 m, and every point is where
    the same linkage drawn there in numbers puts it, 50 deg on (reference), to 1e-15 m."""
    d = Description.from_toml(COMPOUND, "drawn.toml")
    assert d.groups[1]["branch"] == "sign(0.30000000000000004 * h)"
    below = d.build(h=-0.2)
    drawn = below.kinematics(0.0, order=0)
    assert math.dist(drawn.p["C"], (0.3, -0.2)) <= 1e-15
    numbers = Description.from_toml(COMPOUND.replace('C = [0.3, "h"]', "C = [0.3, -0.2]"),
                                    "numbers.toml").build()
    assert numbers.description.groups[1]["branch"] == -1
    at, want = below.kinematics(math.radians(50.0), order=0), \
        numbers.kinematics(math.radians(50.0), order=0)
    for p in "BCEF":
        assert math.dist(at.p[p], want.p[p]) <= 1e-15, p


def test_a_drawn_pose_at_a_toggle():
    text = COMPOUND.replace('C = [0.3, "h"]', "C = [0.3, 0]")
    assert problems(text) == [
        "[joints] C: the dyad B-C-D (links 2, 3) is drawn at a toggle (B, C, D in line): "
        "its assembly mode is undefined; draw it apart"]


def test_a_group_the_decomposition_cannot_solve_slides():
    """A block on the crank pin sliding in a slot of a lever that does not pass through
    the lever's pivot: no dyad of the library (an RPR's slot passes through its lever's
    pivot), said with the distance by which it misses it (0.4 m: the slot along x through
    B = (0.1, 0), the pivot C = (0, -0.4)), the sine (0.4 / |BC| = 0.970) against the
    tolerance, and how to write the slot through it exactly."""
    text = HEAD + """
[joints]
A = [0, 0]
B = [0.1, 0]
C = [0, -0.4]
s = { at = [0.1, 0], slide = [1, 0], guide = "3" }

[[links]]
name = "1"
joints = ["A", "B"]

[[links]]
name = "2"
joints = ["B", "s"]

[[links]]
name = "3"
joints = ["C", "s"]

[crank]
link = "1"
pivot = "A"
"""
    assert problems(text) == [
        "[joints] s slide: [1, 0] through the pin B misses the pivot C of the lever 3 by "
        "0.4 m (the sine of the angle between the slide and the line B-C is 0.97; the "
        "tolerance is 1e-06): a block in the slot of a turning lever (an RPR dyad) slides "
        'on a line through the lever\'s pivot; write slide = ["x_B - x_C", "y_B - y_C"] '
        "for a slot exactly through it"]


def test_a_group_the_decomposition_cannot_solve_none_left_is_held():
    """The crank with a rod to the frame is locked (mobility 0), a four-bar beside it
    moves freely (mobility 1): one in all, but no group of the links left has mobility
    0."""
    text = HEAD + """
[joints]
A = [0, 0]
B = [0.1, 0]
C = [0.1, 0.3]
P = [1, 0]
Q = [1.1, 0.2]
R = [1.4, 0.3]
S = [1.5, 0]

[[links]]
name = "1"
joints = ["A", "B"]

[[links]]
name = "2"
joints = ["B", "C"]

[[links]]
name = "5"
joints = ["P", "Q"]

[[links]]
name = "6"
joints = ["Q", "R"]

[[links]]
name = "7"
joints = ["R", "S"]

[crank]
link = "1"
pivot = "A"
"""
    assert problems(text) == [
        "[[links]]: a group the decomposition cannot solve: links 2, 5, 6, 7 are left, "
        "and no connected set of them is held by the placed links with mobility 0"]


def test_the_crank_turns_to_a_revolute_joint():
    """A crank whose first joint after the pivot is a slot: theta would be undefined."""
    text = HEAD + """
[joints]
A = [0, 0]
g = { at = [0.1, 0], slide = [1, 0], guide = "1" }
C = [0.3, 0.2]
D = [0.4, 0]

[[links]]
name = "1"
joints = ["A", "g"]

[[links]]
name = "2"
joints = ["g", "C"]

[[links]]
name = "3"
joints = ["C", "D"]

[crank]
link = "1"
pivot = "A"
"""
    assert problems(text) == [
        "[crank] link: the crank's first other joint g is a prismatic pair; list a "
        "revolute joint after the pivot"]


# -- against an independent Newton-Euler reference ---------------------------------------
#: the compound-joint linkage with masses, inertias, gravity and a force on link 5 at E
LOADED = HEAD.replace('name = "drawn"', 'name = "drawn"\ngravity = "g"') + """
g = { default = 9.81, kind = "gravity", description = "gravitational acceleration" }

[joints]
A = [0, 0]
B = [0.1, 0]
C = [0.3, "h"]
D = [0.4, 0]
E = [0.55, 0.3]
F = [0.7, 0.1]

[[links]]
name = "1"
joints = ["A", "B"]

[[links]]
name = "2"
joints = ["B", "C"]
mass = 1.0
inertia = 0.012
cg = [0.2, 0.1]

[[links]]
name = "3"
joints = ["C", "D"]
mass = 0.7
inertia = 0.004

[[links]]
name = "4"
joints = ["C", "E"]
mass = 0.5
cg = [0.45, 0.25]

[[links]]
name = "5"
joints = ["E", "F"]
mass = 0.9
inertia = 0.006

[crank]
link = "1"
pivot = "A"

[[loads]]
name = "P"
body = "5"
kind = "force"
at = "E"
direction = [0.6, -0.8]
start = 35.0
"""
#: link -> (mass, inertia, cg where drawn), as LOADED gives them (a cg not given is at
#: the link's first joint)
INERTIA = {"1": (0.0, 0.0, (0.0, 0.0)), "2": (1.0, 0.012, (0.2, 0.1)),
           "3": (0.7, 0.004, (0.3, 0.2)), "4": (0.5, 0.0, (0.45, 0.25)),
           "5": (0.9, 0.006, (0.55, 0.3))}


def newton_euler(theta: float, omega: float, alpha: float, g: float, load: float):
    """Mb and the shaking force and moment of LOADED, from the drawn joints and the
    links' distance constraints alone: positions by Newton on the constraints from the
    drawn pose (continued along theta), their derivatives from the differentiated
    constraints, then every link's Newton-Euler equations with the pair forces and Mb as
    unknowns (a pair per joint and link beyond the first, the frame's per frame joint)."""
    drawn = {"A": (0, 0), "B": (0.1, 0), "C": (0.3, 0.2), "D": (0.4, 0),
             "E": (0.55, 0.3), "F": (0.7, 0.1)}
    links = {"1": "AB", "2": "BC", "3": "CD", "4": "CE", "5": "EF"}
    frame = {"A", "D", "F"}
    free = ["B", "C", "E"]
    idx = {p: 2 * k for k, p in enumerate(free)}
    dist = {(a, b): math.dist(drawn[a], drawn[b]) for a, b in ("BC", "CD", "CE", "EF")}
    L = math.dist(drawn["A"], drawn["B"])

    def point(q, p):
        return np.array(drawn[p], float) if p in frame else q[idx[p]:idx[p] + 2]

    def constraints(q, th):
        out = [*(point(q, "B") - L * np.array([math.cos(th), math.sin(th)]))]
        for (a, b), d in dist.items():
            r = point(q, a) - point(q, b)
            out.append(r @ r - d * d)
        return np.array(out)

    def jacobian(q):
        J = np.zeros((6, 6))
        J[0:2, idx["B"]:idx["B"] + 2] = np.eye(2)
        for row, (a, b) in enumerate(dist, start=2):
            r = point(q, a) - point(q, b)
            for p, s in ((a, 2.0), (b, -2.0)):
                if p not in frame:
                    J[row, idx[p]:idx[p] + 2] += s * r
        return J

    q = np.array([c for p in free for c in drawn[p]], float)
    for th in np.linspace(0.0, theta, 16)[1:]:
        for _ in range(30):
            q = q - np.linalg.solve(jacobian(q), constraints(q, th))
    J = jacobian(q)
    c, s = math.cos(theta), math.sin(theta)
    q1 = np.linalg.solve(J, -np.array([L * s, -L * c, 0, 0, 0, 0]))
    quad = [L * c, L * s]
    for a, b in dist:
        v = point(q1, a) * (a not in frame) - point(q1, b) * (b not in frame)
        quad.append(2.0 * v @ v)
    q2 = np.linalg.solve(J, -np.array(quad))

    def pv(vec, p):
        return np.zeros(2) if p in frame else vec[idx[p]:idx[p] + 2]

    # each link's angle derivatives and its centre of mass's acceleration
    acc, eps, cg = {}, {}, {}
    for name, (a, b) in links.items():
        r = point(q, b) - point(q, a)
        r1 = pv(q1, b) - pv(q1, a)
        r2 = pv(q2, b) - pv(q2, a)
        n2 = r @ r
        w1 = (r[0] * r1[1] - r[1] * r1[0]) / n2
        w2 = (r[0] * r2[1] - r[1] * r2[0]) / n2 - 2.0 * (r @ r1) * w1 / n2
        r0 = np.subtract(drawn[b], drawn[a])
        phi = math.atan2(r[1], r[0]) - math.atan2(r0[1], r0[0])
        rot = np.array([[math.cos(phi), -math.sin(phi)], [math.sin(phi), math.cos(phi)]])
        arm = rot @ (np.array(INERTIA[name][2]) - drawn[a])
        cg[name] = point(q, a) + arm
        perp = np.array([-arm[1], arm[0]])
        a1 = pv(q1, a) + w1 * perp
        a2 = pv(q2, a) + w2 * perp - w1 * w1 * arm
        acc[name] = a2 * omega ** 2 + a1 * alpha
        eps[name] = w2 * omega ** 2 + w1 * alpha
    # unknowns: (Fx, Fy) of each pair as the action of its first body on its second, Mb
    pairs = [("A", "0", "1"), ("B", "1", "2"), ("C", "2", "3"), ("C", "2", "4"),
             ("D", "0", "3"), ("E", "4", "5"), ("F", "0", "5")]
    order = list(links)
    A = np.zeros((15, 15))
    rhs = np.zeros(15)
    for k, (p, a, b) in enumerate(pairs):
        for body, sign in ((b, 1.0), (a, -1.0)):
            if body == "0":
                continue
            row = 3 * order.index(body)
            arm = point(q, p) - cg[body]
            A[row, 2 * k] += sign
            A[row + 1, 2 * k + 1] += sign
            A[row + 2, 2 * k] += -sign * arm[1]
            A[row + 2, 2 * k + 1] += sign * arm[0]
    A[2, 14] = 1.0  # Mb on the crank
    direction = np.array([0.6, -0.8])
    for name in order:
        m, inertia, _ = INERTIA[name]
        row = 3 * order.index(name)
        force = m * acc[name] - m * np.array([0.0, -g])
        moment = inertia * eps[name]
        if name == "5":
            force = force - load * direction
            arm = point(q, "E") - cg[name]
            moment -= arm[0] * load * direction[1] - arm[1] * load * direction[0]
        rhs[row:row + 3] = (*force, moment)
    x = np.linalg.solve(A, rhs)
    mb = x[14]
    # what the moving links exert on the frame: minus the frame's forces on them, and
    # minus the balancing moment the frame applies to the crank; moments about A
    shake, shake_m = np.zeros(2), -mb
    for k, (p, a, _) in enumerate(pairs):
        if a == "0":
            f = x[2 * k:2 * k + 2]
            shake -= f
            r = point(q, p)
            shake_m -= r[0] * f[1] - r[1] * f[0]
    return mb, shake[0], shake[1], shake_m


@pytest.mark.parametrize("theta_deg", [-30.0, -12.5, 0.0, 7.0, 21.0, 30.0])
def test_mb_and_the_shaking_force_against_newton_euler(theta_deg):
    """Within 30 degrees of the drawn angle, at omega = 10 rad/s, alpha = 5 rad/s2,
    g = 9.81: Mb and the shaking force and moment equal the reference to 1e-9 (relative
    to 1 N or 1 N.m, or to the value where it is larger)."""
    mech = Description.from_toml(LOADED, "drawn.toml").build()
    theta = math.radians(theta_deg)
    sol = mech.solve(theta, 10.0, 5.0, P=35.0)
    want = newton_euler(theta, 10.0, 5.0, 9.81, 35.0)
    for key, value in zip(("Mb", "shake_x", "shake_y", "shake_M"), want):
        assert abs(sol[key] - value) <= 1e-9 * max(1.0, abs(value)), key


# -- a point of a link ----------------------------------------------------------------------
def test_a_coupler_point_carries_a_load_as_in_the_group_form():
    """examples/coupler_four_bar.toml (written as groups, by hand) drawn as joints and
    links, its coupler point P one of link 2's points: the same outputs at every state
    to 1e-14 of each unit's largest value, and it starts at the drawn angle."""
    from pathlib import Path

    example = Path(__file__).parents[1] / "examples" / "coupler_four_bar.toml"
    text = example.read_text()
    head = text[:text.index("[points]")]
    tail = text[text.index("[[loads]]"):]
    drawn = head + """
[joints]
A = [0, 0]
B = ["l_AB", 0]
C = ["l_AB + (l_BC**2 - l_CD**2 + (l_AD - l_AB)**2) / (2 * (l_AD - l_AB))",
     "sqrt(((l_BC + l_CD)**2 - (l_AD - l_AB)**2) * ((l_AD - l_AB)**2 - (l_BC - l_CD)**2)) / (2 * (l_AD - l_AB))"]
D = ["l_AD", 0]

[[links]]
name = "1"
joints = ["A", "B"]

[[links]]
name = "2"
joints = ["B", "C"]
mass = "m2"
inertia = "J2"
cg = ["(x_B + x_C) / 2", "(y_B + y_C) / 2"]
points = { P = ["x_B + (P_along * (x_C - x_B) - P_across * (y_C - y_B)) / l_BC",
                "y_B + (P_along * (y_C - y_B) + P_across * (x_C - x_B)) / l_BC"] }

[[links]]
name = "3"
joints = ["C", "D"]
mass = "m3"
inertia = "J3"
cg = ["(x_C + x_D) / 2", "(y_C + y_D) / 2"]

[crank]
link = "1"
pivot = "A"

""" + tail  # noqa: E501 (TOML)
    d = Description.from_toml(drawn, "drawn.toml")
    assert [row[:3] for row in outline(d.groups)] == [
        ("crank", "crank", ("1",)), ("II", "RRR", ("2", "3")), ("point", "point", ("2",))]
    want_mech = Description.read(example).build()
    got_mech = d.build()
    assert got_mech.start["theta"] == 0.0
    theta = np.linspace(0.0, 2.0 * np.pi, 73)
    want = want_mech.solve(theta, 10.0, 5.0, F_P=80.0, T4=-40.0)
    got = got_mech.solve(theta, 10.0, 5.0, F_P=80.0, T4=-40.0)
    units = {k: want_mech.output_info[k][0] for k in want}
    for key in want:
        same_unit = [np.max(np.abs(want[k])) for k in want if units[k] == units[key]]
        assert np.max(np.abs(got[key] - want[key])) <= 1e-14 * max(same_unit), key


def test_a_point_of_a_link_is_no_joint():
    text = COMPOUND.replace('joints = ["E", "F"]',
                            'joints = ["E", "F"]\npoints = { D = [0.6, 0.2] }')
    assert problems(text) == [
        "[[links]] #5 (5) points: 'D' is a joint; a point of a link joins nothing"]


def test_no_group_of_a_link_that_turns_freely():
    """x, pinned to the crank and the frame, is a structure with it; y hangs from x by
    one pin and from the unplaced z: {x, y} counts mobility 0 (3 x 2 - 2 x 3), but y
    would turn about D. With a free four-bar w, v, u beside them the linkage counts 1,
    and no group solves what is left."""
    text = HEAD + """
[joints]
A = [0, 0]
B = [0.1, 0]
C = [0.2, 0.3]
D = [0.3, 0.1]
E = [0.5, 0.2]
F = [0.6, 0]
G = [1, 0]
H = [1.1, 0.2]
I = [1.4, 0.3]
J = [1.5, 0]

[[links]]
name = "1"
joints = ["A", "B"]

[[links]]
name = "x"
joints = ["B", "C", "D"]

[[links]]
name = "y"
joints = ["D", "E"]

[[links]]
name = "z"
joints = ["E", "F"]

[[links]]
name = "w"
joints = ["G", "H"]

[[links]]
name = "v"
joints = ["H", "I"]

[[links]]
name = "u"
joints = ["I", "J"]

[crank]
link = "1"
pivot = "A"
"""
    assert problems(text) == [
        "[[links]]: a group the decomposition cannot solve: links x, y, z, w, v, u are left, "
        "and no connected set of them is held by the placed links with mobility 0"]


def test_two_links_of_a_closure_on_one_placed_joint_are_two_pairs():
    """The class III six-bar with rod 3 pinned to the crank at A instead of the frame at
    P: A is a compound joint of the crank, 2 and 3, so the closure pins 2 at A and 3 at
    A_3, the crank's point where A is."""
    data = {**CLASS_III, "links": [dict(link) for link in CLASS_III["links"]]}
    data["links"][2]["joints"] = ["A", "F"]  # rod 3 from A instead of the frame joint P
    data["joints"] = {k: v for k, v in CLASS_III["joints"].items() if k != "P"}
    t, found = read(data, {})
    assert found == []
    dec = decompose(t, {})
    assert [row[:2] for row in outline(dec.groups)] == [
        ("crank", "crank"), ("point", "point"), ("III", "closure")]
    assert dec.groups[1] == {"type": "point", "link": "1", "from": "A", "name": "A_3"}
    assert dec.groups[2]["links"] == {"2": ["A", "E"], "3": ["A_3", "F"], "4": ["Q", "G"],
                                      "5": ["E", "F", "G"]}
    assert [p for p in dec.pairs if p[0].startswith("A")] == [("A", "1", "2"),
                                                              ("A_3", "1", "3")]


def test_a_load_over_the_cycle_may_use_a_prismatic_pairs_point():
    """The scotch yoke drawn as joints and links with its load 400 N + 3000 N/m * y_slot
    (slot's point on the block, at B): the preset with that load given state by state,
    400 + 3000 * l_AB sin(theta), to 1e-12 N."""
    from pathlib import Path

    from linkage_fmu import presets

    path = Path(__file__).parents[1] / "examples" / "joints" / "scotch_yoke.toml"
    text = path.read_text().replace("start = 400.0", 'value = "400 + 3000 * y_slot"')
    mech = Description.from_toml(text, str(path)).build()
    preset = presets.get("scotch_yoke")
    for theta in (0.3, 1.0, 2.5, 4.0):
        got = mech.solve(theta, 10.0, 5.0)
        want = preset.solve(theta, 10.0, 5.0, 400.0 + 3000.0 * 0.1 * math.sin(theta))
        for key in ("F23y", "Mb", "F4", "F41y"):
            assert got[key] == pytest.approx(want[key], abs=1e-12), key


# -- one frame pin for several links: the frame's entry in [[links]] --------------------
#: a four-bar A-B-C-D with a dyad C-E-S on its pin C; link 5's far end S is on the frame,
#: where the rocker's pivot D or the crank's pivot A is. ``{frame}`` is the frame's entry
#: and ``{s}`` the joint link 5 lists.
SHARED_PIN = """
[linkage]
name = "drawn"
gravity = "g"

[parameters]
g = {{ default = 9.81, kind = "gravity", description = "gravitational acceleration" }}

[joints]
A = [0, 0]
B = [0.1, 0]
C = [0.3, 0.2]
D = [0.4, 0]
E = {e}
{extra}
{frame}
[[links]]
name = "1"
joints = ["A", "B"]
mass = 0.3
inertia = 0.0004
cg = [0.05, 0.0]

[[links]]
name = "2"
joints = ["B", "C"]
mass = 1.0
inertia = 0.012
cg = [0.2, 0.1]

[[links]]
name = "3"
joints = ["C", "D"]
mass = 0.7
inertia = 0.004
cg = [0.35, 0.1]

[[links]]
name = "4"
joints = ["C", "E"]
mass = 0.5
inertia = 0.003
cg = {cg4}

[[links]]
name = "5"
joints = ["E", "{s}"]
mass = 0.9
inertia = 0.006
cg = {cg5}

[crank]
link = "1"
pivot = "A"

[[loads]]
name = "P"
body = "5"
kind = "force"
at = "E"
direction = [0.6, -0.8]
start = 35.0
"""
#: the shared frame pin -> where E is drawn, link 4's and link 5's centres of mass
SHARED = {"D": ("[0.55, 0.3]", "[0.425, 0.25]", "[0.475, 0.15]"),
          "A": ("[0.15, 0.4]", "[0.225, 0.3]", "[0.075, 0.2]")}


def shared_pin(pin: str, one_pin: bool) -> str:
    """SHARED_PIN with link 5 on the frame at ``pin``: the frame's entry listing it
    (``one_pin``), or a second joint ``S`` drawn where ``pin`` is."""
    e, cg4, cg5 = SHARED[pin]
    at = {"A": "[0, 0]", "D": "[0.4, 0]"}[pin]
    return SHARED_PIN.format(
        e=e, cg4=cg4, cg5=cg5, s=pin if one_pin else "S",
        extra="" if one_pin else f"S = {at}",
        frame='[[links]]\nname = "0"\njoints = ["A", "D"]\n' if one_pin else "")


@pytest.mark.parametrize("pin", SHARED)
def test_two_links_on_one_frame_pin(pin):
    """Link 5 pinned to the frame where the rocker's pivot D (or the crank's pivot A)
    is: written as one frame pin listed by the frame's entry, its pairs are ``pin``
    (the link placed first) and ``<pin>_5``, both with the frame; Mb and the shaking
    force and moment equal those of the same linkage written with two joints drawn at
    one place (1e-13), and the independent reference's (tests/newton_euler.py, 1e-9),
    within 30 deg of the drawn angle at omega 10 rad/s, alpha 5 rad/s2, g 9.81."""
    import tomllib

    import newton_euler as ne

    one = Description.from_toml(shared_pin(pin, True), "drawn.toml")
    two = Description.from_toml(shared_pin(pin, False), "drawn.toml")
    first = "1" if pin == "A" else "3"
    assert (pin, "0", first) in one.drawn.pairs and (f"{pin}_5", "0", "5") in one.drawn.pairs
    assert one.points[f"{pin}_5"] == one.points[pin]
    lk = ne.from_data(tomllib.loads(shared_pin(pin, True)))
    assert lk.on(pin) == [first, "5"] and lk.frame_joints == {"A", "D"}
    one_mech, two_mech = one.build(), two.build()
    for theta in np.radians(np.linspace(-30.0, 30.0, 7)):
        got = one_mech.solve(theta, 10.0, 5.0, P=35.0)
        same = two_mech.solve(theta, 10.0, 5.0, P=35.0)
        ref = ne.solve(lk, theta, 10.0, 5.0, 9.81, {"P": 35.0})
        for key in ("Mb", "shake_x", "shake_y", "shake_M"):
            assert got[key] == pytest.approx(same[key], abs=1e-13), (key, theta)
            assert got[key] == pytest.approx(ref[key], abs=1e-9), (key, theta)


def split_triad() -> str:
    """examples/triad_six_bar.toml with its plate P1 P2 P3 replaced by three bars u
    (P1 P2), v (P1 P3) and w (P2 P3) of the plate's mass shared out: three pins of three
    links each, all inside the class III group."""
    import re
    from pathlib import Path

    text = (Path(__file__).resolve().parents[1] / "examples" / "triad_six_bar.toml").read_text()
    plate = re.search(r'\[\[links\]\][^\[]*name = "plate".*?(?=\n\[)', text, flags=re.S)[0]
    bars = "\n".join(f'[[links]]\nname = "{n}"\njoints = ["{a}", "{b}"]\nmass = 0.2\n'
                     f'inertia = 0.0003\n'
                     for n, a, b in (("u", "P1", "P2"), ("v", "P1", "P3"), ("w", "P2", "P3")))
    return text.replace(plate, bars).replace('body = "plate"', 'body = "u"')


def test_every_pair_at_a_compound_joint_inside_a_closure_is_an_output():
    """At each pin of three links inside the class III group, the closure makes two
    pairs (the first two links listing it, then the third pinned to the second); the
    default outputs name both, and the force each pin puts on each link (the sum of its
    pairs' forces on it) equals the independent reference's (tests/newton_euler.py) to
    1e-9 N, within 30 deg of the drawn angle at omega 10 rad/s, alpha 5 rad/s2, g 9.81.
    (The reference's pin is massless: the force on the link it gives none is minus the
    others'.)"""
    import tomllib

    import newton_euler as ne
    from linkage_fmu.descriptions.assur import output_name

    text = split_triad()
    d = Description.from_toml(text, "split.toml")
    at = {p: [(a, b) for name, a, b in d.drawn.pairs if name.split("_")[0] == p]
          for p in ("P1", "P2", "P3")}
    assert all(len(v) == 2 for v in at.values()), at  # 3 links on a pin: 2 pairs
    mech = d.build()
    lk = ne.from_data(tomllib.loads(text))

    def on(sol, by, link):  # the force of the pair's other link on ``link``
        if output_name(by, link) + "x" in sol:
            name, sign = output_name(by, link), 1.0
        else:
            name, sign = output_name(link, by), -1.0
        return sign * np.array([sol[name + "x"], sol[name + "y"]])

    for theta in lk.theta_drawn + np.radians([-30.0, -10.0, 0.0, 15.0, 30.0]):
        sol = mech.solve(theta, 10.0, 5.0, T=5.0)
        ref = ne.solve(lk, theta, 10.0, 5.0, 9.81, {"T": 5.0})["R"]
        for p, pairs in at.items():
            links = {x for pair in pairs for x in pair}
            for n in links:
                got = sum(on(sol, b if n == a else a, n) for a, b in pairs if n in (a, b))
                want = ref.get((p, n))
                if want is None:
                    want = -sum(ref[(p, m)] for m in links - {n})
                assert np.max(np.abs(got - want)) <= 1e-9, (p, n, theta)


def test_a_parameter_that_turns_a_slot_off_its_lever_is_refused():
    """The slotted lever's slot, drawn through the lever's pivot C, makes an RPR group,
    whose slot runs along its lever: a parameter ``e`` that tilts the drawn slide would
    be dropped, so a build where it is not 0 is refused, naming the pair; at e = 0 it
    builds. Where the parameters are a kernel's arguments (an FMU's, set at run time; a
    sweep's), its parameter step refuses e = 0.2 too, naming the pair, and takes e = 0."""
    from pathlib import Path

    text = (Path(__file__).resolve().parents[1] / "examples" / "joints"
            / "slotted_lever.toml").read_text()
    text = text.replace('slide = ["x_B - x_C", "y_B - y_C"]',
                        'slide = ["x_B - x_C", "y_B - y_C + e"]').replace(
        "[parameters]\n", '[parameters]\ne = { default = 0.0, kind = "coordinate", '
                          'description = "tilt of the drawn slot" }\n')
    d = Description.from_toml(text, "tilt.toml")
    assert d.build().solve(0.7)["Mb"] == pytest.approx(
        Description.read(Path(__file__).resolve().parents[1] / "examples" / "joints"
                         / "slotted_lever.toml").build().solve(0.7)["Mb"], abs=1e-12)
    with pytest.raises(ValueError, match=r"^tilt\.toml: \[joints\] slot slide: a drawn pose "
                                         r"from which a group cannot be assembled: at the "
                                         r"drawn crank angle 0 deg the pair slides along "
                                         r"\(.*\), not along its drawn slide \(.*\) \(sine "
                                         r"of the angle between them 0\.\d+; the tolerance "
                                         r"is 1e-06\)$"):
        d.build(e=0.2)
    kernel = d.build().kernel()
    values = {name: d.build().parameters[name] for name in kernel.parameters}
    assert "e" in values and kernel.parameter_problem(*values.values()) is None
    values["e"] = 0.2
    assert kernel.parameter_problem(*values.values()) == (
        "the parameter set is invalid: [joints] slot slide: the parameters turn the slide "
        "off the line B-C through the lever's pivot (the sine of the angle between them "
        "above 1e-06): the slot of a turning lever runs through its pivot")


# -- a Whitworth quick-return written as joints and links, its numbers typed as a drawing
# tool shows them (six digits) -----------------------------------------------------------
#: crank 2 = O2-A (0.2 m, drawn at 60 deg), block 4 on A sliding in the slot of lever 3
#: (pivot O3 = (0, -0.1), below O2: the lever turns fully), rod 5 = C-D, ram 6 at D on a
#: horizontal frame guide; the slot's direction is O3 -> A = (0.1, 0.1 + 0.1 sqrt(3)) /
#: 0.29093 = (0.34372377, 0.93907080), typed (0.343724, 0.939071)
WHITWORTH = """
[linkage]
name = "whitworth"
model = "Whitworth"

[joints]
O2 = [0, 0]
A = [0.1, 0.173205]
O3 = [0, -0.1]
slot = { at = [0.1, 0.173205], slide = [0.343724, 0.939071], guide = "3" }
C = [-0.085931, -0.334768]
D = [0.312555, -0.3]
guide = { at = [0.312555, -0.3], slide = [1, 0] }

[[links]]
name = "0"
joints = ["O2", "O3"]

[[links]]
name = "2"
joints = ["O2", "A"]
mass = 1.0
inertia = 0.004
cg = [0.05, 0.0866]

[[links]]
name = "4"
joints = ["A", "slot"]
mass = 0.3
inertia = 0.0002
cg = [0.1, 0.173205]

[[links]]
name = "3"
joints = ["O3", "slot", "C"]
mass = 3.0
inertia = 0.05
cg = [0, -0.1]

[[links]]
name = "5"
joints = ["C", "D"]
mass = 1.5
inertia = 0.02
cg = [0.113312, -0.317384]

[[links]]
name = "6"
joints = ["D", "guide"]
mass = 8.0
cg = [0.312555, -0.3]

[crank]
link = "2"
pivot = "O2"
"""
TYPED = "slide = [0.343724, 0.939071]"


def test_a_slot_typed_to_six_digits_is_its_levers_line():
    """The slot typed to six digits misses the lever's pivot by a sine of 5.3e-8 (1.5e-8 m
    at |O3 A| = 0.29 m), under the tolerance of 1e-6: it is an RPR dyad (it was refused
    as "no dyad of the library"), and the linkage is the one whose slot is written
    through the pivot exactly, ``["x_A - x_O3", "y_A - y_O3"]``: the same Mb at every
    angle of a revolution, bit for bit, and the same angles where the rod cannot reach
    the ram's guide (the RPR's slot runs along its lever)."""
    a = (0.1, 0.173205 + 0.1)
    sine = abs(a[0] * 0.939071 - a[1] * 0.343724) / math.hypot(*a) / math.hypot(0.343724,
                                                                               0.939071)
    assert 5e-8 < sine < 6e-8
    typed = Description.from_toml(WHITWORTH, "whitworth.toml")
    exact = Description.from_toml(
        WHITWORTH.replace(TYPED, 'slide = ["x_A - x_O3", "y_A - y_O3"]'), "exact.toml")
    assert [g["type"] for g in typed.groups][:3] == ["crank", "RPR", "point"]
    theta = np.linspace(0.0, 2.0 * math.pi, 72, endpoint=False)
    got, want = typed.build().solve(theta, 10.0), exact.build().solve(theta, 10.0)
    # the rod reaches the ram's guide over most of the turn, not with C at its top
    np.testing.assert_array_equal(got.valid, want.valid)
    assert 60 <= np.sum(got.valid) < 72
    np.testing.assert_array_equal(got["Mb"], want["Mb"])


def test_a_slot_that_misses_the_pivot_says_by_how_much():
    """The slot typed to four digits, (0.3437, 0.9391), misses the pivot O3 by a sine of
    3.25e-5 (computed here from the typed numbers), above the tolerance: refused with
    the distance (|O3 A| times the sine), the sine, the tolerance and how to write the
    slot through the pivot exactly, where it said only "no dyad of the library"."""
    a = (0.1, 0.173205 + 0.1)
    d = (0.3437, 0.9391)
    sine = abs(a[0] * d[1] - a[1] * d[0]) / math.hypot(*a) / math.hypot(*d)
    assert problems(WHITWORTH.replace(TYPED, "slide = [0.3437, 0.9391]")) == [
        f"[joints] slot slide: [0.3437, 0.9391] through the pin A misses the pivot O3 of the "
        f"lever 3 by {sine * math.hypot(*a):.3g} m (the sine of the angle between the slide "
        f"and the line A-O3 is {sine:.3g}; the tolerance is 1e-06): a block in the slot of a "
        'turning lever (an RPR dyad) slides on a line through the lever\'s pivot; write '
        'slide = ["x_A - x_O3", "y_A - y_O3"] for a slot exactly through it']
    assert f"{sine:.3g}" == "3.25e-05"


# -- outputs: a file's [[outputs]] add to the defaults ------------------------------------
#: a Stephenson III six-bar: the four-bar A-B-C-D (crank 1, ternary coupler 2 = B, C, E,
#: rocker 3), and the dyad E-F-G (links 4, 5) from the coupler to the frame at G
STEPHENSON = """
[linkage]
name = "stephenson3"
model = "Stephenson3"

[joints]
A = [0, 0]
B = [0.1, 0]
C = [0.3, 0.25]
D = [0.4, 0]
E = [0.2, 0.35]
F = [0.45, 0.5]
G = [0.6, 0.2]

[[links]]
name = "1"
joints = ["A", "B"]
mass = 0.5
inertia = 0.001
cg = [0.05, 0]

[[links]]
name = "2"
joints = ["B", "C", "E"]
mass = 1.5
inertia = 0.01
cg = [0.2, 0.2]

[[links]]
name = "3"
joints = ["C", "D"]
mass = 0.8
inertia = 0.006
cg = [0.35, 0.125]

[[links]]
name = "4"
joints = ["E", "F"]
mass = 0.6
inertia = 0.004
cg = [0.325, 0.425]

[[links]]
name = "5"
joints = ["F", "G"]
mass = 0.7
inertia = 0.005
cg = [0.525, 0.35]

[crank]
link = "1"
pivot = "A"
"""
F12 = '\n[[outputs]]\nkind = "force"\nname = "F12"\nby = "1"\non = "2"\nmagnitude = true\n'
DEFAULTS = ["F01", "F12", "F23", "F03", "F24", "F45", "F05"]


def test_an_output_table_adds_to_the_default_outputs(tmp_path):
    """The Stephenson III plus one ``[[outputs]]`` table, F12 with its magnitude: Mb and
    every pair's force are still reported (one table dropped them all: ``solve()["Mb"]``
    was a KeyError, and ``info`` listed F12x, F12y, F12_abs only), the table's outputs
    first, then the pairs' forces it does not report, then the effort; Mb and every force
    are those of the file without the table (bit for bit), F12_abs is hypot(F12x, F12y).
    ``linkage-fmu info`` lists them."""
    from linkage_fmu.cli import main

    plain = Description.from_toml(STEPHENSON, "plain.toml").build()
    assert plain.output_names[:-3] == tuple(f"{n}{a}" for n in DEFAULTS for a in "xy") + ("Mb",)
    more = Description.from_toml(STEPHENSON + F12, "more.toml").build()
    assert more.output_names[:-3] == ("F12x", "F12y", "F12_abs") + tuple(
        f"{n}{a}" for n in DEFAULTS if n != "F12" for a in "xy") + ("Mb",)
    state = (0.7, 12.0, 3.0)
    got, want = more.solve(*state), plain.solve(*state)
    for name in plain.output_names:
        assert got[name] == want[name], name
    assert got["F12_abs"] == math.hypot(got["F12x"], got["F12y"])
    path = tmp_path / "stephenson3.toml"
    path.write_text(STEPHENSON + F12)
    import contextlib
    import io

    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main(["info", str(path)]) == 0
    listed = [line.split()[0] for line in out.getvalue().split("outputs:\n")[1].splitlines()]
    assert listed[:4] == ["F12x", "F12y", "F12_abs", "F01x"] and "Mb" in listed


def test_default_outputs_false_keeps_the_files_outputs_and_the_effort():
    """``[linkage] default_outputs = false``: the file's one table, F12 and its
    magnitude, and Mb, which every linkage reports (the same number as with the
    defaults)."""
    text = STEPHENSON.replace('model = "Stephenson3"\n',
                              'model = "Stephenson3"\ndefault_outputs = false\n') + F12
    mech = Description.from_toml(text, "only.toml").build()
    assert mech.output_names == ("F12x", "F12y", "F12_abs", "Mb", "shake_x", "shake_y",
                                 "shake_M")
    plain = Description.from_toml(STEPHENSON, "plain.toml").build()
    assert mech.solve(0.7, 12.0)["Mb"] == plain.solve(0.7, 12.0)["Mb"]

# -- a pose drawn at parameters: its assembly mode follows them --------------------------
POSED = """
[linkage]
name = "posed"
model = "Posed"
frame = "4"

[parameters]
cx = { default = 0.30416666666666664, kind = "coordinate", description = "x of C, drawn" }
cy = { default = 0.28428150247801206, kind = "coordinate", description = "y of C, drawn" }

[joints]
A = [0, 0]
B = [0.1, 0]
C = [CX, CY]
D = [0.4, 0]

[[links]]
name = "1"
joints = ["A", "B"]
mass = 1.0
inertia = 0.001
cg = [0.05, 0]

[[links]]
name = "2"
joints = ["B", "C"]
mass = 2.0
inertia = 0.02
cg = [0.2, 0.1]

[[links]]
name = "3"
joints = ["C", "D"]
mass = 1.5
inertia = 0.012
cg = [0.35, 0.1]

[crank]
link = "1"
pivot = "A"

[[loads]]
name = "load"
body = "3"
kind = "moment"
start = 3.0
description = "a torque on the rocker"
"""
#: C drawn on the other side of the line B-D, and on it
MIRRORED, ON_THE_LINE = {"cx": 0.30416666666666664, "cy": -0.28428150247801206}, \
    {"cx": 0.25, "cy": 0.0}


def test_the_assembly_mode_of_a_pose_drawn_at_parameters_follows_them(tmp_path):
    """A four-bar written as joints and links with its coupler pin C drawn at the
    parameters (cx, cy), given C on the other side of B-D. Reference: the same four-bar
    drawn there in numbers (its decomposition gives the dyad branch -1). The library
    builds it with those parameters, and both FMU flavours, built at the defaults and
    given them at run time (a fresh host process), answer Mb, F12x and F12y at 8 crank
    angles equal to the reference's to 1e-12 of the largest, never the default's mode
    (whose Mb differs by more than 0.1 N.m there). C drawn on the line B-D: the library
    refuses it, and both FMUs answer exitInitializationMode with Error, saying the dyad
    B-C-D is drawn at a toggle; no call answers Fatal."""
    from fmpy import read_model_description

    from test_fmu_protocol import ERROR, OK, raw

    posed = POSED.replace("CX", '"cx"').replace("CY", '"cy"')
    numbers = POSED.replace("CX", repr(MIRRORED["cx"])).replace("CY", repr(MIRRORED["cy"]))
    names = ("Mb", "F12x", "F12y")
    thetas = [float(t) for t in np.radians(np.arange(0.0, 360.0, 45.0))]
    reference = Description.from_toml(numbers, "numbers.toml").build()
    want = np.array([[reference.solve(t, 10.0, 0.0)[n] for n in names] for t in thetas])
    d = Description.from_toml(posed, "posed.toml")
    default = d.build()
    assert min(abs(default.solve(t, 10.0, 0.0)["Mb"] - w[0]) for t, w in zip(thetas, want)) > 0.1
    got = np.array([[d.build(**MIRRORED).solve(t, 10.0, 0.0)[n] for n in names]
                    for t in thetas])
    assert np.abs(got - want).max() <= 1e-12 * np.abs(want).max()
    with pytest.raises(ValueError, match="at a toggle"):
        d.build(**ON_THE_LINE)

    source = tmp_path / "posed.toml"
    source.write_text(posed)
    for flavour in (fmu_cache.build_fmu, fmu_cache.build_native_fmu):
        fmu = flavour(str(source), tmp_path / flavour.__name__)
        refs = {v.name: v.valueReference for v in read_model_description(str(fmu)).modelVariables}
        ops = [["a", "new", "Posed"], ["a", "setup", 0.0, None], ["a", "enter"],
               ["a", "setReal", [refs["cx"], refs["cy"]], list(MIRRORED.values())],
               ["a", "exit"]]
        for k, theta in enumerate(thetas):
            ops += [["a", "setReal", [refs[n] for n in ("theta", "omega", "alpha", "load")],
                     [theta, 10.0, 0.0, 3.0]], ["a", "doStep", 0.01 * k, 0.01],
                    ["a", "getReal", [refs[n] for n in names]]]
        ops += [["a", "free"], ["b", "new", "Posed"], ["b", "setup", 0.0, None],
                ["b", "enter"],
                ["b", "setReal", [refs["cx"], refs["cy"]], list(ON_THE_LINE.values())],
                ["b", "exit"], ["b", "lastLog"], ["b", "free"]]
        out = raw(fmu.parent, ops, tmp_path, models=("Posed",))
        results, exit_b = out["results"], len(ops) - 3
        assert all(status == OK for status, _ in results[:exit_b]), flavour.__name__
        values = np.array([results[7 + 3 * k][1] for k in range(len(thetas))])
        assert np.abs(values - want).max() <= 1e-12 * np.abs(want).max(), flavour.__name__
        assert results[exit_b][0] == ERROR, flavour.__name__
        said = results[exit_b + 1][1]
        assert "the dyad B-C-D is drawn at a toggle (its points in line)" in said, said


def test_a_dyad_drawn_near_a_toggle_warns_and_the_examples_do_not():
    """The four-bar above with C drawn 1e-5 m off the line B-D: building warns
    (NearSingularWarning), naming the joint, the dyad and its condition number in the
    drawn pose, (1 + |cos g|) / |sin g| with g the angle at C between C-B and C-D,
    computed here from the drawn coordinates, to 3 digits. Every example written as
    joints and links builds without one."""
    import re
    import warnings
    from pathlib import Path

    from linkage_fmu import NearSingularWarning

    text = POSED.replace("CX", "0.3").replace("CY", "1e-5")
    u, w = np.array([0.1 - 0.3, -1e-5]), np.array([0.4 - 0.3, -1e-5])
    cos = u @ w / np.linalg.norm(u) / np.linalg.norm(w)
    kappa = (1 + abs(cos)) / math.sqrt(1 - cos * cos)
    with pytest.warns(NearSingularWarning) as caught:
        Description.from_toml(text, "near.toml").build()
    message = str(caught[0].message)
    assert message.startswith("near.toml: [joints] C: the dyad B-C-D is drawn near a toggle: "
                              "the condition number of its position there is ")
    assert abs(float(re.search(r"there is ([0-9.e+]+)", message)[1]) / kappa - 1) <= 5e-3
    examples = Path(__file__).parents[1] / "examples"
    with warnings.catch_warnings():
        warnings.simplefilter("error", NearSingularWarning)
        for path in sorted([*examples.glob("*.toml"), *examples.glob("joints/*.toml")]):
            Description.read(path).build()


# -- a group type drawn as joints and links is one class ---------------------------------
def test_a_group_type_that_declares_its_drawing_is_recognised_from_joints_and_links(registry):
    """Defined here and nowhere else, a type that declares its DRAWING (an RRR dyad under
    another name, ranked before the RRR) is what the decomposition takes two links pinned
    together for: the drawn four-bar is built with it and gives the same numbers, and the
    reference lists it among the dyads a drawing may show."""
    path = ROOT / "examples" / "joints" / "four_bar.toml"
    drawn = Description.read(path)
    assert [g["type"] for g in drawn.groups][:2] == ["crank", "RRR"]

    class Elbow(groups.RRR):
        """Two links pinned together at an elbow."""

        kind = "elbow"
        FIELDS = groups.RRR.FIELDS
        DRAWING = groups.Drawing(0, 2, "two links pinned at an elbow",
                                 "each pinned to a placed joint")

    assert [cls.kind for cls in recognisers()] == ["elbow", "RRR", "RRP", "RPR", "RPP",
                                                   "closure"]
    elbow = Description.read(path)
    assert [g["type"] for g in elbow.groups] == [
        "elbow" if g["type"] == "RRR" else g["type"] for g in drawn.groups]
    assert [{k: v for k, v in g.items() if k != "type"} for g in elbow.groups] == [
        {k: v for k, v in g.items() if k != "type"} for g in drawn.groups]
    mech = elbow.build()
    assert [type(grp) for grp in mech.groups][:2] == [groups.Crank, Elbow]
    theta, omega, alpha, load = 0.7, 3.0, 1.0, 20.0
    assert dict(mech.solve(theta, omega, alpha, load)) == dict(
        drawn.build().solve(theta, omega, alpha, load))
    assert ("| `elbow` | two links pinned at an elbow | each pinned to a placed joint |\n"
            "| `RRR` |") in reference.markdown()


def test_a_drawing_and_its_recognise_come_together(registry):
    """A type that declares a DRAWING recognises it, and one that recognises declares
    its own: each is refused, naming what it misses, when it is defined; a type that
    inherits its parent's recognise without a DRAWING of its own is not recognised."""
    with pytest.raises(TypeError, match=r"Bare \(kind 'bare'\) declares a DRAWING but no "
                                        "recognise"):
        class Bare(groups.Crank):
            kind = "bare"
            FIELDS = groups.Crank.FIELDS
            DRAWING = groups.Drawing(0, 2, "a link", "a pin")
    with pytest.raises(TypeError, match=r"Looks \(kind 'looks'\) implements recognise but "
                                        "declares no DRAWING"):
        class Looks(groups.Crank):
            kind = "looks"
            FIELDS = groups.Crank.FIELDS

            @classmethod
            def recognise(cls, drawn, links):
                return False
    with pytest.raises(TypeError, match=r"DRAWING = 'two links' must be a Drawing or None"):
        class Words(groups.RRR):
            kind = "words"
            FIELDS = groups.RRR.FIELDS
            DRAWING = "two links"

    class Quiet(groups.RRR):
        kind = "quiet"
        FIELDS = groups.RRR.FIELDS

    assert "quiet" in registry and Quiet not in recognisers()
    with pytest.raises(ValueError, match="a group has 2 links or more"):
        groups.Drawing(0, 1, "a link", "a pin")


#: a five-bar: a crank at A, and a motor at C between its links 2 and 3
MOTOR_INSIDE = FIVE_BAR + '[[drivers]]\njoint = "A"\n\n[[drivers]]\njoint = "C"\n'


def test_a_driver_inside_a_group_is_refused_naming_it():
    assert problems(MOTOR_INSIDE) == [
        "[[drivers]] #2 (C): the decomposition cannot place this driver (a motor is placed "
        "once its first link 2 and its joint are, before its second link 3); a driver moves "
        "links that no group holds yet (not one inside a class III group or a closure)"]


def test_a_motor_follows_its_first_link_its_zero_that_link_s_direction():
    """A motor at B between the crank 1 and the link 2: its angle is 2's (B -> C)
    relative to 1's (B -> A), the crank's base turned by pi."""
    text = MOTOR_INSIDE.replace('joint = "C"', 'joint = "B"')
    d = Description.from_toml(text, "drawn.toml")
    crank, motor, dyad = d.groups
    assert (motor["type"], motor["link"], motor["pivot"], motor["tip"], motor["base"]) == (
        "crank", "2", "B", "C", "1")
    assert motor["offset"] == pytest.approx(math.pi, abs=1e-15)
    # B -> A is (-0.1, -0.1), B -> C (0.1, 0.2)
    want = math.atan2(-0.1 * 0.2 + 0.1 * 0.1, -0.1 * 0.1 - 0.1 * 0.2)
    assert d.inputs["theta_B"] == pytest.approx(want, abs=1e-15)
    assert dyad["type"] == "RRR" and (dyad["end1"], dyad["middle"], dyad["end2"]) == (
        "C", "D", "E")

"""The closure group (an Assur group of revolute pairs solved as one): a six-bar whose
ternary link E-F-G is held by three binary rods, pinned to the crank tip B and to the
frame points C and D (a class III group), written in group form.

References, each written here from the drawn pose and the links' distances, not from
the library's groups: a continuation of the positions with numpy in steps of 0.5 deg;
mpmath.findroot at 50 digits and its central finite differences; the direct solver
(the whole linear system of every link) for the group's own statics; the dyad (RRR) for
a four-bar written as a closure.
"""

from __future__ import annotations

import math
import re
import warnings

import mpmath
import numpy as np
import pytest

import arclength
import fmu_cache
import triads
from linkage_fmu import AssemblyError, Description, NearSingularWarning, newton, presets
from linkage_fmu.descriptions.description import DescriptionError
from linkage_fmu.groups import Closure, closure
from linkage_fmu.precise import reference

TH0 = 0.5  # the drawn crank angle, rad
R = 0.05  # the crank's length, m
C, D = (0.55, 0.05), (0.15, 0.5)
POSE = {"E": (0.25, 0.2), "F": (0.45, 0.25), "G": (0.35, 0.38)}
LINKS = {"3": ["B", "E"], "4": ["C", "F"], "6": ["D", "G"], "5": ["E", "F", "G"]}
#: the distances the group keeps, every pair of joints of one link
PAIRS = [("B", "E"), ("C", "F"), ("D", "G"), ("E", "F"), ("E", "G"), ("F", "G")]
FORCES = {"F13": ("1", "3"), "F35": ("3", "5"), "F04": ("0", "4"), "F45": ("4", "5"),
          "F06": ("0", "6"), "F65": ("6", "5")}


def six_bar(r: float = R, links: dict | None = None, pose: dict | None = None,
            theta="th0") -> Description:
    """The class III six-bar in group form, with gravity and a force on the ternary link."""
    drawn = {"B": ["r * cos(th0)", "r * sin(th0)"], "C": list(C), "D": list(D),
             **{p: list(xy) for p, xy in POSE.items()}}
    d = (Description("class3", model="Class3", frame="0", gravity="g")
         .parameter("r", r, "length", "crank radius")
         .parameter("th0", TH0, "angle", "crank angle of the drawn pose")
         .parameter("g", 9.81, "gravity", "gravitational acceleration")
         .point("A", 0, 0).point("C", *C).point("D", *D)
         .group("crank", link="1", pivot="A", tip="B", length="r")
         .group("closure", links=LINKS if links is None else links,
                pose=drawn if pose is None else pose, theta=theta)
         .body("1", mass=1.0, inertia=0.001, cg={"from": "A", "along": "r / 2"})
         .body("3", mass=0.5, inertia=0.002, cg={"from": "B", "along": 0.1})
         .body("4", mass=0.4, inertia=0.0015, cg={"from": "C", "along": 0.1})
         .body("6", mass=0.3, inertia=0.001, cg={"from": "D", "along": 0.1})
         .body("5", mass=1.2, inertia=0.01, cg={"from": "E", "along": 0.1, "across": 0.05})
         .load("P", body="5", kind="force", at="G", direction=[0.3, -1],
               description="a force on the ternary link at G")
         .effort("Mb", body="1")
         .output("effort", name="Mb"))
    for name, (by, on) in FORCES.items():
        d.output("force", name=name, by=by, on=on)
    return d


def drawn(theta: float) -> dict:
    """The frame points and the crank tip at ``theta``."""
    return {"C": C, "D": D, "B": (R * math.cos(theta), R * math.sin(theta))}


def lengths() -> dict:
    p = {**drawn(TH0), **POSE}
    return {(i, j): math.dist(p[i], p[j]) for i, j in PAIRS}


def _residual(p: dict, L: dict, lib=math):
    return [lib.sqrt((p[i][0] - p[j][0]) ** 2 + (p[i][1] - p[j][1]) ** 2) - L[i, j]
            for i, j in PAIRS]


def newton_numpy(theta: float, start: np.ndarray, L: dict) -> np.ndarray:
    """E, F, G (6 coordinates) at ``theta`` by Newton from ``start`` (numpy, dense)."""
    x = start.copy()
    for _ in range(50):
        p = {**drawn(theta), "E": x[0:2], "F": x[2:4], "G": x[4:6]}
        f = np.array([(p[i][0] - p[j][0]) ** 2 + (p[i][1] - p[j][1]) ** 2 - L[i, j] ** 2
                      for i, j in PAIRS])
        J = np.zeros((6, 6))
        for row, (i, j) in enumerate(PAIRS):
            for point, sign in ((i, 2.0), (j, -2.0)):
                if point in "EFG":
                    c = 2 * "EFG".index(point)
                    J[row, c:c + 2] = sign * (np.asarray(p[i]) - np.asarray(p[j]))
        d = np.linalg.solve(J, f)
        x -= d
        if np.abs(d).max() < 1e-15:
            break
    return x


def track(thetas) -> np.ndarray:
    """Positions of E, F, G at ``thetas`` continued from the drawn pose by the shorter
    way in steps of at most 0.5 deg (the reference's own path and steps)."""
    L = lengths()
    out = []
    for theta in thetas:
        delta = math.atan2(math.sin(theta - TH0), math.cos(theta - TH0))
        n = max(1, math.ceil(abs(delta) / math.radians(0.5)))
        x = np.array([v for p in "EFG" for v in POSE[p]], float)
        for k in range(1, n + 1):
            x = newton_numpy(TH0 + delta * k / n, x, L)
        out.append(x)
    return np.array(out).T


def mp_position(theta, start) -> list:
    """E, F, G at ``theta`` by mpmath.findroot (at the working precision) from ``start``."""
    # the lengths from the drawn pose in mpmath (the floats are its exact values)
    p0 = {**{k: (mpmath.mpf(x), mpmath.mpf(y)) for k, (x, y) in POSE.items()},
          "B": (R * mpmath.cos(mpmath.mpf(TH0)), R * mpmath.sin(mpmath.mpf(TH0))),
          "C": tuple(map(mpmath.mpf, C)), "D": tuple(map(mpmath.mpf, D))}
    L = {(i, j): mpmath.sqrt((p0[i][0] - p0[j][0]) ** 2 + (p0[i][1] - p0[j][1]) ** 2)
         for i, j in PAIRS}
    fixed = {"B": (R * mpmath.cos(theta), R * mpmath.sin(theta)),
             "C": p0["C"], "D": p0["D"]}

    def f(*x):
        p = {**fixed, "E": x[0:2], "F": x[2:4], "G": x[4:6]}
        return [(p[i][0] - p[j][0]) ** 2 + (p[i][1] - p[j][1]) ** 2 - L[i, j] ** 2
                for i, j in PAIRS]

    return list(mpmath.findroot(f, [mpmath.mpf(float(v)) for v in start],
                                tol=mpmath.mpf(10) ** -45))


@pytest.fixture(scope="module")
def mech():
    return six_bar().build()


ANGLES = [TH0 + math.radians(d) for d in (-60, -35, -10, 0, 5, 30, 59)]
THETAS = np.linspace(0.0, 2 * math.pi, 72, endpoint=False)


def test_the_drawn_angle_reproduces_the_drawn_pose(mech):
    """Tolerance: 1e-12 m."""
    st = mech.kinematics(TH0, order=0)
    for p, xy in POSE.items():
        assert math.dist(st.p[p], xy) <= 1e-12, p


def test_positions_keep_every_distance_and_the_drawn_assembly_mode(mech):
    """Every distance of the drawn pose holds to 1e-12 m, and the points are the
    reference continuation's (numpy Newton in 0.5 deg steps) to 1e-10 m: at 7 angles
    within 60 deg of the drawn one, and over 72 angles of a full turn (arrays)."""
    L = lengths()
    ref = track(ANGLES)
    for k, theta in enumerate(ANGLES):
        st = mech.kinematics(theta, order=0)
        assert max(map(abs, _residual(st.p, L))) <= 1e-12
        got = [v for p in "EFG" for v in st.p[p]]
        assert np.abs(np.array(got) - ref[:, k]).max() <= 1e-10
    st = mech.kinematics(THETAS, order=0)
    assert st.invalid is None or not st.invalid.any()
    res = np.array(_residual(st.p, L, np))
    assert np.abs(res).max() <= 1e-12
    got = np.array([v for p in "EFG" for v in st.p[p]])
    assert np.abs(got - track(THETAS)).max() <= 1e-10


def test_first_and_second_orders_are_finite_differences_of_an_mpmath_solve(mech):
    """Reference: central differences (h = 1e-12 and 1e-10) of mpmath.findroot at 50
    digits. Tolerance: 1e-8 of the largest coefficient of the order, for every point
    and link direction."""
    with mpmath.workdps(50):
        for theta in (ANGLES[0], ANGLES[3], ANGLES[5]):
            st = mech.kinematics(theta, order=2)
            start = [v for p in "EFG" for v in st.p[p]]
            t = mpmath.mpf(theta)
            h1, h2 = mpmath.mpf("1e-12"), mpmath.mpf("1e-10")
            at = {s: mp_position(t + s, start) for s in (-h1, h1, -h2, 0, h2)}
            d1 = [(a - b) / (2 * h1) for a, b in zip(at[h1], at[-h1])]
            d2 = [(a - 2 * c + b) / h2 ** 2 for a, c, b in zip(at[h2], at[0], at[-h2])]
            got1 = [v for p in "EFG" for v in st.d1[p]]
            got2 = [v for p in "EFG" for v in st.d2[p]]
            for got, ref in ((got1, d1), (got2, d2)):
                scale = max(abs(float(v)) for v in ref)
                assert max(abs(g - float(r)) for g, r in zip(got, ref)) <= 1e-8 * scale
            # the link directions: the ternary link's E -> F, rod 3's B -> E
            for link, (a, b) in (("5", ("E", "F")), ("3", ("B", "E"))):
                def phi(x, b=b, a=a, s=None):
                    p = {"E": x[0:2], "F": x[2:4]}
                    p["B"] = (R * mpmath.cos(s), R * mpmath.sin(s))
                    return mpmath.atan2(p[b][1] - p[a][1], p[b][0] - p[a][0])
                w1 = (phi(at[h1], s=t + h1) - phi(at[-h1], s=t - h1)) / (2 * h1)
                w2 = (phi(at[h2], s=t + h2) - 2 * phi(at[0], s=t)
                      + phi(at[-h2], s=t - h2)) / h2 ** 2
                assert abs(st.w1[link] - float(w1)) <= 1e-8 * max(1.0, abs(float(w1)))
                assert abs(st.w2[link] - float(w2)) <= 1e-8 * max(1.0, abs(float(w2)))


STATE = dict(omega=10.0, alpha=5.0, P=40.0)


def _relative(a, b, names) -> float:
    scale = np.max([np.abs(np.asarray(b[n], float)) for n in names], axis=0)
    return float(np.max([np.abs(np.asarray(a[n], float) - np.asarray(b[n], float)) / scale
                         for n in names]))


def test_the_group_by_group_statics_is_the_direct_solve(mech):
    """Reference: method="direct" (the LU solve of every link's equations).
    Tolerance: 1e-10 of the largest force or Mb at the state, over 72 angles and at
    the 7 angles one by one (omega 10 rad/s, alpha 5 rad/s2, g 9.81, the force P)."""
    forces = [n for n in mech.output_names if n.startswith("F") or n == "Mb"]
    a = mech.solve(THETAS, method="closed_form", **STATE)
    b = mech.solve(THETAS, method="direct", **STATE)
    assert a.valid.all() and _relative(a, b, forces) <= 1e-10
    for theta in ANGLES:
        assert _relative(mech.solve(theta, method="closed_form", **STATE),
                         mech.solve(theta, method="direct", **STATE), forces) <= 1e-10


def test_scalars_arrays_and_the_compiled_kernel_agree(mech):
    """The interpreted formulas on floats and on arrays, the traced kernel on floats
    and the compiled array kernel: equal to 1e-13 of the largest output at the state."""
    names = mech.output_names
    arrays = mech.solve(THETAS, method="interpreted", **STATE)
    compiled = mech.solve(THETAS, **STATE)
    if compiled.valid.all():  # without a C compiler: numpy again
        assert _relative(compiled, arrays, names) <= 1e-13
    kernel = mech.kernel()
    # the continuation is one loop of the C kernel (each step's Newton a loop inside
    # it), then the last step's Newton: nothing unrolled
    source = kernel.c_source()
    assert source.count(f"< {closure.TRIALS}; k") == 1
    assert source.count(f"< {closure.CORRECTIONS}; k") == 1
    assert source.count(f"< {newton.MAX_ITERATIONS}; k") == 1
    for k in range(0, 72, 7):
        one = mech.solve(float(THETAS[k]), method="interpreted", **STATE)
        row = {n: arrays[n][k] for n in names}
        assert _relative(one, row, names) <= 1e-13
        r = kernel(float(THETAS[k]), STATE["omega"], STATE["alpha"], STATE["P"])
        assert _relative({n: r[kernel.index[n]] for n in names}, one, names) <= 1e-13


def test_the_mpmath_path_agrees(mech):
    """Reference: the floats; linkage_fmu.precise.reference (40 digits) runs the same
    formulas in mpmath. Tolerance: 1e-11 of the largest output."""
    for theta in (ANGLES[1], ANGLES[4]):
        ref = {n: float(v) for n, v in reference(mech, theta, **STATE).items()}
        got = mech.solve(theta, **STATE)
        assert _relative(got, ref, mech.output_names) <= 1e-11


def test_a_state_the_group_cannot_reach_is_refused_not_solved():
    """With a crank twice as long the group cannot close over part of the turn: there a
    float state raises AssemblyError naming the group's joints, an array of states has
    NaN and valid False there, and the kernel refuses the same states. Where it
    closes, the distances hold to 1e-12 m."""
    mech = six_bar(r=0.1).build()
    L = lengths()
    L["B", "E"] = math.dist((0.1 * math.cos(TH0), 0.1 * math.sin(TH0)), POSE["E"])
    sol = mech.solve(THETAS, method="interpreted", **STATE)
    assert 0 < sol.valid.sum() < 72
    assert all(np.isnan(sol[n][~sol.valid]).all() for n in mech.output_names)
    kernel = mech.kernel()
    for k in range(72):
        theta = float(THETAS[k])
        assert (kernel(theta, 10.0, 5.0, 40.0) is not None) == sol.valid[k]
        if sol.valid[k]:
            st = mech.kinematics(theta, order=0)
            assert max(map(abs, _residual(st.p, L))) <= 1e-12
        else:
            with pytest.raises(AssemblyError, match="the group of joints B, E, C, F, D, G"):
                mech.solve(theta, **STATE)


def test_a_four_bar_written_as_a_closure_is_the_dyad():
    """Reference: the four-bar preset (its RRR dyad). Its coupler and rocker written as
    a closure drawn at 0.3 rad: every output and the transmission angle at C equal to
    1e-11 of the largest output, within 60 deg of the drawn angle."""
    rrr = presets.get("four_bar")
    d = presets.preset("four_bar").copy()
    st = rrr.kinematics(0.3, order=0)
    d.groups[1] = {"type": "closure", "links": {"2": ["B", "C"], "3": ["D", "C"]},
                   "pose": {p: list(st.p[p]) for p in "BCD"}, "theta": 0.3}
    closed = d._changed().build()
    names = rrr.output_names
    for theta in (0.3 + math.radians(x) for x in (-60, -20, 0, 25, 60)):
        a = closed.solve(theta, 10.0, 5.0, 3.0)
        b = rrr.solve(theta, 10.0, 5.0, 3.0)
        assert _relative(a, b, names) <= 1e-11
        assert abs(a["gamma_C"] - b["gamma_C"]) <= 1e-11


def test_friction_in_a_pin_of_the_group():
    """mu 0.2 and a 10 mm pin at E (links 3 and 5) and at C (frame and rod 4): the group
    by group solve equals the direct Newton on every link's equations to 1e-10 of the
    largest output, and the friction moment is mu r |R| at E."""
    d = six_bar().joint_friction("E", 0.2, 0.01).joint_friction("C", 0.2, 0.01)
    mech = d.build()
    names = mech.output_names
    for theta in ANGLES[::2]:
        a = mech.solve(theta, method="closed_form", **STATE)
        b = mech.solve(theta, method="direct", **STATE)
        assert _relative(a, b, [n for n in names if n != "eta"]) <= 1e-10
        assert abs(abs(a["Mf_E"]) - 0.2 * 0.01 * math.hypot(a["F35x"], a["F35y"])) <= 1e-12
    arrays = mech.solve(THETAS, method="closed_form", **STATE)
    direct = mech.solve(THETAS, method="direct", **STATE)
    assert _relative(arrays, direct, [n for n in names if n != "eta"]) <= 1e-10


def test_the_transmission_angle_and_the_condition_number_of_the_group(mech):
    """Reference: the angle at E between E -> B (rod 3) and E -> F (the ternary link),
    and numpy's 1-norm condition number of the group's equilibrium matrix assembled
    here (per link: forces x, y and the moment about its first joint over the length
    scale; per pair, the reaction of its first body on its second). Tolerance: 1e-12
    rad and 1e-9 relative."""
    group = mech.groups[1]
    pairs = [("B", "1", "3"), ("E", "3", "5"), ("C", "0", "4"), ("F", "4", "5"),
             ("D", "0", "6"), ("G", "6", "5")]
    first = {"3": "B", "4": "C", "6": "D", "5": "E"}
    L = mech.length_scale
    for theta in ANGLES:
        st = mech.kinematics(theta, order=0)
        p = {k: np.array(v) for k, v in st.p.items()}
        u, w = p["B"] - p["E"], p["F"] - p["E"]
        angle = math.atan2(abs(u[0] * w[1] - u[1] * w[0]), u @ w)
        A = np.zeros((12, 12))
        for row, link in enumerate(first):
            for k, (point, a, b) in enumerate(pairs):
                if link in (a, b):
                    s = 1.0 if link == b else -1.0
                    arm = (p[point] - p[first[link]]) / L
                    A[3 * row:3 * row + 3, 2 * k] += s * np.array([1.0, 0.0, -arm[1]])
                    A[3 * row:3 * row + 3, 2 * k + 1] += s * np.array([0.0, 1.0, arm[0]])
        gamma, kappa = group.transmission(st, L)
        assert abs(gamma - angle) <= 1e-12
        assert abs(kappa / np.linalg.cond(A, 1) - 1.0) <= 1e-9
        assert mech.solve(theta, outputs=("gamma_E",))["gamma_E"] == gamma


def test_the_pairs_are_named_by_their_points():
    """Compound joints chain the links at a point: E joins 3 and 4, E_5 joins 4 and 5."""
    links = {"3": ["B", "E"], "4": ["E", "C", "F"], "5": ["E", "F", "D"]}
    assert Closure.pairs({"links": links}, {"B", "C", "D"}) == ("B", "E", "E_5", "C", "F", "D")
    g = Closure(links, dict.fromkeys(["B", "C", "D", "E", "F"], (0.0, 0.0)), 0.0,
                {"B", "C", "D"})
    assert [(j.name, j.a, j.b) for j in g.joints] == [
        ("B", "<owner of the point>", "3"), ("E", "3", "4"), ("E_5", "4", "5"),
        ("C", "<owner of the point>", "4"), ("F", "4", "5"), ("D", "<owner of the point>", "5")]


BAD = [
    (dict(links=["B", "E"]), "[[groups]] #2 (closure) links: must be a table { LINK = "
                             "[POINT, POINT, ...], ... }"),
    (dict(links={**LINKS, "3": "B"}), "[[groups]] #2 (closure) links 3: must be a list of "
                                      "point names"),
    (dict(links={**LINKS, "7": ["G"]}), "[[groups]] #2 (closure) links 7: a link has two "
                                        "joints or more; it has 1"),
    (dict(links={**LINKS, "3": ["B", "E", "B"]}), "[[groups]] #2 (closure) links 3: lists B "
                                                  "twice"),
    (dict(pose=[1, 2]), "[[groups]] #2 (closure) pose: must be a table { POINT = [x, y], "
                        "... }"),
    (dict(links={**LINKS, "4": ["C", "D", "F"]}), "[[groups]] #2 (closure) links: link '4' "
                                                  "is pinned to the placed points C and D"),
    (dict(links={**LINKS, "6": ["D", "H"]}), "[[groups]] #2 (closure) pose: no [x, y] for "
                                             "H, a joint of link '6'"),
    (dict(pose={"B": [0, 0], "C": [0, 0], "D": [0, 0], "E": [0, 0], "F": [0, 0],
                "G": [0, 0], "K": [1, 1]}), "[[groups]] #2 (closure) pose K: is listed "
                                            "by no link"),
    (dict(links={"3": ["B", "E"], "4": ["C", "F"]}, pose={"B": [0, 0], "C": [0, 0],
                                                         "E": [1, 0], "F": [1, 1]}),
     "[[groups]] #2 (closure) links: no point the group places joins two of its links"),
    (dict(links={"3": ["B", "E"], "4": ["C", "F"], "5": ["E", "F"]}),
     "[[groups]] #2 (closure) links: 3 distance equations for 4 unknown coordinates (x and "
     "y of E, F): an Assur group has as many"),
]


@pytest.mark.parametrize("fields, message", BAD, ids=range(len(BAD)))
def test_bad_fields_are_description_errors(fields, message):
    pose = fields.pop("pose", None)
    if pose is None and "links" in fields and isinstance(fields["links"], dict):
        listed = {p for js in fields["links"].values() if isinstance(js, list) for p in js}
        base = {"B": [0.0, 0.0], "C": list(C), "D": list(D), **POSE}
        pose = {p: list(base[p]) for p in listed if p in base}
    with pytest.raises(DescriptionError, match=re.escape(message)):
        six_bar(pose=pose, **fields).check()


def test_a_drawn_pose_off_the_groups_before_is_refused():
    """B drawn where the crank does not put it at the drawn angle."""
    pose = {"B": [0.05, 0.0], "C": list(C), "D": list(D),
            **{p: list(xy) for p, xy in POSE.items()}}
    with pytest.raises(ValueError, match=re.escape(
            "class3: the group of joints B, E, C, F, D, G: pose B = [0.05, 0] is not where "
            "the groups before it place B at the drawn angle theta = 0.5 rad, [0.0438791, "
            "0.0239713]")):
        six_bar(pose=pose).build()


def test_a_drawn_angle_the_groups_before_cannot_reach_is_refused():
    """A dyad before the group that cannot close at the drawn angle (pi: |BQ| = 0.6 m
    > 0.25 + 0.25 m): building says so, naming the group."""
    d = (Description("upstream", model="Upstream", frame="0")
         .point("A", 0, 0).point("Q", 0.5, 0).point("C", 0.5, 0.4)
         .group("crank", link="1", pivot="A", tip="B", length=0.1)
         .group("RRR", link1="2", link2="7", end1="B", middle="M", end2="Q", length1=0.25,
                length2=0.25, branch=1)
         .group("point", link="2", **{"from": "B"}, name="N", along=0.1)
         .group("closure", links={"3": ["N", "E"], "4": ["C", "E"]},
                pose={"N": [0.2, 0.1], "E": [0.3, 0.3], "C": [0.5, 0.4]}, theta="pi")
         .effort("Mb", body="1").output("effort", name="Mb"))
    for link, at in zip("12734", "BBQNC"):
        d.body(link, mass=1.0, cg={"from": at})
    with pytest.raises(ValueError, match=re.escape(
            "the group of joints N, E, C: the linkage cannot be assembled at the drawn angle "
            "theta = 3.14159 rad: the dyad B-M-Q cannot close")):
        d.build()


# -- the assembly mode it follows, at the edges (tests/triads.py) -------------------------
@pytest.fixture(scope="module")
def designs() -> list:
    """160 random triad six-bars, every other one drawn near a limit position, each with
    25 states: ``(design, branch, thetas)``."""
    return triads.designs(160)


@pytest.fixture(scope="module")
def triad_kernel(designs):
    """The compiled static kernel of the triad with its coordinates as parameters
    (skips without a C compiler)."""
    kernel = triads.triad(designs[0][0]).build().kernel(static=True)
    if not kernel.compile():
        pytest.skip("no C compiler: the compiled kernel is what is compared here")
    return kernel


def test_no_state_is_answered_on_another_assembly_mode(designs, triad_kernel):
    """160 random triad six-bars (every other one drawn within 1e-3 rad of a limit
    position, on either mode that meets there), 25 static states each, against the
    reference pseudo-arclength continuation of the whole linkage (tests/arclength.py),
    by :func:`triads.judge`: a state the drawn mode reaches farther than 1e-9 rad from a
    limit is solved, its transmission angle at E within 1e-9 rad of the reference's and
    its Mb within 1e-6 of max(1, |Mb|) N.m (more near a limit, where Mb grows without
    bound); a state past a limit is refused for a reason of kind 'assembly', the Python
    kernel by the same guard as the compiled one (once per design); nearer than 1e-9
    rad, either. Reached, refused and near states are each a large share."""
    counts = {"reached": 0, "past": 0, "near": 0}
    for design, branch, thetas in designs:
        checked = False
        for theta in thetas:
            kind, r = triads.judge(triad_kernel, design, branch, theta)
            counts[kind] += 1
            if kind == "past" and not checked:
                _, slow = triads.kernel_at(triad_kernel, design)
                assert slow(theta, 0.0, 0.0, triads.TORQUE) == r, (design, theta)
                checked = True
    assert counts["reached"] > 1500 and counts["past"] > 1000 and counts["near"] > 50, counts


def _built(design: arclength.Design):
    """The triad drawn as ``design``, built on its numbers (near a limit it warns)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NearSingularWarning)
        return triads.triad(design).build()


def test_the_formulas_on_floats_and_arrays_decide_as_the_kernel(designs, triad_kernel):
    """Every tenth design built on its own numbers. On floats, at a state reached and one
    past a limit: the points E, F, G within 1e-9 m of the reference's, or AssemblyError
    saying the group cannot reach the state on its drawn mode. On arrays, at the 25
    states of two designs of each kind: valid where the kernel solves (farther than 1e-9
    rad from a limit), gamma_E within 1e-9 rad of the kernel's."""
    igamma = triad_kernel.index["gamma_E"]
    for k, (design, branch, thetas) in enumerate(designs[::10]):
        mech = _built(design)
        reached = [t for t in thetas if branch.margin(t) > 1e-6]
        past = [t for t in thetas if branch.margin(t) < -1e-6]
        for theta in reached[:1]:
            st = mech.kinematics(theta, order=0)
            got = np.array([v for p in "EFG" for v in st.p[p]])
            assert np.abs(got - branch.at(theta)).max() <= 1e-9, (k, theta)
        for theta in past[:1]:
            with pytest.raises(AssemblyError, match="cannot reach the state on its drawn"):
                mech.kinematics(theta, order=0)
        if k < 4:
            fast, _ = triads.kernel_at(triad_kernel, design)
            sol = mech.solve(np.array(thetas), 0.0, 0.0, triads.TORQUE, method="interpreted")
            for i, theta in enumerate(thetas):
                r = fast(theta, 0.0, 0.0, triads.TORQUE)
                if abs(branch.margin(theta)) > triads.REACH:
                    assert bool(sol.valid[i]) == (type(r) is tuple), (k, theta)
                if sol.valid[i] and type(r) is tuple:
                    assert abs(sol["gamma_E"][i] - r[igamma]) <= 1e-9, (k, theta)


def test_the_native_fmu_follows_the_drawn_mode(designs, triad_kernel, tmp_path):
    """The native FMU of the triad with its coordinates as parameters, set at each of 8
    designs (4 drawn near a limit), 25 steps each (200 states), in a fresh host process
    (tests/fmu_raw_host.py): doStep answers OK with Mb and gamma_E equal to the compiled
    kernel's (:func:`triads.close`: to 1e-12 of max(1, |value|), and 1e-15 of its
    condition number more) where the library solves the state, Discard where it refuses
    it; no call answers Error or Fatal (tests/triads.py runs every state of
    any number of designs, with fuzzed inputs)."""
    from fmpy import read_model_description

    from test_fmu_protocol import DISCARD, ERROR, OK, raw

    source = tmp_path / "triad.toml"
    source.write_text(triads.triad(designs[0][0]).to_toml())
    fmu = fmu_cache.build_native_fmu(str(source), tmp_path / "dist")
    refs = {v.name: v.valueReference for v in read_model_description(str(fmu)).modelVariables}
    runs = [(design, thetas) for design, _, thetas in designs[:8]]
    ops = triads.fmu_ops(refs, runs)
    out = raw(fmu.parent, ops, tmp_path, models=("Triad",))
    statuses = [status for status, _ in out["results"]]
    assert ERROR not in statuses
    steps = iter(i for i, op in enumerate(ops) if op[1] == "doStep")
    counts = {OK: 0, DISCARD: 0}
    for design, thetas in runs:
        fast, _ = triads.kernel_at(triad_kernel, design)
        for theta in thetas:
            i = next(steps)
            status, values = statuses[i], out["results"][i + 1][1]
            counts[status] = counts.get(status, 0) + 1
            r = fast(theta, 0.0, 0.0, triads.TORQUE)
            if type(r) is not tuple:
                assert status == DISCARD, (design, theta)
                continue
            assert status == OK, (design, theta)
            assert triads.close(values, r, triad_kernel), (design, theta, values)
    assert sum(counts.values()) == 200 and counts[OK] > 50 and counts[DISCARD] > 20, counts


def test_the_pythonfmu_fmu_follows_the_drawn_mode(designs, triad_kernel, tmp_path):
    """The pythonfmu FMU of the same triad at two designs (one drawn near a limit), 25
    steps each, as the native one: OK with the kernel's Mb and gamma_E where the library
    solves the state, Discard where it refuses it, no Error or Fatal."""
    from fmpy import read_model_description

    from test_fmu_protocol import DISCARD, ERROR, OK, raw

    source = tmp_path / "triad.toml"
    source.write_text(triads.triad(designs[0][0]).to_toml())
    fmu = fmu_cache.build_fmu(str(source), tmp_path / "dist")
    refs = {v.name: v.valueReference for v in read_model_description(str(fmu)).modelVariables}
    runs = [(design, thetas) for design, _, thetas in designs[2:4]]
    ops = triads.fmu_ops(refs, runs)
    out = raw(fmu.parent, ops, tmp_path, models=("Triad",))
    statuses = [status for status, _ in out["results"]]
    assert ERROR not in statuses
    steps = iter(i for i, op in enumerate(ops) if op[1] == "doStep")
    for design, thetas in runs:
        fast, _ = triads.kernel_at(triad_kernel, design)
        for theta in thetas:
            i = next(steps)
            r = fast(theta, 0.0, 0.0, triads.TORQUE)
            if type(r) is not tuple:
                assert statuses[i] == DISCARD, (design, theta)
            else:
                assert statuses[i] == OK, (design, theta)
                assert triads.close(out["results"][i + 1][1], r, triad_kernel), (design, theta)


def test_a_pose_drawn_near_a_limit_warns_and_one_at_a_singular_position_is_refused(designs):
    """Drawn 1e-7 rad from a limit position: building warns (NearSingularWarning), naming
    the group and the condition number of its equations in the drawn pose, each row over
    its distance: numpy's 2-norm condition number of the reference's Jacobian so scaled,
    to 3 digits. The six-bar above, drawn far from one, builds without it. The four-bar's
    coupler and rocker as a closure drawn with C on the line B-D are refused: the drawing
    does not fix the assembly mode."""
    design, branch, _ = next(item for item in designs
                             if any(at is not None for at in item[1].limits))
    way, at = next((w, a) for w, a in zip((1.0, -1.0), branch.limits) if a is not None)
    x = branch.at(at - way * 1e-7)
    near = triads.redrawn(design, at - way * 1e-7, x)
    scaled = arclength.Branch(near)._J(np.array([near.theta0 * near.r, *x]))[:, 1:]
    scaled /= np.array([[L] for L in near.lengths.values()])
    cond = np.linalg.cond(scaled)
    with pytest.warns(NearSingularWarning) as caught:
        triads.triad(near).build()
    message = str(caught[0].message)
    assert message.startswith("the group of joints B, E, C, F, D, G is drawn near a singular "
                              "position: the condition number of its equations there is ")
    said = float(re.search(r"there is ([0-9.e+]+)", message)[1])
    assert cond > 1e3 and abs(said / cond - 1.0) <= 5e-3, (said, cond)
    with warnings.catch_warnings():
        warnings.simplefilter("error", NearSingularWarning)
        six_bar().build()
    d = presets.preset("four_bar").copy()
    d.groups[1] = {"type": "closure", "links": {"2": ["B", "C"], "3": ["D", "C"]},
                   "pose": {"B": [0.1, 0.0], "C": [0.25, 0.0], "D": [0.4, 0.0]}, "theta": 0.0}
    with pytest.raises(ValueError, match=re.escape(
            "its pose is drawn at a singular position (its equations have no unique solution "
            "there): the drawing does not fix its assembly mode")):
        d._changed().build()

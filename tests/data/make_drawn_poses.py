"""Write the joints-and-links files: in tests/data, the four_bar, six_bar and
slider_crank presets and examples/coupler_four_bar.toml, drawn at a crank angle of
60 deg; in examples/, Jansen's and Klann's linkages and the six-bar with a class III
group. Every pose is closed by
:func:`newton_euler.assemble` from the links' lengths (run from the repository root:
``python tests/data/make_drawn_poses.py``)."""

from __future__ import annotations

import math
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

import numpy as np  # noqa: E402

from newton_euler import assemble  # noqa: E402

THETA = math.radians(60.0)


def xy(p) -> str:
    return f"[{float(p[0])!r}, {float(p[1])!r}]"


def four_bar() -> str:
    l_ab, l_bc, l_cd, l_ad = 0.10, 0.35, 0.30, 0.40
    b = (l_ab * math.cos(THETA), l_ab * math.sin(THETA))
    p = assemble({"A": (0.0, 0.0), "B": b, "D": (l_ad, 0.0)}, {"C": (0.35, 0.3)},
                 [("B", "C", l_bc), ("D", "C", l_cd)])
    s2 = p["B"] + 0.175 / l_bc * (p["C"] - p["B"])
    s3 = p["D"] + 0.15 / l_cd * (p["C"] - p["D"])
    return f'''# The four_bar preset at its default parameters, drawn at theta = 60 deg (branch +1:
# C left of B->D), as joints and links. Written by tests/data/make_drawn_poses.py.
[linkage]
name = "four_bar_joints"
frame = "4"
gravity = "g"

[parameters]
g = {{ default = 9.81, kind = "gravity", description = "gravity along -y" }}

[joints]
A = {xy(p["A"])}
B = {xy(p["B"])}
C = {xy(p["C"])}
D = {xy(p["D"])}

[[links]]
name = "1"
joints = ["A", "B"]
mass = 1.0
inertia = 0.0
cg = {xy(p["A"])}

[[links]]
name = "2"
joints = ["B", "C"]
mass = 2.0
inertia = 0.02
cg = {xy(s2)}

[[links]]
name = "3"
joints = ["C", "D"]
mass = 1.5
inertia = 0.012
cg = {xy(s3)}

[crank]
link = "1"
pivot = "A"

[[loads]]
name = "load"
body = "3"
kind = "moment"
description = "moment Mr on the rocker, counter-clockwise positive"

[effort]
name = "Mb"
body = "1"
'''


def six_bar() -> str:
    l_oa, l_ab, l_o1b, l_o1k, l_kd = 0.15, 0.97, 0.66, 0.25, 0.86
    a, b, rho, m4 = 0.5, 0.37, 10.0, 20.0
    pa = (l_oa * math.cos(THETA), l_oa * math.sin(THETA))
    p = assemble({"O": (0.0, 0.0), "A": pa, "O1": (a, b)}, {"B": (0.3, 1.0)},
                 [("A", "B", l_ab), ("O1", "B", l_o1b)])
    k = p["O1"] + l_o1k / l_o1b * (p["B"] - p["O1"])
    d = np.array([a, k[1] + math.sqrt(l_kd ** 2 - (a - k[0]) ** 2)])  # D above K
    mid = {n: (p[u] + q) / 2 for n, u, q in (("OA", "O", p["A"]), ("AB", "A", p["B"]),
                                             ("O1B", "O1", p["B"]))}
    mid["KD"] = (k + d) / 2

    def rod(name, joints, length, cg):
        m = rho * length
        return (f'[[links]]\nname = "{name}"\njoints = {joints}\nmass = {m!r}\n'
                f'inertia = {m * length ** 2 / 12!r}\ncg = {xy(cg)}\n')

    return f'''# The six_bar preset (driver OA) at its default parameters, drawn at theta = 60 deg
# (branch_B +1, branch_D +1), as joints and links; the slider D runs in a frame guide on
# x = a (the joint "guide"). Written by tests/data/make_drawn_poses.py.
[linkage]
name = "six_bar_joints"
frame = "0"
gravity = "g"

[parameters]
g = {{ default = 9.81, kind = "gravity", description = "gravity along -y" }}

[joints]
O = {xy(p["O"])}
A = {xy(p["A"])}
B = {xy(p["B"])}
O1 = {xy(p["O1"])}
K = {xy(k)}
D = {xy(d)}
guide = {{ at = {xy(d)}, slide = [0.0, 1.0] }}

{rod("OA", '["O", "A"]', l_oa, mid["OA"])}
{rod("AB", '["A", "B"]', l_ab, mid["AB"])}
{rod("O1B", '["O1", "B", "K"]', l_o1b, mid["O1B"])}
{rod("KD", '["K", "D"]', l_kd, mid["KD"])}
[[links]]
name = "slider"
joints = ["D", "guide"]
mass = {m4!r}
inertia = 0.0
cg = {xy(d)}

[crank]
link = "OA"
pivot = "O"

[[loads]]
name = "load"
body = "slider"
kind = "force"
at = "D"
direction = [0, -1]
description = "external force on the slider along -y"

[effort]
name = "Mb"
body = "OA"
'''


def slider_crank() -> str:
    l_oa, l_ab, e = 0.05, 0.20, 0.01  # the preset's lengths, with an offset e = 0.01
    a = (l_oa * math.cos(THETA), l_oa * math.sin(THETA))
    b = (a[0] + math.sqrt(l_ab ** 2 - (e - a[1]) ** 2), e)  # on the +x side
    s2 = np.array(a) + 0.06 / l_ab * (np.array(b) - np.array(a))
    return f'''# The slider_crank preset with e = 0.01 (its other parameters at their defaults),
# drawn at theta = 60 deg, as joints and links: the piston 3 slides on a frame guide
# along +x through (0, e) (the joint "guide"). Written by tests/data/make_drawn_poses.py.
[linkage]
name = "slider_crank_joints"
frame = "4"
gravity = "g"

[parameters]
g = {{ default = 9.81, kind = "gravity", description = "gravity along -y" }}

[joints]
O = [0.0, 0.0]
A = {xy(a)}
B = {xy(b)}
guide = {{ at = {xy(b)}, slide = [1.0, 0.0] }}

[[links]]
name = "1"
joints = ["O", "A"]
mass = 0.0
inertia = 0.0
cg = [0.0, 0.0]

[[links]]
name = "2"
joints = ["A", "B"]
mass = 0.8
inertia = 0.004
cg = {xy(s2)}

[[links]]
name = "3"
joints = ["B", "guide"]
mass = 0.6
inertia = 0.0
cg = {xy(b)}

[crank]
link = "1"
pivot = "O"

[[loads]]
name = "load"
body = "3"
kind = "force"
at = "B"
direction = [-1, 0]
description = "force on the piston along the guide, towards the crank"

[effort]
name = "Mb"
body = "1"
'''


def coupler_four_bar() -> str:
    l_ab, l_bc, l_cd, l_ad = 0.10, 0.35, 0.30, 0.40
    b = (l_ab * math.cos(THETA), l_ab * math.sin(THETA))
    p = assemble({"A": (0.0, 0.0), "B": b, "D": (l_ad, 0.0)}, {"C": (0.35, 0.3)},
                 [("B", "C", l_bc), ("D", "C", l_cd)])
    along = (p["C"] - p["B"]) / l_bc
    point = p["B"] + 0.20 * along + 0.05 * np.array([-along[1], along[0]])
    return f'''# examples/coupler_four_bar.toml at its default parameters, drawn at theta = 60 deg,
# as joints and links: the coupler point P is a point of link 2 that is no joint.
# Written by tests/data/make_drawn_poses.py.
[linkage]
name = "coupler_four_bar_joints"
frame = "0"
gravity = "g"

[parameters]
g = {{ default = 9.81, kind = "gravity", description = "gravity along -y" }}

[joints]
A = {xy(p["A"])}
B = {xy(p["B"])}
C = {xy(p["C"])}
D = {xy(p["D"])}

[[links]]
name = "1"
joints = ["A", "B"]
mass = 0.0
inertia = 0.0
cg = {xy(p["A"])}

[[links]]
name = "2"
joints = ["B", "C"]
points = {{ P = {xy(point)} }}
mass = 2.0
inertia = 0.02
cg = {xy((p["B"] + p["C"]) / 2)}

[[links]]
name = "3"
joints = ["C", "D"]
mass = 1.5
inertia = 0.012
cg = {xy((p["C"] + p["D"]) / 2)}

[crank]
link = "1"
pivot = "A"

[[loads]]
name = "F_P"
body = "2"
kind = "force"
at = "P"
direction = [0, -1]
start = 80.0

[[loads]]
name = "T4"
body = "3"
kind = "moment"
start = 120.0

[effort]
name = "Mb"
body = "1"
'''


# --- the joints-and-links examples (examples/) ------------------------------------------

EXAMPLES = HERE.parents[1] / "examples"


def mm(v: float) -> str:
    return f'"{float(v) * 1000.0:.15g} mm"'


def mm_xy(p) -> str:
    return f"[{mm(p[0])}, {mm(p[1])}]"


def bar(p, u, v, rho):
    """(mass, inertia about the cg, cg) of a uniform bar u-v of linear density rho."""
    length = float(np.hypot(*(p[u] - p[v])))
    m = rho * length
    return m, m * length ** 2 / 12.0, (p[u] + p[v]) / 2.0


def plate(p, u, v, w, sigma):
    """(mass, inertia about the centroid, centroid) of a uniform triangular plate."""
    a, b, c = (p[u], p[v], p[w])
    area = 0.5 * abs((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
    m = sigma * area
    sides = sum(float(np.hypot(*(x - y))) ** 2 for x, y in ((a, b), (b, c), (c, a)))
    return m, m * sides / 36.0, (a + b + c) / 3.0


def bent(p, u, v, w, rho):
    """(mass, inertia, cg) of two uniform bars u-v and v-w welded at v."""
    parts = [bar(p, u, v, rho), bar(p, v, w, rho)]
    m = sum(x[0] for x in parts)
    cg = sum(x[0] * x[2] for x in parts) / m
    j = sum(x[1] + x[0] * float(np.hypot(*(x[2] - cg))) ** 2 for x in parts)
    return m, j, cg


def write_example(path, header, name, title, model, p, joints, links, crank, loads, omega,
                  on_frame=()):
    out = [header.rstrip(), "[linkage]", f'name = "{name}"', f'title = "{title}"',
           f'model = "{model}"', 'frame = "0"', 'gravity = "g"', "",
           "[parameters]",
           'g = { default = 9.81, kind = "gravity", description = "gravity along -y" }', "",
           "[joints]"]
    out += [f"{j} = {mm_xy(p[j])}" for j in joints]
    if on_frame:  # the frame's entry: its joints, each a pin of the frame
        out += ["", "[[links]]  # the frame: its pins", 'name = "0"',
                "joints = [" + ", ".join(f'"{j}"' for j in on_frame) + "]"]
    for link in links:
        lname, ljoints, lpoints, (m, inertia, cg), note = link
        out += ["", "[[links]]" + (f"  # {note}" if note else ""), f'name = "{lname}"',
                "joints = [" + ", ".join(f'"{j}"' for j in ljoints) + "]"]
        if lpoints:  # points of the link that are not joints, where drawn
            out.append("points = { " + ", ".join(f"{j} = {mm_xy(p[j])}" for j in lpoints)
                       + " }")
        out += [f"mass = {m:.17g}", f"inertia = {inertia:.17g}", f"cg = {mm_xy(cg)}"]
    out += ["", "[crank]", f'link = "{crank[0]}"', f'pivot = "{crank[1]}"']
    for ld in loads:
        out += ["", "[[loads]]"] + [f"{k} = {v}" for k, v in ld.items()]
    # no [[outputs]]: a linkage of joints and links names its own (F<i><j>, Mb, shake_*)
    out += ["", "[effort]", 'name = "Mb"', f'body = "{crank[0]}"', "",
            "[inputs]", f"omega = {omega!r}", ""]
    path.write_text("\n".join(out))


#: Jansen's "holy numbers" (cm), strandbeest.com/explains
HOLY = dict(a=38.0, b=41.5, c=39.3, d=40.1, e=55.8, f=39.4, g=36.7, h=65.7, i=49.0, j=50.0,
            k=61.9, l=7.8, m=15.0)


def jansen() -> None:
    cm = {k: v / 100.0 for k, v in HOLY.items()}
    fixed = {"O": (0.0, 0.0), "Z": (-cm["a"], -cm["l"]), "A": (0.0, cm["m"])}  # crank up
    # start of Newton: a sketch with the crank up, the leg hanging to the left
    guess = {"B": (-0.47, 0.33), "C": (-0.21, -0.43), "D": (-0.78, -0.14),
             "E": (-0.57, -0.47), "F": (-0.08, -0.90)}
    p = assemble(fixed, guess, [
        ("A", "B", cm["j"]), ("Z", "B", cm["b"]), ("A", "C", cm["k"]), ("Z", "C", cm["c"]),
        ("Z", "D", cm["d"]), ("B", "D", cm["e"]), ("D", "E", cm["f"]), ("C", "E", cm["g"]),
        ("E", "F", cm["h"]), ("C", "F", cm["i"])])
    rho, sigma = 0.15, 6.0
    links = [
        ("crank", ["O", "A"], [], bar(p, "O", "A", rho), "m = 15 cm"),
        ("j", ["A", "B"], [], bar(p, "A", "B", rho), "j = 50 cm"),
        ("k", ["A", "C"], [], bar(p, "A", "C", rho), "k = 61.9 cm"),
        ("bde", ["Z", "B", "D"], [], plate(p, "Z", "B", "D", sigma),
         "the upper triangle b = ZB, d = ZD, e = BD: a plate"),
        ("c", ["Z", "C"], [], bar(p, "Z", "C", rho), "c = 39.3 cm"),
        ("f", ["D", "E"], [], bar(p, "D", "E", rho), "f = 39.4 cm"),
        ("leg", ["C", "E"], ["F"], plate(p, "C", "E", "F", sigma),
         "the leg triangle g = CE, h = EF, i = CF: a plate, F the foot"),
    ]
    header = '''# One leg of Theo Jansen's Strandbeest (Jansen's linkage), with his "holy numbers"
# (strandbeest.com/explains, in cm): a = 38, l = 7.8 (the frame pivot Z from the crank
# axle O: 38 left, 7.8 down), m = 15 (crank OA), j = 50 (AB), b = 41.5 (ZB), c = 39.3
# (ZC), d = 40.1 (ZD), e = 55.8 (BD), f = 39.4 (DE), g = 36.7 (CE), h = 65.7 (EF),
# i = 49 (CF), k = 61.9 (AC). Drawn with the crank straight up (theta = 90 deg), the
# leg hanging to the left of the axle; the pose was closed by Newton on those lengths
# (tests/data/make_drawn_poses.py), so every drawn distance is a holy number.
# The pin A carries three links (crank, j, k) and so does C (k, c, leg): compound joints.
# Z is one frame pivot of two links, the triangle bde and the rocker c: the frame's
# entry in [[links]] lists it (and the crank axle O). Bars are PVC tube (0.15 kg/m,
# m = rho L, J = m L^2 / 12); the two triangles are plates of 6 kg/m^2 (9 mm plywood;
# J = m (a^2 + b^2 + c^2) / 36).
# The load F_foot is the ground's reaction on the foot F, straight up.
'''
    write_example(EXAMPLES / "jansen.toml", header, "jansen", "One leg of Jansen's linkage "
                  "(Strandbeest), holy numbers", "Jansen", p,
                  ["O", "A", "Z", "B", "C", "D", "E"], links, ("crank", "O"),
                  [dict(name='"F_foot"', body='"leg"', kind='"force"', at='"F"',
                        direction="[0, 1]", start="40.0",
                        description='"ground reaction on the foot F, along +y"')], 10.0,
                  on_frame=("O", "Z"))


#: Klann's linkage, optimised proportions published at boim.com/Walkin8r/Klann.html
#: (crank axle A at the origin; B, D frame pivots): units taken as cm
KLANN = dict(AC=17.5, Bx=-38.8, By=-12.5, Dx=-14.6, Dy=41.9, BH=23.7, CF=73.4, CH=38.8,
             DE=34.1, EF=57.7, EG=111.7, FG=59.0, FH=35.2)


def klann() -> None:
    cm = {k: v / 100.0 for k, v in KLANN.items()}
    theta = 0.0
    fixed = {"A": (0.0, 0.0), "B": (cm["Bx"], cm["By"]), "D": (cm["Dx"], cm["Dy"]),
             "C": (cm["AC"] * math.cos(theta), cm["AC"] * math.sin(theta))}
    guess = {"H": (-0.21, 0.03), "F": (-0.54, 0.15), "E": (-0.35, 0.69), "G": (-0.40, -0.42)}
    p = assemble(fixed, guess, [
        ("B", "H", cm["BH"]), ("C", "H", cm["CH"]), ("C", "F", cm["CF"]), ("H", "F", cm["FH"]),
        ("D", "E", cm["DE"]), ("E", "F", cm["EF"]), ("E", "G", cm["EG"]), ("F", "G", cm["FG"])])
    rho = 0.405
    links = [
        ("crank", ["A", "C"], [], bar(p, "A", "C", rho), "AC"),
        ("lower_rocker", ["B", "H"], [], bar(p, "B", "H", rho), "BH"),
        ("arm", ["C", "H", "F"], [], bent(p, "C", "H", "F", rho),
         "the connecting arm C-H-F: two bars welded at H"),
        ("upper_rocker", ["D", "E"], [], bar(p, "D", "E", rho), "DE"),
        ("leg", ["E", "F"], ["G"], bent(p, "E", "F", "G", rho),
         "the leg E-F-G, bent at the knee F: two bars welded at F, G the foot"),
    ]
    header = '''# One leg of Klann's linkage (US patent 6,260,862): a six-bar of pivots only.
# Proportions: the optimised Klann geometry published at boim.com/Walkin8r/Klann.html
# (units taken as cm): crank AC = 17.5 about the axle A; frame pivots B = (-38.8, -12.5)
# and D = (-14.6, 41.9) from A; lower rocker BH = 23.7; connecting arm C-H-F with
# CH = 38.8, FH = 35.2, CF = 73.4 (bent about 15 deg at H); upper rocker DE = 34.1; leg
# E-F-G with EF = 57.7, FG = 59, EG = 111.7 (the knee F bent about 34 deg), G the foot.
# That page gives the lengths, not the assembly modes: of the eight, the one drawn here
# (H above the line B->C; F above the line C->H; E above-left, the foot G below) is the
# one that assembles over the whole turn with the longest flat bottom of the foot path:
# its lowest 3 units span the whole stride of 64 units. Drawn with the crank along +x
# (theta = 0), closed by Newton on those lengths (tests/data/make_drawn_poses.py).
# Links are aluminium flat bar 25 x 6 mm (0.405 kg/m; m = rho L, J = m L^2 / 12); the
# arm and the leg are two such bars welded at their bend. F_foot is the ground's
# reaction on the foot G, straight up.
'''
    write_example(EXAMPLES / "klann.toml", header, "klann", "One leg of Klann's linkage",
                  "Klann", p, ["A", "C", "B", "H", "F", "D", "E"], links,
                  ("crank", "A"),
                  [dict(name='"F_foot"', body='"leg"', kind='"force"', at='"G"',
                        direction="[0, 1]", start="30.0",
                        description='"ground reaction on the foot G, along +y"')], 10.0)


def triad_six_bar() -> None:
    theta, r, rod, radius = math.radians(30.0), 0.04, 0.22, 0.08
    # an equilateral plate (vertices at 0.08 m from its centre), each rod along the tangent
    # of that circle at its vertex, so that the rods' lines never meet in one point
    centre = np.array([0.0, 0.30])
    p = {}
    for k, angle in enumerate((210.0, 90.0, 330.0), start=1):
        a = math.radians(angle)
        p[f"P{k}"] = centre + radius * np.array([math.cos(a), math.sin(a)])
        p[f"R{k}"] = p[f"P{k}"] + rod * np.array([-math.sin(a), math.cos(a)])
    tip = p.pop("R1")
    shift = tip - r * np.array([math.cos(theta), math.sin(theta)])  # the crank's axle -> origin
    p = {k: v - shift for k, v in p.items()}
    p.update(O=np.zeros(2), A=tip - shift, O2=p.pop("R2"), O3=p.pop("R3"))
    rho, sigma = 1.57, 78.5
    links = [
        ("crank", ["O", "A"], [], bar(p, "O", "A", rho), ""),
        ("rod1", ["A", "P1"], [], bar(p, "A", "P1", rho), "from the crank pin to the plate"),
        ("rod2", ["O2", "P2"], [], bar(p, "O2", "P2", rho), "from the frame pivot O2"),
        ("rod3", ["O3", "P3"], [], bar(p, "O3", "P3", rho), "from the frame pivot O3"),
        ("plate", ["P1", "P2", "P3"], [], plate(p, "P1", "P2", "P3", sigma),
         "the ternary link: a triangular plate"),
    ]
    header = '''# A six-bar whose only group besides the crank is of class III: a triangular plate
# P1 P2 P3 held by three binary rods, one pinned to the crank pin A, the others to the
# frame pivots O2 and O3. No dyad can be peeled off it: removing any two links leaves
# the rest unable to be placed on its own, so the plate and the three rods are one
# Assur group of class III, solved together. Our own geometry: an equilateral plate
# (vertices 80 mm from its centre), each rod 220 mm long along the tangent of that
# circle at its vertex, so that the three rods' lines never meet in one point (where
# the group would lock), and a crank of 40 mm drawn at theta = 30 deg. It assembles
# over the whole turn (checked by continuation in tests/test_examples_joints.py).
# Steel: rods of 20 x 10 mm bar (1.57 kg/m, m = rho L, J = m L^2 / 12), the plate
# 10 mm thick (78.5 kg/m^2, J = m (a^2 + b^2 + c^2) / 36). T is a load torque on the
# plate.
'''
    write_example(EXAMPLES / "triad_six_bar.toml", header, "triad_six_bar",
                  "Six-bar with a class III group (a plate on three rods)", "TriadSixBar", p,
                  ["O", "A", "O2", "O3", "P1", "P2", "P3"], links, ("crank", "O"),
                  [dict(name='"T"', body='"plate"', kind='"moment"', start="5.0",
                        description='"load torque on the plate, counter-clockwise positive"')],
                  10.0)


if __name__ == "__main__":
    (HERE / "four_bar_joints.toml").write_text(four_bar())
    (HERE / "six_bar_joints.toml").write_text(six_bar())
    (HERE / "slider_crank_joints.toml").write_text(slider_crank())
    (HERE / "coupler_four_bar_joints.toml").write_text(coupler_four_bar())
    jansen()
    klann()
    triad_six_bar()

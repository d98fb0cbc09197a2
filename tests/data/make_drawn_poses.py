"""Write the joints-and-links files of tests/data: the four_bar and six_bar presets at
their default parameters, drawn at a crank angle of 60 deg, every pose closed by
:func:`newton_euler.assemble` from the presets' lengths (run from the repository root:
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
    l_oa, l_ab, l_o1b, l_o1k, l_kd, a, b, rho, m4 = 0.15, 0.97, 0.66, 0.25, 0.86, 0.5, 0.37, 10.0, 20.0
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


if __name__ == "__main__":
    (HERE / "four_bar_joints.toml").write_text(four_bar())
    (HERE / "six_bar_joints.toml").write_text(six_bar())

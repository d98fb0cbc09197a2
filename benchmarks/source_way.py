"""The source documents' way, for comparison: per crank angle, the kinematics from the
closed-loop vector equations, then the 9x9 equilibrium matrix built with numpy and
solved with ``np.linalg.solve`` (the flowchart of the hinged four-bar worked example; the
MATLAB loop of the scotch yoke worked example).

The four-bar matrix is the hinged four-bar worked example's own (section 6), with the
centres of mass on the link axes (``beta = 0``) and the crank's at A, as there. The slider-crank is the
same scheme for the preset ``slider_crank`` with ``e = gamma = 0`` (its defaults).
"""

from __future__ import annotations

import math

import numpy as np


def four_bar(p: dict, theta: float, omega: float, alpha: float, Mr: float) -> np.ndarray:
    """One state of the four-bar: ``[F21x, F21y, F32x, F32y, F43x, F43y, F14x, F14y, Mb]``.

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> p = presets.get("four_bar").parameters
    >>> x = four_bar(p, 0.3, 10.0, 0.0, 0.0)
    >>> bool(abs(x[-1] - presets.get("four_bar").solve(0.3, 10.0)["Mb"]) < 1e-12)
    True
    """
    l1, l2, l3, l4 = p["l_AB"], p["l_BC"], p["l_CD"], p["l_AD"]
    # positions: B, then C as the intersection of circles about B and D (C left of B->D)
    bx, by = l1 * math.cos(theta), l1 * math.sin(theta)
    dx, dy = l4 - bx, -by
    d = math.hypot(dx, dy)
    phi2 = math.atan2(dy, dx) + math.acos((l2 * l2 + d * d - l3 * l3) / (2 * l2 * d))
    cx, cy = bx + l2 * math.cos(phi2), by + l2 * math.sin(phi2)
    phi3 = math.atan2(cy, cx - l4)
    # velocities and accelerations from the loop l1 e1 + l2 e2 - l3 e3 - l4 = 0
    s13, s12, s23 = math.sin(theta - phi3), math.sin(theta - phi2), math.sin(phi2 - phi3)
    c13, c12, c23 = math.cos(theta - phi3), math.cos(theta - phi2), math.cos(phi2 - phi3)
    w2 = -l1 * omega * s13 / (l2 * s23)
    w3 = -l1 * omega * s12 / (l3 * s23)
    e2 = (-l1 * alpha * s13 - l1 * omega ** 2 * c13 - l2 * w2 ** 2 * c23 + l3 * w3 ** 2) \
        / (l2 * s23)
    e3 = (-(l1 * alpha * s12 + l1 * omega ** 2 * c12 + l2 * w2 ** 2) + l3 * w3 ** 2 * c23) \
        / (l3 * s23)
    c2, s2, c3, s3 = math.cos(phi2), math.sin(phi2), math.cos(phi3), math.sin(phi3)
    abx = -l1 * (alpha * by / l1 + omega ** 2 * bx / l1)
    aby = l1 * (alpha * bx / l1 - omega ** 2 * by / l1)
    r2, r3 = p["l_BS2"], p["l_DS3"]
    a2x = abx + r2 * (-e2 * s2 - w2 ** 2 * c2)
    a2y = aby + r2 * (e2 * c2 - w2 ** 2 * s2)
    a3x = r3 * (-e3 * s3 - w3 ** 2 * c3)
    a3y = r3 * (e3 * c3 - w3 ** 2 * s3)
    g = p["g"]
    m2, m3 = p["m2"], p["m3"]
    G1, G2, G3 = -p["m1"] * g, -m2 * g, -m3 * g
    A = np.zeros((9, 9))
    A[0, 0], A[0, 6] = 1.0, -1.0
    A[1, 1], A[1, 7] = 1.0, -1.0
    A[2, 0], A[2, 1], A[2, 8] = -l1 * math.sin(theta), l1 * math.cos(theta), 1.0
    A[3, 0], A[3, 2] = -1.0, 1.0
    A[4, 1], A[4, 3] = -1.0, 1.0
    A[5, 2], A[5, 3] = -l2 * s2, l2 * c2
    A[6, 2], A[6, 4] = -1.0, 1.0
    A[7, 3], A[7, 5] = -1.0, 1.0
    A[8, 2], A[8, 3] = l3 * s3, -l3 * c3
    b = np.array([
        0.0, -G1, 0.0,
        m2 * a2x, -G2 + m2 * a2y,
        p["J_S2"] * e2 - r2 * c2 * (G2 - m2 * a2y) + r2 * s2 * (-m2 * a2x),
        m3 * a3x, -G3 + m3 * a3y,
        r3 * c3 * (m3 * a3y - G3) + r3 * s3 * (-m3 * a3x) + p["J_S3"] * e3 - Mr,
    ])
    return np.linalg.solve(A, b)


def slider_crank(p: dict, theta: float, omega: float, alpha: float, P: float) -> np.ndarray:
    """One state of the slider-crank: ``[F21x, F21y, F32x, F32y, N43, F14x, F14y, Mb]``.

    Unknowns (9): F21, F32, N43 and the guide couple M43 on the piston, F14, Mb; rows:
    forces and moment of crank (about O), rod (about its centre of mass) and piston.

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> p = presets.get("slider_crank").parameters
    >>> x = slider_crank(p, 0.3, 10.0, 0.0, 50.0)
    >>> bool(abs(x[-1] - presets.get("slider_crank").solve(0.3, 10.0, 0.0, 50.0)["Mb"]) < 1e-12)
    True
    """
    l1, l2, r1, r2 = p["l_OA"], p["l_AB"], p["l_OS1"], p["l_AS2"]
    ct, st = math.cos(theta), math.sin(theta)
    s2 = -l1 * st / l2                      # rod angle: A_y + l2 sin(phi2) = 0
    c2 = math.sqrt(1.0 - s2 * s2)           # piston on the +x side
    w2 = -l1 * omega * ct / (l2 * c2)
    e2 = (l1 * omega ** 2 * st - l1 * alpha * ct + l2 * w2 ** 2 * s2) / (l2 * c2)
    aAx, aAy = -l1 * (alpha * st + omega ** 2 * ct), l1 * (alpha * ct - omega ** 2 * st)
    a1x, a1y = aAx * r1 / l1, aAy * r1 / l1
    a2x = aAx + r2 * (-e2 * s2 - w2 ** 2 * c2)
    a2y = aAy + r2 * (e2 * c2 - w2 ** 2 * s2)
    aB = aAx - l2 * (e2 * s2 + w2 ** 2 * c2)
    g = p["g"]
    m1, m2, m3 = p["m1"], p["m2"], p["m3"]
    J1, J2 = p["J1"], p["J2"]
    ax, ay = l1 * ct, l1 * st               # A from O
    sx, sy = r2 * c2, r2 * s2               # S2 from A
    ux, uy = l2 * c2 - sx, l2 * s2 - sy     # B from S2
    # unknowns: F21x F21y F32x F32y N43 M43 F14x F14y Mb
    A = np.zeros((9, 9))
    A[0, 0], A[0, 6] = 1.0, -1.0
    A[1, 1], A[1, 7] = 1.0, -1.0
    A[2, 0], A[2, 1], A[2, 8] = -ay, ax, 1.0
    A[3, 0], A[3, 2] = -1.0, 1.0
    A[4, 1], A[4, 3] = -1.0, 1.0
    A[5, 0], A[5, 1], A[5, 2], A[5, 3] = -sy, sx, -uy, ux
    A[6, 2] = -1.0
    A[7, 3], A[7, 4] = -1.0, 1.0
    A[8, 5] = 1.0
    b = np.array([
        m1 * a1x, m1 * a1y + m1 * g, J1 * alpha + m1 * g * r1 * ct
        + r1 * (ct * m1 * a1y - st * m1 * a1x),
        m2 * a2x, m2 * a2y + m2 * g, J2 * e2,
        m3 * aB + P, m3 * g, 0.0,
    ])
    x = np.linalg.solve(A, b)
    return np.delete(x, 5)

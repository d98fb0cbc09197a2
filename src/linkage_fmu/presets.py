"""The four preset linkages of the specification, with its parameter and output names.

Each preset is a composition of a :class:`~linkage_fmu.kinematics.Crank`, Assur groups
and bodies; none has a solver of its own.

Examples
--------
>>> from linkage_fmu import presets
>>> presets.names()
('scotch_yoke', 'four_bar', 'six_bar', 'slider_crank')
>>> mech = presets.get("four_bar", l_AB=0.12)
>>> mech.output_names
('F21x', 'F21y', 'F32x', 'F32y', 'F43x', 'F43y', 'F14x', 'F14y', 'Mb')
>>> presets.get("four_bar", l_ab=0.12)
Traceback (most recent call last):
...
TypeError: four_bar has no parameter 'l_ab'; its parameters are: l_AB, l_BC, l_CD, l_AD, m1, J1, l_AS1, beta1, m2, J_S2, l_BS2, beta2, m3, J_S3, l_DS3, beta3, g, branch
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

from .kinematics import RPP, RRP, RRR, Crank, LinkPoint
from .mechanism import Body, Derived, Effort, EffortOutput, Force, Mechanism, Normal
from .parameters import Parameter, resolve

P = Parameter


@dataclass(frozen=True)
class Inputs:
    """Start values and meaning of the inputs of a preset (the seeds' values)."""

    theta: float = 0.0
    omega: float = 0.0
    alpha: float = 0.0
    load: float = 0.0
    load_unit: str = "N"
    load_description: str = ""


@dataclass(frozen=True)
class Preset:
    """A named linkage: parameter specification, input start values and a builder."""

    name: str
    title: str
    parameters: tuple
    inputs: Inputs
    build: Callable[[dict], Mechanism]


def _forces(name: str, by: str, on: str) -> list:
    return [Force(name + "x", by, on, "x"), Force(name + "y", by, on, "y")]


# -- scotch yoke (seed 000) ------------------------------------------------------
def _scotch_yoke(p: dict) -> Mechanism:
    h2 = p["h2"]
    groups = [
        Crank("1", "A", "B", p["l_AB"]),
        RPP("2", "3", "B", "S3", slot_angle=0.0, guide_point=(0.0, 0.0),
            guide_angle=math.pi / 2, slot_joint="slot", guide_joint="guide"),
    ]
    bodies = [Body("1", p["m1"], p["J1"], "A"), Body("2", p["m2"], 0.0, "B"),
              Body("3", p["m3"], p["J3"], "S3")]
    # guide (N along its normal -x, couple M about S3) as two bearings h2 apart along y:
    # F4 = upper bearing along +x, F4p = lower bearing along -x (the seed's FR4, FR4')
    outputs = _forces("F12", "1", "2") + [
        Force("F23y", "2", "3", "y"),
        Derived("F4", lambda R: -0.5 * R["guide"][0] - R["guide"][1] / h2,
                description="force of the upper guide bearing on the yoke, along +x"),
        Derived("F4p", lambda R: 0.5 * R["guide"][0] - R["guide"][1] / h2,
                description="force of the lower guide bearing on the yoke, along -x"),
    ] + _forces("F41", "4", "1") + [EffortOutput("Mb")]
    return Mechanism("scotch_yoke", "4", {"A": (0.0, 0.0)}, groups, bodies,
                     Effort("Mb", "1"), outputs, {"3": (0.0, -1.0, 0.0)}, p["g"], p)


SCOTCH_YOKE = Preset(
    "scotch_yoke", "Scotch yoke (sine mechanism), seed 000",
    (
        P("l_AB", 0.1, "length", "crank length AB"),
        P("h2", 0.08, "length", "spacing of the yoke's two guide bearings"),
        P("m1", 0.0, "mass", "crank mass (centre of mass at A)"),
        P("J1", 0.0, "inertia", "crank moment of inertia about A"),
        P("m2", 4.0, "mass", "slider block mass (centre of mass at B)"),
        P("m3", 10.0, "mass", "yoke mass (centre of mass on its axis)"),
        P("J3", 0.0, "inertia", "yoke moment of inertia"),
        P("g", 0.0, "gravity", "gravitational acceleration along -y"),
    ),
    Inputs(omega=10.0, load=400.0, load_unit="N",
           load_description="resistance force Fr on the yoke along -y"),
    _scotch_yoke,
)


# -- four-bar (seed 002) ---------------------------------------------------------
def _four_bar(p: dict) -> Mechanism:
    groups = [
        Crank("1", "A", "B", p["l_AB"]),
        RRR("2", "3", "B", "C", "D", p["l_BC"], p["l_CD"], p["branch"]),
    ]
    bodies = [
        Body("1", p["m1"], p["J1"], "A", p["l_AS1"], p["beta1"]),
        Body("2", p["m2"], p["J_S2"], "B", p["l_BS2"], p["beta2"]),
        Body("3", p["m3"], p["J_S3"], "D", p["l_DS3"], p["beta3"]),
    ]
    outputs = (_forces("F21", "2", "1") + _forces("F32", "3", "2") + _forces("F43", "4", "3")
               + _forces("F14", "1", "4") + [EffortOutput("Mb")])
    return Mechanism("four_bar", "4", {"A": (0.0, 0.0), "D": (p["l_AD"], 0.0)}, groups,
                     bodies, Effort("Mb", "1"), outputs, {"3": (0.0, 0.0, 1.0)}, p["g"], p)


FOUR_BAR = Preset(
    "four_bar", "Hinged four-bar, seed 002",
    (
        P("l_AB", 0.10, "length", "crank length AB"),
        P("l_BC", 0.35, "length", "coupler length BC"),
        P("l_CD", 0.30, "length", "rocker length CD"),
        P("l_AD", 0.40, "length", "frame length AD (D on the +x axis)"),
        P("m1", 1.0, "mass", "crank mass"),
        P("J1", 0.0, "inertia", "crank moment of inertia about its centre of mass"),
        P("l_AS1", 0.0, "distance", "crank centre of mass from A"),
        P("beta1", 0.0, "angle", "crank centre of mass direction: link angle - beta1"),
        P("m2", 2.0, "mass", "coupler mass"),
        P("J_S2", 0.02, "inertia", "coupler moment of inertia about S2"),
        P("l_BS2", 0.175, "distance", "coupler centre of mass S2 from B"),
        P("beta2", 0.0, "angle", "S2 direction: coupler angle - beta2"),
        P("m3", 1.5, "mass", "rocker mass"),
        P("J_S3", 0.012, "inertia", "rocker moment of inertia about S3"),
        P("l_DS3", 0.15, "distance", "rocker centre of mass S3 from D"),
        P("beta3", 0.0, "angle", "S3 direction: rocker angle - beta3"),
        P("g", 9.81, "gravity", "gravitational acceleration along -y"),
        P("branch", 1, "branch", "assembly mode: +1 puts C left of the line B->D"),
    ),
    Inputs(omega=10.0, load_unit="N.m",
           load_description="moment Mr on the rocker, counter-clockwise positive"),
    _four_bar,
)


# -- six-bar (seed 001) ----------------------------------------------------------
SIX_BAR_DRIVERS = ("OA", "AB", "O1B", "KD", "D")


def _six_bar(p: dict) -> Mechanism:
    a, b, rho = p["a"], p["b"], p["rho"]
    groups = [
        Crank("OA", "O", "A", p["l_OA"]),
        RRR("AB", "O1B", "A", "B", "O1", p["l_AB"], p["l_O1B"], p["branch_B"]),
        LinkPoint("O1B", "O1", "K", p["l_O1K"]),
        RRP("KD", "slider", "K", "D", p["l_KD"], (a, 0.0), math.pi / 2, p["branch_D"], "guide"),
    ]

    def rod(name, ref, length):
        m = rho * length
        return Body(name, m, m * length * length / 12.0, ref, length / 2.0)

    bodies = [rod("OA", "O", p["l_OA"]), rod("AB", "A", p["l_AB"]),
              rod("O1B", "O1", p["l_O1B"]), rod("KD", "K", p["l_KD"]),
              Body("slider", p["m4"], 0.0, "D")]
    driver = p["driver"]
    effort = (Effort("Pb", "slider", "D", (0.0, 1.0)) if driver == "D"
              else Effort("Mb", driver))
    outputs = (_forces("XO", "0", "OA") + _forces("XA", "AB", "OA") + _forces("XB", "O1B", "AB")
               + _forces("XO1", "0", "O1B") + _forces("XK", "KD", "O1B")
               + _forces("XD", "slider", "KD")
               + [Force("N4", "0", "slider", "x"), EffortOutput("Mb"),
                  EffortOutput("Pb", "N", "balancing vertical force on the slider, +y")])
    # seed 001 names the y components Y*, not X*y
    outputs = [_rename(o) for o in outputs]
    return Mechanism("six_bar", "0", {"O": (0.0, 0.0), "O1": (a, b)}, groups, bodies, effort,
                     outputs, {"slider": (0.0, -1.0, 0.0)}, p["g"], p)


def _rename(o):
    if isinstance(o, Force) and o.name.startswith("X") and o.name.endswith(("x", "y")):
        base = o.name[1:-1]
        return Force(("X" if o.axis == "x" else "Y") + base, o.by, o.on, o.axis)
    return o


SIX_BAR = Preset(
    "six_bar", "Six-bar with slider, seed 001 (static equilibrium, five driver variants)",
    (
        P("l_OA", 0.15, "length", "crank length OA"),
        P("l_AB", 0.97, "length", "coupler length AB"),
        P("l_O1B", 0.66, "length", "rocker length O1B"),
        P("l_O1K", 0.25, "distance", "distance of K from O1 along O1B"),
        P("l_KD", 0.86, "length", "connecting rod length KD"),
        P("a", 0.50, "coordinate", "x of O1; the slider guide is the line x = a"),
        P("b", 0.37, "coordinate", "y of O1"),
        P("rho", 10.0, "density", "linear density of the four rods"),
        P("m4", 20.0, "mass", "slider mass"),
        P("g", 9.81, "gravity", "gravitational acceleration along -y"),
        P("driver", "OA", "choice", "where the balancing effort acts", SIX_BAR_DRIVERS),
        P("branch_B", 1, "branch", "assembly mode: +1 puts B left of the line A->O1"),
        P("branch_D", 1, "branch", "assembly mode: +1 puts D above K"),
    ),
    Inputs(load_unit="N", load_description="external force on the slider along -y"),
    _six_bar,
)


# -- slider-crank ----------------------------------------------------------------
def _slider_crank(p: dict) -> Mechanism:
    gamma, e = p["gamma"], p["e"]
    q = (-e * math.sin(gamma), e * math.cos(gamma))  # offset e along the guide's left normal
    groups = [
        Crank("1", "O", "A", p["l_OA"]),
        RRP("2", "3", "A", "B", p["l_AB"], q, gamma, +1, "guide"),
    ]
    bodies = [Body("1", p["m1"], p["J1"], "O", p["l_OS1"]),
              Body("2", p["m2"], p["J2"], "A", p["l_AS2"]),
              Body("3", p["m3"], 0.0, "B")]
    outputs = (_forces("F21", "2", "1") + _forces("F32", "3", "2") + [Normal("N43", "guide")]
               + _forces("F14", "1", "4") + [EffortOutput("Mb")])
    towards_crank = (-math.cos(gamma), -math.sin(gamma), 0.0)
    return Mechanism("slider_crank", "4", {"O": (0.0, 0.0)}, groups, bodies, Effort("Mb", "1"),
                     outputs, {"3": towards_crank}, p["g"], p)


SLIDER_CRANK = Preset(
    "slider_crank", "Offset slider-crank",
    (
        P("l_OA", 0.05, "length", "crank length OA"),
        P("l_AB", 0.20, "length", "connecting rod length AB"),
        P("e", 0.0, "coordinate", "offset of the guide from O along its left normal"),
        P("gamma", 0.0, "angle", "direction of the guide (0 = +x)"),
        P("m1", 0.0, "mass", "crank mass"),
        P("J1", 0.0, "inertia", "crank moment of inertia about its centre of mass"),
        P("l_OS1", 0.0, "distance", "crank centre of mass from O"),
        P("m2", 0.8, "mass", "connecting rod mass"),
        P("J2", 0.004, "inertia", "connecting rod moment of inertia about its centre of mass"),
        P("l_AS2", 0.06, "distance", "connecting rod centre of mass from A"),
        P("m3", 0.6, "mass", "piston mass"),
        P("g", 9.81, "gravity", "gravitational acceleration along -y"),
    ),
    Inputs(omega=10.0, load_unit="N",
           load_description="force on the piston along the guide, towards the crank"),
    _slider_crank,
)

PRESETS = {p.name: p for p in (SCOTCH_YOKE, FOUR_BAR, SIX_BAR, SLIDER_CRANK)}


def names() -> tuple:
    """Names of the presets."""
    return tuple(PRESETS)


def preset(name: str) -> Preset:
    """The :class:`Preset` called ``name`` (parameter specs, input start values)."""
    try:
        return PRESETS[name]
    except KeyError:
        raise ValueError(f"no preset {name!r}; the presets are: {', '.join(PRESETS)}") from None


def get(name: str, **parameters) -> Mechanism:
    """Build the preset ``name`` with ``parameters`` overriding its defaults.

    Raises a ``TypeError`` for an unknown parameter name and a ``ValueError`` for an
    invalid value, naming the parameter.

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> mech = presets.get("slider_crank", e=0.01)
    >>> round(mech.solve(0.5, omega=100.0, load=1000.0)["Mb"], 3)
    -14.315
    """
    spec = preset(name)
    return spec.build(resolve(spec.parameters, parameters, name))

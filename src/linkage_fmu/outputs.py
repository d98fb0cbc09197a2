"""What a linkage reports: output declarations, each bound once to a mechanism.

``bind(mech)`` returns ``fn(R, E, st)`` of the reactions ``R`` (joint name -> ``(Fx, Fy)``
or ``(N, M)``), the balancing effort ``E`` and the kinematic state ``st``; it works on
floats and arrays alike.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from . import numerics
from .errors import OutputError
from .expressions import Expression


def has_friction(mech, joint: str) -> bool:
    """Whether the pair ``joint`` of ``mech`` has friction declared."""
    return any(jf.joint.name == joint for jf in mech.friction.joints)


def joint_between(mech, by: str, on: str, output: str):
    """The joint between bodies ``by`` and ``on``, and +1 if it is declared as the
    action of ``by`` on ``on``, -1 if the other way round."""
    for j in mech.joints:
        if {j.a, j.b} == {by, on}:
            return j, (1.0 if (j.a, j.b) == (by, on) else -1.0)
    raise OutputError(output, f"no joint between bodies {by!r} and {on!r}")


@dataclass(frozen=True)
class Force:
    """Output: component ``axis`` ('x' or 'y') of the force of body ``by`` on body ``on``."""

    name: str
    by: str
    on: str
    axis: str
    note: str = ""  # the description, if not the default one
    unit = "N"

    @property
    def description(self) -> str:
        return self.note or f"force of link {self.by} on link {self.on}, {self.axis} component"

    def bind(self, mech) -> Callable:
        j, sign = joint_between(mech, self.by, self.on, self.name)
        return j.force_output("xy".index(self.axis), sign, has_friction(mech, j.name))


@dataclass(frozen=True)
class Magnitude:
    """Output: magnitude of the force of body ``by`` on body ``on`` (bearing sizing)."""

    name: str
    by: str
    on: str
    note: str = ""
    unit = "N"

    @property
    def description(self) -> str:
        return self.note or f"magnitude of the force of link {self.by} on link {self.on}"

    def bind(self, mech) -> Callable:
        j, _ = joint_between(mech, self.by, self.on, self.name)
        return j.magnitude_output()


@dataclass(frozen=True)
class Normal:
    """Output: normal force of the prismatic pair ``joint`` (of body a on body b, along
    the pair's normal)."""

    name: str
    joint: str
    note: str = ""
    unit = "N"
    component = 0  # of the pair's reaction (N, M)
    what = "normal force of the prismatic pair '{joint}' along its normal"

    @property
    def description(self) -> str:
        return self.note or self.what.format(joint=self.joint)

    def bind(self, mech) -> Callable:
        i = self.component
        return lambda R, E, st: R[self.joint][i]


@dataclass(frozen=True)
class Couple(Normal):
    """Output: couple transmitted by the prismatic pair ``joint`` (of body a on body b)."""

    unit = "N.m"
    component = 1
    what = "couple of the prismatic pair '{joint}', counter-clockwise positive"


@dataclass(frozen=True)
class EffortOutput:
    """Output: the balancing effort if it is the one named ``name``, else zero."""

    name: str
    unit: str = "N.m"
    description: str = "balancing moment on the driver link, counter-clockwise positive"

    def bind(self, mech) -> Callable:
        if mech.effort.name == self.name:
            return lambda R, E, st: E
        return lambda R, E, st: 0.0


@dataclass(frozen=True)
class Derived:
    """Output: an expression of the joint reactions (``N_<joint>``, ``M_<joint>``,
    ``Fx_<joint>``, ``Fy_<joint>``), the balancing effort (by its name) and the
    parameters, e.g. the scotch yoke's two guide bearings."""

    name: str
    expression: str
    unit: str = "N"
    description: str = ""

    def bind(self, mech) -> Callable:
        by_name = {f"{k}_{j.name}": (j.name, i) for j in mech.joints
                   for i, k in enumerate(j.components)}

        def resolve(name):
            if name in by_name:
                joint, i = by_name[name]
                return lambda R, E, st: R[joint][i]
            if name == mech.effort.name:
                return lambda R, E, st: E
            if name in mech.parameters:  # a float, or a traced parameter
                return numerics.real(mech.parameters[name])
            return lambda R, E, st: 0.0  # another effort's name: not this linkage's effort

        return Expression(self.expression).bind(resolve)


#: the names of the shaking outputs every linkage has
SHAKING = ("shake_x", "shake_y", "shake_M")


@dataclass(frozen=True)
class Shaking:
    """Output: the shaking force (``component`` 'x' or 'y') or moment ('M'): the
    resultant of what the moving links exert on the frame, through its joints (their
    friction included) and through the driver (the reaction of the balancing effort,
    which the frame applies), the moment about the crank's pivot, counter-clockwise
    positive. It equals the external loads, weights and d'Alembert forces of the moving
    links together (their momentum balance: friction is internal); a load whose reaction also acts
    on the frame (gas pressure on a cylinder head) is not subtracted."""

    name: str
    component: str

    @property
    def unit(self) -> str:
        return "N.m" if self.component == "M" else "N"

    @property
    def description(self) -> str:
        if self.component == "M":
            return ("shaking moment: moment about the crank pivot of what the moving links "
                    "exert on the frame (joints and driver), counter-clockwise positive")
        return (f"shaking force: resultant force the moving links exert on the frame "
                f"(joints and driver), {self.component} component")

    def bind(self, mech) -> Callable:
        # each frame joint: +1 where the reaction is declared as the link's action on
        # the frame, -1 where it is the frame's on the link
        joints = [(j, 1.0 if j.b == mech.frame else -1.0) for j in mech.joints
                  if mech.frame in (j.a, j.b)]
        pivot, effort = mech.crank.pivot, mech.effort
        rubbing = {j.name for j, _ in joints if has_friction(mech, j.name)}

        def forces(R, E, st):
            """(fx, fy, point or None, couple) of each action on the frame."""
            for j, sign in joints:
                yield j.action(R, st, sign, j.name in rubbing)
            if effort.direction is None:  # the driver's reaction: a couple
                yield 0.0, 0.0, None, -E
            else:
                yield -E * effort.direction[0], -E * effort.direction[1], effort.point, 0.0

        if self.component in "xy":
            i = "xy".index(self.component)

            def resultant(R, E, st):
                total = 0.0
                for f in forces(R, E, st):
                    total = total + f[i]
                return total

            return resultant

        def moment(R, E, st):
            x0, y0 = st.p[pivot]
            total = 0.0
            for fx, fy, point, couple in forces(R, E, st):
                if point is not None:
                    x, y = st.p[point]
                    total = total + (x - x0) * fy - (y - y0) * fx
                total = total + couple
            return total

        return moment

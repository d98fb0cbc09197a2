"""What a linkage reports: output declarations, each bound once to a mechanism.

``bind(mech)`` returns ``fn(R, E, st)`` of the reactions ``R`` (joint name -> ``(Fx, Fy)``
or ``(N, M)``), the balancing effort ``E`` and the kinematic state ``st``; it works on
floats and arrays alike.

The output kinds of the ``[[outputs]]`` tables of description files are the classes
here with a ``kind``, in :attr:`Output.registry`: each declares its keys and what it
reports, checks its table and builds its outputs from it. A new kind is one class.

Examples
--------
>>> list(Output.registry)
['force', 'normal', 'couple', 'effort', 'expression']
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable
from dataclasses import dataclass
from typing import ClassVar

from . import numerics
from .drivers import EFFORTS
from .errors import InputTypeError, OutputError
from .expressions import Expression


class Output(ABC):
    """An output: one value at each state, with its ``name``, ``unit`` and
    ``description``; :meth:`bind` makes the function that computes it.

    A class with a ``kind`` of its own is the output kind of that name in the
    ``[[outputs]]`` tables of description files, registered in the order the classes
    are defined. It declares its own ``REPORTS`` and ``KEYS`` and implements
    :meth:`check` and :meth:`from_spec` (it may inherit these two); one that misses any
    is refused when it is defined (``TypeError`` naming it). A class without a kind is
    an output that no table declares by itself (a magnitude, the shaking force).

    Examples
    --------
    The contract with description files is on the class:

    >>> Normal.KEYS["joint"]
    'the prismatic pair, by its name (required)'
    >>> Output.registry["couple"] is Couple
    True

    A kind that does not say what it reports is refused when it is defined:

    >>> class Speed(Output):
    ...     kind = "speed_example"
    Traceback (most recent call last):
    ...
    linkage_fmu.errors.InputTypeError:
    output kind Speed (kind 'speed_example') must declare REPORTS, what its outputs
    report, for the reference of the format; it has none

    Attributes
    ----------
    kind : str
        Name of the kind in description files (``kind = "force"``), '' for none.
    REPORTS : str
        What the kind's outputs report, in one phrase with the unit.
    KEYS : dict of str to str
        The keys of the kind's table besides ``kind`` -> what each is, ``name``
        among them, in the order the reference lists them.
    registry : dict of str to type
        Kind -> class, of every output kind defined.
    """

    kind: ClassVar[str] = ""
    registry: ClassVar[dict[str, type]] = {}
    REPORTS: ClassVar[str]  # no default: every kind declares its own
    KEYS: ClassVar[dict[str, str]]

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        if cls.__dict__.get("kind"):  # a subclass that inherits its kind is no new kind
            problem = _contract_problem(cls)
            if problem:
                raise InputTypeError(f"output kind {cls.__qualname__} (kind {cls.kind!r}) "
                                     f"{problem}")
            if cls.kind in Output.registry:
                raise InputTypeError(f"output kind {cls.kind!r} is defined twice: "
                                     f"{Output.registry[cls.kind].__qualname__} and "
                                     f"{cls.__qualname__}")
            Output.registry[cls.kind] = cls

    @abstractmethod
    def bind(self, mech) -> Callable:
        """``fn(R, E, st)``: the output of the linkage ``mech`` at a state (the module
        says what the arguments are). Raises :class:`~linkage_fmu.errors.OutputError`
        for an output ``mech`` cannot report."""

    @classmethod
    def check(cls, checker, where: str, name: str, spec: dict) -> list[str]:
        """The names of the outputs the table ``spec`` of this kind gives (``name`` is
        its ``name``, an identifier), its problems added to the
        :class:`~linkage_fmu.descriptions.checker.Checker` ``checker``, each starting
        with ``where`` (the table). Unknown keys and the name are checked before, and
        that the names are not taken after. The checker says what the tables before
        define: its ``links``, ``joints`` (pairs), ``placed`` (points), ``d`` (the
        description), and checks values (``expr``, ``unit``).

        Every kind implements it; the base has nothing to check.
        """
        raise NotImplementedError(f"output kind {cls.kind!r} has no check")

    @classmethod
    def from_spec(cls, spec: dict, d) -> list[Output]:
        """The outputs of the checked table ``spec`` of this kind, in the description
        ``d`` (its ``efforts``, ...).

        Every kind implements it; the base has none.
        """
        raise NotImplementedError(f"output kind {cls.kind!r} builds no outputs")


def _contract_problem(cls: type) -> str:
    """What an output kind misses of the description-file contract, or ''."""
    if not isinstance(cls.kind, str) or not cls.kind.isidentifier():
        return "must have a kind that is an identifier"
    reports = cls.__dict__.get("REPORTS")
    if not (isinstance(reports, str) and reports):
        return ("must declare REPORTS, what its outputs report, for the reference of the "
                f"format; it has {'none' if reports is None else repr(reports)}")
    keys = cls.__dict__.get("KEYS")
    if keys is None:
        # a new kind with its parent's keys is explicit, as a group type's fields are
        return ("must declare KEYS, a dict of key -> what it is; it has none of its own "
                "(KEYS = Parent.KEYS keeps its parent's)")
    if not isinstance(keys, dict) or not all(
            isinstance(k, str) and isinstance(v, str) and v for k, v in keys.items()):
        return f"must declare KEYS, a dict of key -> what it is; it has {keys!r}"
    if "name" not in keys:
        return "KEYS has no 'name': every output's table names it"
    if "kind" in keys:
        return "KEYS has 'kind', which names the output's kind in a description file"
    for method in ("check", "from_spec"):
        if getattr(getattr(cls, method), "__func__", None) is getattr(Output, method).__func__:
            return (f"implements no {method}: the description's "
                    f"{'checker' if method == 'check' else 'builder'} asks it")
    return ""


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
class Force(Output):
    """Output: component ``axis`` ('x' or 'y') of the force of body ``by`` on body ``on``.

    Its kind ``force`` gives the components a table asks for, and their magnitude
    (:class:`Magnitude`) if it asks for it.

    Examples
    --------
    >>> spec = {"kind": "force", "name": "F12", "by": "1", "on": "2", "magnitude": True}
    >>> [o.name for o in Force.from_spec(spec, None)]
    ['F12x', 'F12y', 'F12_abs']
    """

    name: str
    by: str
    on: str
    axis: str
    note: str = ""  # the description, if not the default one
    unit = "N"
    kind = "force"
    REPORTS = "components of the force one body exerts on another through their joint, N"
    KEYS = {
        "name": "stem of the outputs' names: NAMEx and NAMEy (required)",
        "by": "the body that exerts the force, a moving link or the frame (required)",
        "on": "the body it acts on, joined to by (required)",
        "components": "the components reported, a list of \"x\" and/or \"y\" (default "
                      "both)",
        "x": "name of the x component (default NAMEx)",
        "y": "name of the y component (default NAMEy)",
        "magnitude": "also report the force's magnitude (a prismatic pair's: its normal "
                     "force): true for NAME_abs, or its name",
        "description": "what the force is; the outputs' descriptions add the component",
    }

    @classmethod
    def check(cls, checker, where: str, name: str, spec: dict) -> list[str]:
        for key in ("by", "on"):
            if spec.get(key) not in checker.links and spec.get(key) != checker.d.frame:
                checker.found.append(f"{where} {key}: {spec.get(key)!r} is not a body")
        comps = spec.get("components", ["x", "y"])
        if not set(comps) <= {"x", "y"} or not comps:
            checker.found.append(f"{where} components: must be a list of 'x' and/or 'y'")
        names = [spec.get(c, name + c) for c in comps]
        if spec.get("magnitude"):
            m = spec["magnitude"]
            names.append(m if isinstance(m, str) else f"{name}_abs")
        return names

    @classmethod
    def from_spec(cls, spec: dict, d) -> list[Output]:
        name, text = spec["name"], spec.get("description", "")
        made: list[Output] = [
            cls(spec.get(axis, name + axis), spec["by"], spec["on"], axis,
                f"{text}, {axis} component" if text else "")
            for axis in spec.get("components", ["x", "y"])]
        if spec.get("magnitude"):
            m = spec["magnitude"]
            made.append(Magnitude(m if isinstance(m, str) else f"{name}_abs", spec["by"],
                                  spec["on"], f"{text}, magnitude" if text else ""))
        return made

    @property
    def description(self) -> str:
        return self.note or f"force of link {self.by} on link {self.on}, {self.axis} component"

    def bind(self, mech) -> Callable:
        j, sign = joint_between(mech, self.by, self.on, self.name)
        return j.force_output("xy".index(self.axis), sign, has_friction(mech, j.name))


@dataclass(frozen=True)
class Magnitude(Output):
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
class Normal(Output):
    """Output: normal force of the prismatic pair ``joint`` (of body a on body b, along
    the pair's normal)."""

    name: str
    joint: str
    note: str = ""
    unit = "N"
    component = 0  # of the pair's reaction (N, M)
    what = "normal force of the prismatic pair '{joint}' along its normal"
    kind = "normal"
    REPORTS = "normal force of a prismatic pair along its normal, N"
    KEYS = {
        "name": "name of the output (required)",
        "joint": "the prismatic pair, by its name (required)",
        "description": "what it is",
    }

    @classmethod
    def check(cls, checker, where: str, name: str, spec: dict) -> list[str]:
        if spec.get("joint") not in checker.joints:
            checker.found.append(f"{where} joint: {spec.get('joint')!r} is not a pair")
        return [name]

    @classmethod
    def from_spec(cls, spec: dict, d) -> list[Output]:
        return [cls(spec["name"], spec["joint"], spec.get("description", ""))]

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
    kind = "couple"
    REPORTS = "couple transmitted by a prismatic pair, counter-clockwise positive, N.m"
    KEYS = Normal.KEYS


@dataclass(frozen=True)
class EffortOutput(Output):
    """Output: the balancing effort if it is the one named ``name``, else zero.

    Its kind ``effort`` reports an ``[effort]`` by its name; every effort that no table
    names is reported too (:meth:`from_spec` of ``{"name": NAME}``).

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> d = presets.preset("four_bar")
    >>> EffortOutput.from_spec({"name": "Mb"}, d)[0].unit
    'N.m'
    """

    name: str
    unit: str = "N.m"
    description: str = "balancing moment on the driver link, counter-clockwise positive"
    kind = "effort"
    REPORTS = ("the balancing effort of an [effort] (zero when a choice makes another the "
               "effort)")
    KEYS = {
        "name": "the name of an [effort] (required)",
        "unit": "its unit (default: N.m for a moment, N for a force)",
        "description": "what it is",
    }

    @classmethod
    def check(cls, checker, where: str, name: str, spec: dict) -> list[str]:
        if name not in checker.effort_names():
            checker.found.append(f"{where} name: {name!r} is not the name of an [effort]")
        elif "unit" in spec and not checker.unit(f"{where} unit", spec["unit"]):
            kinds = {"N" if "direction" in e else "N.m" for e in checker.d.efforts.values()
                     if isinstance(e, dict) and e.get("name") == name}
            if spec["unit"] not in kinds:
                what = "a force" if kinds == {"N"} else "a moment"
                checker.found.append(f"{where} unit: {spec['unit']!r}: {name} is {what}, in "
                                     f"{' or '.join(sorted(kinds))}")
        return [name]

    @classmethod
    def from_spec(cls, spec: dict, d) -> list[Output]:
        name = spec["name"]
        moment = any(s.get("name") == name and "direction" not in s
                     for s in d.efforts.values()) or (  # a driver's moment, Mb_<j>
            not d.efforts and name.split("_")[0] == EFFORTS["angle"])
        unit = spec.get("unit") or ("N.m" if moment else "N")
        if not d.efforts:  # a driver's: the mechanism words it from the driver
            return [cls(name, unit, spec.get("description", ""))]
        return [cls(name, unit, spec.get("description", "") or (
            "balancing moment on the driver link, counter-clockwise positive"
            if unit == "N.m" else "balancing force"))]

    def bind(self, mech) -> Callable:
        return effort_value(mech, self.name)


def effort_value(mech, name: str) -> Callable:
    """``fn(R, E, st)``: the effort ``name`` of ``mech`` (one of its drivers' in a
    linkage driven by time, where ``E`` is the tuple of them), zero for the name of an
    effort a choice of its description did not make the effort."""
    if mech.rates:
        for k, e in enumerate(mech.efforts):
            if e.name == name:
                return lambda R, E, st: E[k]
    elif mech.effort.name == name:
        return lambda R, E, st: E
    return lambda R, E, st: 0.0


@dataclass(frozen=True)
class Derived(Output):
    """Output: an expression of the joint reactions (``N_<joint>``, ``M_<joint>``,
    ``Fx_<joint>``, ``Fy_<joint>``), the balancing effort (by its name) and the
    parameters, e.g. the scotch yoke's two guide bearings."""

    name: str
    expression: str
    unit: str = "N"
    description: str = ""
    kind = "expression"
    REPORTS = "an expression of the joint reactions, the effort and the parameters"
    KEYS = {
        "name": "name of the output (required)",
        "expression": "an expression of N_J, M_J (the normal force and couple of a "
                      "prismatic pair J), Fx_J, Fy_J (the force of a revolute pair J), "
                      "the efforts' names and the parameters (required)",
        "unit": "its unit (default N)",
        "description": "what it is",
    }

    @classmethod
    def check(cls, checker, where: str, name: str, spec: dict) -> list[str]:
        joint_vars = {f"{v}_{j}" for j in checker.joints for v in ("N", "M", "Fx", "Fy")}
        checker.expr(f"{where} expression", spec.get("expression", ""),
                     set(checker.d.parameters) | joint_vars | checker.effort_names())
        if "unit" in spec:
            checker.unit(f"{where} unit", spec["unit"])
        return [name]

    @classmethod
    def from_spec(cls, spec: dict, d) -> list[Output]:
        return [cls(spec["name"], spec["expression"], spec.get("unit", "N"),
                    spec.get("description", ""))]

    def bind(self, mech) -> Callable:
        by_name = {f"{k}_{j.name}": (j.name, i) for j in mech.joints
                   for i, k in enumerate(j.components)}

        def resolve(name):
            if name in by_name:
                joint, i = by_name[name]
                return lambda R, E, st: R[joint][i]
            if name in {e.name for e in mech.efforts}:
                return effort_value(mech, name)
            if name in mech.parameters:  # a float, or a traced parameter
                return numerics.real(mech.parameters[name])
            return lambda R, E, st: 0.0  # another effort's name: not this linkage's effort

        return Expression(self.expression).bind(resolve)


#: the names of the shaking outputs every linkage has
SHAKING = ("shake_x", "shake_y", "shake_M")


def shaking_pivot(mech) -> str:
    """The point the shaking moment is taken about: the crank's pivot, or, for a
    linkage driven by time, its first frame point."""
    return next(iter(mech.frame_points)) if mech.rates else mech.crank.pivot


@dataclass(frozen=True)
class Shaking(Output):
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
        pivot, effort = shaking_pivot(mech), mech.effort
        rubbing = {j.name for j, _ in joints if has_friction(mech, j.name)}
        # a linkage driven by time: the reactions of its drivers that act on the frame
        grounded = [(k, e) for k, e in enumerate(mech.efforts) if e.base == mech.frame] \
            if mech.rates else ()

        def forces(R, E, st):
            """(fx, fy, point or None, couple) of each action on the frame."""
            for j, sign in joints:
                yield j.action(R, st, sign, j.name in rubbing)
            if mech.rates:
                for k, e in grounded:
                    if e.direction is None:
                        yield 0.0, 0.0, None, -E[k]
                    else:
                        dx, dy = st.u[e.direction] if isinstance(e.direction, str) \
                            else e.direction
                        yield -E[k] * dx, -E[k] * dy, e.point, 0.0
            elif effort.direction is None:  # the driver's reaction: a couple
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

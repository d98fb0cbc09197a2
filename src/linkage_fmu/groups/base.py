"""What every group type is: the state it writes into, its joints, and the abstract base.

A linkage is a driver (the crank) followed by Assur groups and points fixed on links,
each placing new points, or orienting new links, from points already placed. Every group
works at three orders:

* ``position``: joint positions and link directions (unit vectors), with an explicit
  assembly ``branch`` where there is a choice; a state that cannot be assembled is an
  error (scalars) or NaN with ``invalid = True`` (arrays), never clamped;
* ``first``: first-order coefficients ``dX/dtheta`` of every point and ``dphi/dtheta``
  of every link (velocities at unit crank speed);
* ``second``: second-order coefficients ``d2X/dtheta2`` and ``d2phi/dtheta2``;

and knows its own statics (the reactions of its joints from the loads on its links, in
closed form), the equilibrium rows of its joints, and its transmission angle.

Velocity and acceleration follow as ``v = X'*omega`` and ``a = X''*omega**2 + X'*alpha``,
so a static scene needs none of the derivative work, and the equations of motion are
linear in ``omega**2``, ``alpha`` and the loads. Every formula is written once and runs
on floats (:data:`~linkage_fmu.numerics.SCALAR`), arrays (:data:`~linkage_fmu.numerics.ARRAY`)
or mpmath numbers (:data:`linkage_fmu.precise.MP`).
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from collections.abc import Callable, Collection, Iterable
from dataclasses import dataclass
from typing import ClassVar, NamedTuple

import numpy as np

from .. import numerics
from ..drivers import Driver
from ..errors import InputError, InputTypeError
from ..kernels.trace import Reason
from ..numerics import Number

Vec = tuple  # (x, y) of floats or arrays


class KinematicState:
    """Positions and derivative coefficients of every point and link at one or many states
    (:meth:`linkage_fmu.Mechanism.kinematics` names the points and shows them).

    Attributes
    ----------
    theta : float or ndarray
        Crank angle(s) [rad].
    xp : namespace
        :data:`~linkage_fmu.numerics.SCALAR`, :data:`~linkage_fmu.numerics.ARRAY` or
        :data:`linkage_fmu.precise.MP`.
    p, d1, d2 : dict
        Point name -> ``(x, y)`` [m], ``(x', y')`` [m/rad], ``(x'', y'')`` [m/rad2]: the
        position and its first and second derivatives with respect to ``theta``.
    u, w1, w2 : dict
        Link name -> unit direction ``(cos phi, sin phi)``, ``phi'``, ``phi''`` (the
        derivatives of the link's angle ``phi`` with respect to ``theta``).
    invalid : ndarray of bool or None
        For arrays, the states that could not be assembled.
    locked : ndarray of bool or None
        For arrays, the states that friction locks (:mod:`~linkage_fmu.friction`).
    on_invalid : callable
        ``on_invalid(condition, what)`` raises for a scalar state (set by the mechanism):
        ``condition`` says what failed with its numbers, ``what`` without them.
    rates : tuple or None
        None for a linkage driven by one crank on the frame, whose coefficients are
        derivatives by its angle. For any other (several drivers, a motor between two
        links, a cylinder): each driver's ``(speed, acceleration)``, in the order of
        ``mech.drivers``; ``theta`` is then the tuple of the drivers' coordinates, and
        ``d1``, ``d2``, ``w1``, ``w2`` are the velocities and accelerations themselves
        (the coefficients at unit speed and zero acceleration of one coordinate, time).
    """

    __slots__ = ("theta", "xp", "p", "d1", "d2", "u", "w1", "w2", "invalid", "locked",
                 "on_invalid", "rates")

    def __init__(self, theta: Number, xp, on_invalid: Callable[[str], None] | None = None,
                 rates: tuple | None = None):
        self.theta = theta
        self.rates = rates
        self.xp = xp
        self.p: dict = {}
        self.d1: dict = {}
        self.d2: dict = {}
        self.u: dict = {}
        self.w1: dict = {}
        self.w2: dict = {}
        self.invalid = None
        self.locked = None
        self.on_invalid = on_invalid or _raise_value_error

    def velocity(self, point: str, omega: Number) -> Vec:
        """Velocity of ``point`` at crank speed ``omega``."""
        x1, y1 = self.d1[point]
        return x1 * omega, y1 * omega

    def acceleration(self, point: str, omega: Number, alpha: Number) -> Vec:
        """Acceleration of ``point`` at crank speed ``omega`` and acceleration ``alpha``."""
        x1, y1 = self.d1[point]
        x2, y2 = self.d2[point]
        w2 = omega * omega
        return x2 * w2 + x1 * alpha, y2 * w2 + y1 * alpha

    def root(self, value: Number, condition: Callable[[], str], what: str = "") -> Number:
        """``sqrt(value)``; a negative value is an assembly failure (raise, or NaN + mask).
        ``condition()`` says what failed with its numbers, ``what`` without them."""
        if _in_loop(value):
            _check_in_loop(value, "lt", False, Reason("assembly", what))
            return self.xp.sqrt(self.xp.maximum(value, 0.0))
        if self.xp.scalar:
            fails = value < 0.0
            numerics.label(value, Reason("assembly", what))
            if fails:
                self.on_invalid(condition(), what)
            return self.xp.sqrt(value)
        bad = value < 0.0
        if bad.any():
            self.mark(bad)
            value = np.where(bad, np.nan, value)
        return np.sqrt(value)

    def positive(self, value: Number, condition: Callable[[], str], what: str = "") -> Number:
        """``value``, which must be > 0 to assemble (raise, or NaN + mask)."""
        if _in_loop(value):
            _check_in_loop(value, "gt", True, Reason("assembly", what))
            return value
        if self.xp.scalar:
            fails = not value > 0.0
            numerics.label(value, Reason("assembly", what))
            if fails:
                self.on_invalid(condition(), what)
            return value
        bad = ~(value > 0.0)
        if bad.any():
            self.mark(bad)
            value = np.where(bad, np.nan, value)
        return value

    def mark(self, bad: np.ndarray) -> None:
        """Add the states ``bad`` (arrays) to those that cannot be assembled."""
        self.invalid = bad if self.invalid is None else (self.invalid | bad)


def _in_loop(value) -> bool:
    """Whether ``value`` is a traced number computed inside a loop's body (where a
    check is a failure flag the loop carries, not a branch)."""
    tape = getattr(value, "tape", None)
    return tape is not None and tape.scopes[value.index] is not None


def _check_in_loop(value, op: str, outcome: bool, reason: Reason) -> None:
    """Fail the state, with ``reason``, where ``value op 0`` is not ``outcome`` in any
    run of the loop."""
    value.tape.check(value.tape.compare(op, value, 0.0), outcome, reason)


#: Placeholder body names in joint declarations, resolved by the mechanism.
FRAME = "<frame>"
OWNER = "<owner of the point>"


def left_normal(t: Vec) -> Vec:
    """Left normal of the unit vector ``t``."""
    return -t[1], t[0]


def unit_vector(angle: float) -> Vec:
    return numerics.cos(angle), numerics.sin(angle)


def _raise_value_error(condition: str, what: str = "") -> None:
    raise InputError(condition)


def fmt(x: Number) -> str:
    """First value of ``x`` for a message."""
    x = np.asarray(x)
    return f"{float(x):.6g}" if x.ndim == 0 else f"{float(x.flat[0]):.6g}"


def mode(branch, group: str):
    """A group's assembly mode, +1 or -1: a number, or where the parameters draw it
    (``sign`` of the drawn pose), traced, checked by the parameter step. 0 is a pose
    drawn at a toggle of ``group``, where the mode is undefined (ValueError).

    Examples
    --------
    >>> mode(-1.0, "the dyad B-C-D")
    -1
    >>> mode(0.0, "the dyad B-C-D")
    Traceback (most recent call last):
    ...
    linkage_fmu.errors.InputError:
    the dyad B-C-D is drawn at a toggle (its points in line): its assembly mode is
    undefined
    """
    what = f"{group} is drawn at a toggle (its points in line): its assembly mode is undefined"
    if not hasattr(branch, "traced"):
        if branch == 0.0:
            raise InputError(what)
        return int(branch)
    abs(branch) > 0.0  # noqa: B015 -- an order comparison of parameters: recorded
    numerics.label(branch, Reason("parameter", what))
    return branch


def angle_and_kappa(xp, sin_gamma, cos_gamma, what: str = ""):
    """``(gamma, kappa)`` from the sine and cosine of a transmission angle: ``gamma`` in
    [0, pi] and ``kappa = (1 + |cos gamma|) / |sin gamma|``, the 2-norm condition number of a
    dyad's normalised 2x2 core system (infinite at a toggle, which ``what`` names)."""
    a = xp.abs(sin_gamma)
    gamma = xp.atan2(a, cos_gamma)
    if xp.scalar:
        apart = a > 0.0
        numerics.label(a, Reason("singular", what))
        kappa = (1.0 + abs(cos_gamma)) / a if apart else math.inf
    else:
        with np.errstate(divide="ignore", invalid="ignore"):
            kappa = (1.0 + np.abs(cos_gamma)) / a
    return gamma, kappa


#: The roles of a group's fields in description files, and the unit each implies:
#: ``new link`` a moving link the group adds; ``link`` one an earlier group added;
#: ``point`` a point placed before the group; ``new point`` a point the group places;
#: ``new joint`` a pair the group makes that no point names (a prismatic pair);
#: ``length`` a fixed length (> 0); ``angle`` counter-clockwise; ``coordinate`` a signed
#: distance; ``vector`` ``[x, y]`` in the frame; ``branch`` +1 or -1; ``link joints`` the
#: moving links a group adds, each with its joints (placed points and points the group
#: places); ``pose`` where each of those joints is drawn, ``[x, y]`` in the frame.
ROLES: dict[str, str] = {
    "new link": "", "link": "", "point": "", "new point": "", "new joint": "",
    "length": "m", "angle": "rad", "coordinate": "m", "vector": "m", "branch": "",
    "link joints": "", "pose": "m",
}
NAME_ROLES = ("new link", "link", "point", "new point", "new joint")
#: what the value of a field of each role is, in words (a reference of the format lists it)
ROLE_MEANINGS: dict[str, str] = {
    "new link": "the name of a moving link the group adds",
    "link": "the name of a moving link an earlier group added",
    "point": "the name of a point placed before the group",
    "new point": "the name of a point the group places",
    "new joint": "the name of a pair the group makes that no point names (a prismatic pair)",
    "length": "a fixed length, > 0",
    "angle": "an angle, counter-clockwise",
    "coordinate": "a signed distance",
    "vector": "[x, y] in the frame",
    "branch": "+1 or -1, the assembly mode",
    "link joints": "{ LINK = [POINT, POINT, ...] }: each moving link the group adds and its "
                   "joints (two or more), points placed before the group or that it places; "
                   "the first two give the link's direction",
    "pose": "{ POINT = [x, y] }: where each joint the group's links list is drawn",
}


class LinkJoints(NamedTuple):
    """The value of a ``link joints`` field as a group is built from it: each new link ->
    its joints (a tuple of point names), and which of those points are ``placed``
    before the group (the others are its new points)."""

    links: dict
    placed: frozenset


@dataclass(frozen=True)
class Field:
    """One field of a group type in description files: its role, and what it means.

    Parameters
    ----------
    role : str
        One of :data:`ROLES`: what the checker requires of the value (a name that is
        placed, new, ...; an expression; ``[x, y]``) and the unit of a number.
    description : str
        What the field is, in one phrase, for a reference of the format.

    Raises
    ------
    ValueError
        An unknown role.

    Examples
    --------
    >>> f = Field("length", "length of link1, from end1 to middle")
    >>> f.unit, f.is_name
    ('m', False)
    >>> Field("new point", "joint of link1 and link2").unit
    ''
    >>> Field("mass", "mass of the link")
    Traceback (most recent call last):
    ...
    linkage_fmu.errors.InputError:
    unknown field role 'mass'; the roles are new link, link, point, new point, new
    joint, length, angle, coordinate, vector, branch, link joints, pose
    """

    role: str
    description: str

    def __post_init__(self) -> None:
        if self.role not in ROLES:
            raise InputError(f"unknown field role {self.role!r}; the roles are "
                             f"{', '.join(ROLES)}")

    @property
    def unit(self) -> str:
        """Unit of the value: ``'m'``, ``'rad'``, or ``''`` for a name or a branch."""
        return ROLES[self.role]

    @property
    def is_name(self) -> bool:
        """Whether the value is a name (of a link, point or joint), not a number."""
        return self.role in NAME_ROLES


@dataclass(frozen=True)
class Drawing:
    """How a group type is drawn in a linkage written as joints and links: what the
    decomposition of such a linkage looks for, and what the reference of the format
    says of it. A type recognises its drawing itself (:meth:`Group.recognise`).

    Parameters
    ----------
    rank : int
        Types of one size are tried in the order of their rank (then of their kind).
    size : int or None
        How many links the group has: the decomposition offers the type every set of
        that many links not yet placed, in the order of [[links]], smallest sizes first;
        None for a group of any size, offered every link not yet placed once no type of
        a fixed size is found (a closure).
    links, pairs : str
        Its links and their pairs, in words, for the reference's table of the groups of a
        fixed size: what joins them to one another and to the placed bodies.

    Raises
    ------
    ValueError
        A size below 2, or a fixed size without its words.

    Examples
    --------
    >>> Drawing(1, 2, "two links pinned together", "each pinned to a placed joint").size
    2
    >>> Drawing(1, 2)
    Traceback (most recent call last):
    ...
    linkage_fmu.errors.InputError:
    a group of 2 links says what its links and their pairs are (links, pairs), for
    the reference of the format
    """

    rank: int
    size: int | None = 2
    links: str = ""
    pairs: str = ""

    def __post_init__(self) -> None:
        if self.size is not None and not (isinstance(self.size, int) and self.size >= 2):
            raise InputError(f"size = {self.size!r}: a group has 2 links or more (None: any "
                             "number)")
        if self.size is not None and not (self.links and self.pairs):
            raise InputError(f"a group of {self.size} links says what its links and their "
                             "pairs are (links, pairs), for the reference of the format")


def names_in(spec: dict, keys: Iterable[str]) -> tuple[str, ...]:
    """The values of ``keys`` in ``spec`` that are names (non-empty strings), in order.

    A missing or malformed field is left out: the description's checker reports it.

    Examples
    --------
    >>> names_in({"pivot": "A", "tip": "", "end": 3}, ("pivot", "tip", "end", "link"))
    ('A',)
    """
    return tuple(spec[k] for k in keys if isinstance(spec.get(k), str) and spec[k])


class Group(ABC):
    """A driver, an Assur group or a point fixed on a link.

    Subclasses state what they need and give, and implement every abstract method; a
    class that misses one cannot be instantiated (``TypeError`` naming it). Each
    concrete class with a ``kind`` is the group type of that name in description files,
    and must declare its own ``FIELDS`` (``TypeError`` naming it when the class is
    created); ``OPTIONAL``, ``DRIVER`` and ``pairs`` have defaults. A type that a
    linkage written as joints and links may show declares its own ``DRAWING`` and
    implements ``recognise``; by default a type is not recognised from joints and links.

    Examples
    --------
    The contract with description files is on the class:

    >>> from linkage_fmu.groups import RRR, Crank
    >>> RRR.FIELDS["length1"]
    Field(role='length', description='length of link1, from end1 to middle')
    >>> Crank.DRIVER, RRR.DRIVER, RRR.OPTIONAL
    (True, False, ())

    A type that does not declare its fields is refused when it is defined:

    >>> class NoFields(Group):
    ...     kind = "no_fields_example"
    Traceback (most recent call last):
    ...
    linkage_fmu.errors.InputTypeError:
    group type NoFields (kind 'no_fields_example') must declare FIELDS, a dict of field
    name -> Field; it has none

    Attributes
    ----------
    kind : str
        Name of the type in description files (``'RRR'``, ...).
    FIELDS : dict of str to Field
        The fields of the type's table in description files, in the order messages
        list them (a class attribute every type declares).
    OPTIONAL : tuple of str
        The fields that may be left out.
    DRIVER : bool
        True for a driver: a group whose coordinate is an input (a crank's or a motor's
        angle, a cylinder's travel). A linkage has one driver per degree of freedom,
        before the groups that use what they place; its coordinate, speed and
        acceleration are the linkage's inputs (its :meth:`driver` names them), and every
        other group follows from the points placed before it.
    DRAWING : Drawing or None
        How the type is drawn as joints and links, declared by the type itself (a new
        kind does not take its parent's); None for a type the decomposition of such a
        linkage does not recognise (the crank, which ``[crank]`` names, and a point on
        a link, which it adds itself).
    needs : tuple of str
        Points that must be placed before this group.
    places : tuple of str
        Points this group places.
    links : tuple of str
        Moving links this group adds (one body each).
    joints : tuple of :class:`~linkage_fmu.pairs.Pair`
        The pairs this group closes, with :data:`FRAME`/:data:`OWNER` placeholders.
    owners : dict
        Point -> link for the points placed that belong to one link only.
    key : str or None
        Name of the group in diagnostics (``gamma_<key>``), None for a group without a
        transmission angle (the crank, a point on a link).
    """

    kind: ClassVar[str] = ""
    registry: ClassVar[dict] = {}
    FIELDS: ClassVar[dict[str, Field]]  # no default: every type declares its own
    OPTIONAL: ClassVar[tuple[str, ...]] = ()
    DRIVER: ClassVar[bool] = False
    DRAWING: ClassVar[Drawing | None] = None

    needs: tuple = ()
    places: tuple = ()
    links: tuple = ()
    joints: tuple = ()
    lengths: tuple = ()  # fixed lengths, for the linkage's length scale
    #: False for a group whose size no fixed length gives (its position varies with the
    #: state): the linkage's length scale then includes the frame's size
    fixed_size: bool = True
    owners: dict = {}
    key: str | None = None
    #: a driver whose speed and acceleration its kinematics take as they are, even
    #: alone (a motor, a cylinder): its linkage's state is then one of time
    #: (:attr:`KinematicState.rates`)
    by_time: bool = False
    #: a driver's place among its linkage's drivers (set when it is attached)
    index: int = 0

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        if cls.__dict__.get("kind"):  # a subclass that inherits its kind is no new type
            problem = _contract_problem(cls)
            if problem:
                raise InputTypeError(f"group type {cls.__qualname__} (kind {cls.kind!r}) {problem}")
            if cls.kind in Group.registry:
                raise InputTypeError(f"group kind {cls.kind!r} is defined twice: "
                                     f"{Group.registry[cls.kind].__qualname__} and "
                                     f"{cls.__qualname__}")
            Group.registry[cls.kind] = cls

    @classmethod
    def pairs(cls, spec: dict, placed: Collection[str] | None = None) -> tuple[str, ...]:
        """Names of the kinematic pairs (joints) the group of fields ``spec`` makes, with
        ``placed`` the points placed before it (None: not known; a type whose pairs
        depend on it, such as the closure, says how it takes that).

        By default, one revolute pair at each point the group uses or places (named by
        the point), then one pair per ``new joint`` field; a type whose pairs differ
        overrides this. The names are those its ``joints`` will have once built; only
        fields given as names count.

        Examples
        --------
        >>> from linkage_fmu.groups import RRR
        >>> RRR.pairs({"link1": "2", "link2": "3", "end1": "B", "middle": "C", "end2": "D"})
        ('B', 'C', 'D')
        """
        points = [k for k, f in cls.FIELDS.items() if f.role in ("point", "new point")]
        named = [k for k, f in cls.FIELDS.items() if f.role == "new joint"]
        return names_in(spec, points + named)

    @classmethod
    def problems(cls, spec: dict, placed: Collection[str]) -> list[str]:
        """What is wrong with the fields ``spec`` as a whole, with ``placed`` the points
        placed before the group: one message per problem, each starting with the field's
        key (the checker names the file and table). Each field alone is checked by its
        role; by default nothing more.

        Examples
        --------
        >>> from linkage_fmu.groups import RRR
        >>> RRR.problems({"link1": "2"}, {"A"})
        []
        """
        return []

    @classmethod
    def recognise(cls, drawn, links: tuple[str, ...]) -> bool:
        """Whether the links ``links`` not yet placed (as many as the type's ``DRAWING``
        says, in the order of [[links]]) form this group in the joints-and-links linkage
        under decomposition ``drawn``
        (:class:`~linkage_fmu.descriptions.assur.Decomposer`), with the links and joints
        placed so far; if they do, the group's table, its pairs and its links' points
        are added to ``drawn`` (its methods say how), and True is returned. A drawing
        they form that cannot be solved (a toggle) raises the decomposition's error.

        By default False: the type is not recognised from joints and links.

        Examples
        --------
        >>> from linkage_fmu.groups import Crank
        >>> Crank.DRAWING, Crank.recognise(None, ("1",))
        (None, False)
        """
        return False

    def driver(self, effort: str, alone: bool = True) -> Driver:
        """The :class:`~linkage_fmu.drivers.Driver` of a driving group: the pair it
        drives, its inputs (named as :meth:`Driver.named
        <linkage_fmu.drivers.Driver.named>` says for a linkage's only driver, or one of
        several) and the name of its ``effort`` output. A type with ``DRIVER = True``
        implements it (checked when the class is defined); for others it is an error.

        Examples
        --------
        >>> from linkage_fmu.groups import Crank
        >>> Crank("1", "A", "B", 0.1).driver("Mb").inputs
        ('theta', 'omega', 'alpha')
        """
        raise InputTypeError(f"{type(self).__name__} is no driver (DRIVER = False)")

    @classmethod
    def drives(cls, spec: dict) -> tuple | None:
        """What a driving group of the fields ``spec`` drives, as a description's
        checker needs it before anything is built: ``(pair, kind, by_time)``, None where
        the fields do not name it (the checker reports them). For a type that is no
        driver it is an error.

        Examples
        --------
        >>> from linkage_fmu.groups import Crank, Cylinder
        >>> Crank.drives({"pivot": "A"}), Cylinder.drives({"pair": "P"})
        (('A', 'angle', False), ('P', 'travel', True))
        """
        raise InputTypeError(f"{cls.__name__} is no driver (DRIVER = False)")

    def acts(self) -> tuple:
        """Where a driving group's effort acts, as
        :class:`~linkage_fmu.bodies.Effort` takes it: ``(body, point, direction,
        base)``, a moment on ``body`` (``point`` '' and ``direction`` None) or a force at
        ``point`` along the link ``direction``'s direction, its reaction on ``base``.
        A type with ``DRIVER = True`` implements it (checked when the class is defined).

        Examples
        --------
        >>> from linkage_fmu.groups import Crank
        >>> Crank("1", "A", "B", 0.1).acts()
        ('1', '', None, '<frame>')
        """
        raise InputTypeError(f"{type(self).__name__} is no driver (DRIVER = False)")

    def moment_point(self, link: str) -> str:
        """The point about which the equilibrium equations of its ``link`` take moments,
        as the source documents choose it: the pair by which the link hangs on what is
        placed before the group (a crank's pivot, a dyad link's outer joint), else the
        link's first pair in the group (a slider's pin).

        Examples
        --------
        >>> from linkage_fmu.groups import RRR
        >>> g = RRR("2", "3", "B", "C", "D", 0.3, 0.2, 1)
        >>> g.moment_point("2"), g.moment_point("3")
        ('B', 'D')
        """
        points = [j.point for j in self.joints if link in (j.a, j.b)]
        return next((p for p in points if p in self.needs), points[0])

    def attach(self, before: tuple, frame_points: dict) -> None:  # noqa: B027 (optional hook)
        """Called by the mechanism with the groups ``before`` this one (in order) and
        its frame points (name -> ``(x, y)``): a group that needs to place the points
        it uses at other states than the one it is solved at keeps them. Nothing by
        default. Raises ValueError for a group that does not fit what is before it."""

    @abstractmethod
    def position(self, st: KinematicState) -> None:
        """Place ``places`` and orient ``links`` in ``st``."""

    @abstractmethod
    def first(self, st: KinematicState) -> None:
        """First-order coefficients of ``places`` and ``links``."""

    @abstractmethod
    def second(self, st: KinematicState) -> None:
        """Second-order coefficients of ``places`` and ``links``."""

    @abstractmethod
    def statics(self, mech, st: KinematicState, W: dict, R: dict):
        """Reactions of this group's joints, in closed form, into ``R`` (joint name ->
        ``(Fx, Fy)`` or ``(N, M)``), from the wrenches ``W`` of its links (body name ->
        ``[Fx, Fy, M]`` about the centre of mass). Adds the reactions on the links it is
        attached to into their wrenches (groups are solved from the last back to the
        crank). Returns a driver's effort (the moment or force it must apply), else
        None."""

    @abstractmethod
    def transmission(self, st: KinematicState, scale: float):
        """``(gamma, kappa)``: the transmission angle in [0, pi] and the condition number of
        the group's position and equilibrium, for a linkage of length scale ``scale``;
        None for a group with neither."""

    @classmethod
    @abstractmethod
    def from_spec(cls, spec: dict, value: Callable):
        """Build from the fields ``spec`` of a description file's group table, with
        ``value(field)`` evaluating a field's expression over the parameters."""


def _contract_problem(cls: type) -> str:
    """What a group type with a ``kind`` misses of the description-file contract, or ''."""
    fields = cls.__dict__.get("FIELDS")
    if fields is None:
        # a new kind with its parent's fields is explicit, so that a changed from_spec
        # cannot silently keep fields it no longer reads
        parent = next((c for c in cls.__mro__[1:] if "FIELDS" in c.__dict__), None)
        return ("must declare FIELDS, a dict of field name -> Field; it has none" + (
            "" if parent is None else
            f" of its own (FIELDS = {parent.__qualname__}.FIELDS keeps its parent's)"))
    if not isinstance(fields, dict) or not fields:
        return f"must declare FIELDS, a dict of field name -> Field; it has {fields!r}"
    for key, f in fields.items():
        if not isinstance(key, str) or not isinstance(f, Field):
            return (f"FIELDS[{key!r}] = {f!r}: FIELDS must map field names to Field "
                    "(role, description)")
    if "type" in fields:  # a group's table names its type with this key
        return "FIELDS has 'type', which names the group's type in a description file"
    optional = cls.OPTIONAL
    if not isinstance(optional, tuple) or not set(optional) <= set(fields):
        return f"OPTIONAL = {optional!r} must be a tuple of names in its FIELDS"
    if not isinstance(cls.DRIVER, bool):
        return f"DRIVER = {cls.DRIVER!r} must be True or False"
    if cls.DRIVER and cls.driver is Group.driver:
        return ("is a DRIVER but does not implement driver(effort, alone): the mechanism "
                "asks it which pair it drives and how its inputs are named")
    if cls.DRIVER and cls.drives.__func__ is Group.drives.__func__:
        return ("is a DRIVER but does not implement drives(spec): a description's checker "
                "asks it which pair it drives")
    if cls.DRIVER and cls.acts is Group.acts:
        return ("is a DRIVER but does not implement acts(): the mechanism asks it where "
                "its effort acts")
    drawing = cls.__dict__.get("DRAWING")
    if drawing is not None and not isinstance(drawing, Drawing):
        return f"DRAWING = {drawing!r} must be a Drawing or None"
    if drawing is not None and cls.recognise.__func__ is Group.recognise.__func__:
        return ("declares a DRAWING but no recognise: the decomposition asks recognise "
                "whether links form the group")
    if drawing is None and "recognise" in cls.__dict__:
        return ("implements recognise but declares no DRAWING of its own: the "
                "decomposition asks only the types that declare one")
    return ""


# -- statics helpers shared by the group types ------------------------------------------
def push(mech, st: KinematicState, W: dict, body: str, point: str, fx, fy) -> None:
    """Add the force ``(fx, fy)`` acting at ``point`` to ``body``'s wrench (not the frame)."""
    if body == mech.frame:
        return
    w = W[body]
    (px, py), (sx, sy) = st.p[point], st.p[mech.cg[body]]
    w[0] = w[0] + fx
    w[1] = w[1] + fy
    w[2] = w[2] + (px - sx) * fy - (py - sy) * fx


def moment_about(mech, st: KinematicState, W: dict, body: str, point: str):
    """Force and moment of ``body``'s wrench, the moment taken about ``point``."""
    fx, fy, m = W[body]
    (px, py), (sx, sy) = st.p[point], st.p[mech.cg[body]]
    return fx, fy, m + (sx - px) * fy - (sy - py) * fx

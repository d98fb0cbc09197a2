"""An Assur group of any class made of revolute pairs, solved as one: its closure.

What no dyad resolves (a ternary link held by three binary rods, a class III group, or a
higher one) is solved as a whole: its links' joints are where they are drawn in one pose
of the linkage, which gives every distance the links keep, and the points it places are
found by Newton's method on those distances, continued along the crank angle from the
drawn one. Its statics is its own linear system, three equations per link.
"""

from __future__ import annotations

import itertools
import math
import warnings
from collections.abc import Collection, Mapping, Sequence

import numpy as np

from .. import linalg, newton, numerics
from ..errors import InputError, NearSingularWarning
from ..kernels.trace import Reason
from ..numerics import SCALAR
from ..pairs import Revolute
from .base import (
    OWNER,
    Drawing,
    Field,
    Group,
    KinematicState,
    LinkJoints,
    fmt,
    moment_about,
    push,
)

#: the continuation's longest step, rad: 16 over half a turn. Measured on the class III
#: six-bar of tests/test_closure.py over 720 angles of a full turn, in fixed steps from
#: the line through the last two solutions: 7 steps over half a turn are the fewest that
#: keep every state on the drawn assembly mode; steps this long are taken where the
#: position is far from a limit or a singular one, shorter ones nearer
LONGEST = math.pi / 16
#: the shortest step, as a fraction of the way from the drawn angle to the state's: a
#: position that needs shorter ones to keep its assembly mode is at a limit (the crank
#: turns no further) or a singular position, and the state is not reached
SHORTEST = 2.0 ** -40
#: steps tried at most, taken and refused: a step is halved where refused and doubled
#: (up to LONGEST) where taken, so that reaching a state that far from a limit takes
#: about 4 tries per halving of the distance
TRIALS = 400
#: Newton iterations of a step at most (from the line through the last two solutions
#: they take 2 to 4 where the step is taken)
CORRECTIONS = 10
#: a step's Newton has converged when its last iteration moves at most this fraction of
#: the coordinates' size (the last step, to the state's own angle, converges to
#: :func:`linkage_fmu.newton.tolerance`)
SETTLED = 1e-10
#: a step is taken where its Newton correction is at most this fraction of the
#: predictor's own move, or where Newton's second iteration moves at most KAPPA times
#: its first (the correction is then far inside the region where no other assembly
#: mode lies)
DRIFT = 0.25
KAPPA = 0.1
#: a state is assembled when every distance equation holds to this fraction of its
#: squared length (Newton leaves about 1e-16; a state it did not reach, about 1 or NaN)
RESIDUAL = 1e-9
#: the condition number of the group's equations (each row over its length) in the
#: drawn pose above which building warns: the drawing barely fixes the assembly mode
NEAR_SINGULAR = 1e3


def _listing(links: Mapping) -> dict:
    """Point -> the links that list it, in order of first listing."""
    listing: dict = {}
    for link, joints in links.items():
        for p in joints:
            listing.setdefault(p, []).append(link)
    return listing


def _pairs(listing: dict, placed) -> list[Revolute]:
    """The revolute pairs: at a placed point, one with its owner (named by the point),
    at a point the group places, one between its first two links (named by the point);
    every further link at the point is pinned to the one listed before it
    (``<point>_<link>``)."""
    joints = []
    for p, links in listing.items():
        if p in placed:
            joints.append(Revolute(p, p, OWNER, links[0]))
        for k in range(1, len(links)):
            name = p if (k == 1 and p not in placed) else f"{p}_{links[k]}"
            joints.append(Revolute(name, p, links[k - 1], links[k]))
    return joints


def _rigid(joints: Sequence[str]) -> list[tuple[str, str]]:
    """The ``2m - 3`` distances that keep a link of ``m`` joints rigid: its first two
    joints', then each other joint's from both of them."""
    out = [(joints[0], joints[1])]
    for p in joints[2:]:
        out += [(joints[0], p), (joints[1], p)]
    return out


def _smallest(xp, values: list):
    best = values[0]
    for v in values[1:]:
        best = -xp.maximum(-best, -v)
    return best


def _largest(xp, values: list):
    best = values[0]
    for v in values[1:]:
        best = xp.maximum(best, v)
    return best


class Closure(Group):
    """An Assur group of revolute pairs solved as one (a class III group, or higher):
    ``links`` (new link -> its joints, at least two each; the first two give the link's
    direction, first -> second) drawn in the ``pose`` (point -> ``(x, y)``) at the
    crank angle ``theta``. The listed points placed before the group are its needs,
    the others it places. Its pairs are revolute: one with the owner of each placed
    point (named by the point), one between the first two links at each point it
    places (named by the point), and each further link at a point pinned to the link
    listed before it (``<point>_<link>``). Its transmission angle is at its first point
    joining two links.

    Positions: Newton's method on the distances the pose gives (unknowns: the
    coordinates of the points it places), continued from the drawn pose along the
    crank angle, from the drawn angle to the state's the shorter way round; at each
    angle the groups before it are placed again (:meth:`attach`), so a state's result
    depends on nothing but the state. The continuation follows the drawn assembly
    mode: each step predicts the position from the line through the last two (the
    first, along the tangent of the drawn pose) and corrects it by Newton; a step is
    taken only where Newton converges in :data:`CORRECTIONS` iterations, the sign of
    the Jacobian's determinant is the drawn pose's (it changes where the branch
    turns back or crosses another) and the correction stays small beside the
    predictor's move or Newton contracts fast (:data:`DRIFT`, :data:`KAPPA`);
    refused, it is halved, taken, doubled up to :data:`LONGEST`. A state whose way
    needs a step shorter than :data:`SHORTEST` of it, or more than :data:`TRIALS`
    steps, lies past a limit position (the crank turns no further on the drawn mode)
    or a singular one: it cannot be assembled, and so does one where the groups
    before it cannot be assembled at an angle on the way. No state is answered on
    another assembly mode. The whole continuation is one loop of a kernel, each
    step's Newton a loop inside it, and the linear solves pivot without a branch
    (:func:`linkage_fmu.linalg.solve`).

    Examples
    --------
    A four-bar's coupler and rocker (a dyad) solved as a closure, drawn at theta = 0:

    >>> import math
    >>> from linkage_fmu.groups import Crank
    >>> crank = Crank("1", "A", "B", 0.1)
    >>> g = Closure({"2": ("B", "C"), "3": ("D", "C")},
    ...             {"B": (0.1, 0.0), "C": (0.3, 0.2), "D": (0.4, 0.0)}, 0.0, {"B", "D"})
    >>> g.needs, g.places, [j.name for j in g.joints]
    (('B', 'D'), ('C',), ['B', 'C', 'D'])
    >>> g.attach((crank,), {"A": (0.0, 0.0), "D": (0.4, 0.0)})
    >>> st = KinematicState(0.0, SCALAR)
    >>> st.p.update(A=(0.0, 0.0), D=(0.4, 0.0))
    >>> crank.position(st); g.position(st)
    >>> [round(v, 12) for v in st.p["C"]]
    [0.3, 0.2]
    """

    kind = "closure"
    FIELDS = {
        "links": Field("link joints", "each link the group adds -> its joints (two or "
                                      "more): the placed points it is pinned to and the "
                                      "points the group places; its direction is from "
                                      "the first to the second"),
        "pose": Field("pose", "where every joint its links list is drawn, [x, y]: one "
                              "pose of the linkage, which gives the lengths and the "
                              "assembly mode"),
        "theta": Field("angle", "the crank angle at which the pose is drawn"),
    }
    DRAWING = Drawing(1, None)

    @classmethod
    def recognise(cls, drawn, links):
        """The smallest connected set of ``links`` (the links not yet placed) that the
        placed links hold with mobility 0, each link held twice: one closure group, its
        pairs revolute (one that slides is refused, naming why no dyad took it).

        Examples
        --------
        >>> from linkage_fmu.descriptions.topology import read
        >>> from linkage_fmu.descriptions.assur import decompose
        >>> t, _ = read({"joints": {"O": [0, 0], "A": [0.1, 0], "P": [0.5, -0.1],
        ...                         "Q": [0.3, -0.3], "E": [0.25, 0.3], "F": [0.55, 0.25],
        ...                         "G": [0.4, 0.05]},
        ...              "links": [{"name": "1", "joints": ["O", "A"]},
        ...                        {"name": "2", "joints": ["A", "E"]},
        ...                        {"name": "3", "joints": ["P", "F"]},
        ...                        {"name": "4", "joints": ["Q", "G"]},
        ...                        {"name": "5", "joints": ["E", "F", "G"]}],
        ...              "crank": {"link": "1", "pivot": "O"}}, {})
        >>> closure = decompose(t, {}).groups[1]
        >>> closure["type"], closure["links"]
        ('closure', {'2': ['A', 'E'], '3': ['P', 'F'], '4': ['Q', 'G'], '5': ['E', 'F', 'G']})
        """
        for size in range(2, len(links) + 1):
            for subset in itertools.combinations(links, size):
                if drawn.connected(subset) and drawn.mobility(subset) == 0 and all(
                        drawn.held_twice(n, subset) for n in subset):
                    cls._form(drawn, subset)
                    return True
        return False

    @classmethod
    def _form(cls, drawn, subset: tuple) -> None:
        """The closure group of the links ``subset``, its pairs and its links' points."""
        t = drawn.t
        sliding = [j for n in subset for j in t.links[n].joints if t.joints[j].prismatic]
        missed = [drawn.missed[j] for j in dict.fromkeys(sliding) if j in drawn.missed]
        if missed and len(subset) == 2:
            drawn.refuse(*missed)
        if sliding:
            what = ("a dyad that no dyad of the library is (an RRP's slider and an RPP's "
                    "yoke slide on a frame guide, an RPR's slot passes through its lever's "
                    "pivot)" if len(subset) == 2 else
                    f"a group of {len(subset)} links (only dyads may slide)")
            drawn.refuse(f"[[links]]: a group the decomposition cannot solve: links "
                         f"{', '.join(subset)}, with the prismatic pair(s) "
                         f"{', '.join(dict.fromkeys(sliding))}, form {what}")
        links, pose, places = {}, {}, {}
        for n in subset:
            names = []
            for j in t.links[n].joints:
                inside = [m for m in t.on(j) if m in subset]
                if drawn.placed(j):
                    p = drawn.attach(j, n)
                    names.append(p)
                    pose[p] = drawn.pose_of(p)
                elif len(inside) >= 2:
                    names.append(j)
                    pose[j] = places[j] = drawn.xy(j)
            links[n] = names
        drawn.group({"type": cls.kind, "links": links,
                     "pose": {p: [drawn.fold(x), drawn.fold(y)] for p, (x, y) in pose.items()},
                     "theta": drawn.out.theta}, places)
        for n, names in links.items():
            for p in names:
                if p not in places:
                    drawn.pair(p, drawn.owner[p], n)
        for j in places:
            # the closure group's pairs at a point it places: the first two links listing
            # it, then each further one pinned to the one listed before it
            inside = [n for n, names in links.items() if j in names]
            drawn.pair(j, inside[0], inside[1])
            for k in range(2, len(inside)):
                drawn.pair(f"{j}_{inside[k]}", inside[k - 1], inside[k])
            drawn.owner[j], drawn.first[j] = None, inside[0]
        for n, names in links.items():
            (x0, y0), (x1, y1) = pose[names[0]], pose[names[1]]
            drawn.frame_[n] = (names[0], (f"({x1} - {x0})", f"({y1} - {y0})"))
        for n in subset:
            drawn.finish(n)

    def __init__(self, links: Mapping[str, Sequence[str]], pose: Mapping[str, Sequence],
                 theta: float, placed: Collection[str]):
        self.link_joints = {link: tuple(joints) for link, joints in links.items()}
        self.listing = _listing(self.link_joints)
        order = tuple(self.listing)
        self.needs = tuple(p for p in order if p in placed)
        self.places = tuple(p for p in order if p not in placed)
        self.links = tuple(self.link_joints)
        self.joints = tuple(_pairs(self.listing, placed))
        self.owners = {p: self.listing[p][0] for p in self.places if len(self.listing[p]) == 1}
        shared = [p for p in self.places if len(self.listing[p]) > 1]
        self.key = (shared or list(self.places) or [None])[0]
        self.pose = {p: (pose[p][0], pose[p][1]) for p in order}
        self.theta0 = theta
        #: (point, point, squared distance) of every distance the group keeps
        self.constraints = []
        for joints in self.link_joints.values():
            for i, j in _rigid(joints):
                if i in placed and j in placed:
                    continue  # the checker refuses it (Closure.problems)
                (xi, yi), (xj, yj) = self.pose[i], self.pose[j]
                self.constraints.append((i, j, (xi - xj) ** 2 + (yi - yj) ** 2))
        self.lengths = tuple(numerics.sqrt(c) for _, _, c in self.constraints)
        #: link -> the drawn distance of its first two joints
        self.spans = {link: numerics.hypot(self.pose[js[1]][0] - self.pose[js[0]][0],
                                           self.pose[js[1]][1] - self.pose[js[0]][1])
                      for link, js in self.link_joints.items()}
        self.column = {p: 2 * k for k, p in enumerate(self.places)}
        self.name = f"the group of joints {', '.join(order)}"
        self._cannot_close = f"{self.name} cannot close"
        self._unreached = f"{self.name} cannot reach the state on its drawn assembly mode"
        #: why its equations are singular, in the words of the kernels' guards
        self.singular = f"{self.name} is at a singular position"
        self.before: tuple = ()
        self.frame_points: dict = {}
        #: on floats, the drawn pose's tangent and determinant's sign (:meth:`_start`)
        self._drawn = None

    @classmethod
    def from_spec(cls, spec, value):
        links: LinkJoints = value("links")
        return cls(links.links, value("pose"), value("theta"), links.placed)

    # -- the contract with description files -------------------------------------------
    @staticmethod
    def _links(spec: dict) -> dict | None:
        """The ``links`` field as link -> tuple of names, or None where it is malformed."""
        links = spec.get("links")
        if not isinstance(links, Mapping) or not all(
                isinstance(js, (list, tuple)) and all(isinstance(p, str) and p for p in js)
                for js in links.values()):
            return None
        return {link: tuple(js) for link, js in links.items()}

    @classmethod
    def pairs(cls, spec: dict, placed: Collection[str] | None = None) -> tuple[str, ...]:
        """The pairs of :func:`_pairs`; where ``placed`` is not known, a point one link
        lists is taken as placed (the others as placed by the group).

        Examples
        --------
        >>> links = {"3": ["B", "E"], "4": ["C", "F"], "6": ["D", "G"],
        ...          "5": ["E", "F", "G", "H"]}
        >>> Closure.pairs({"links": links}, {"B", "C", "D"})
        ('B', 'E', 'C', 'F', 'D', 'G')
        >>> Closure.pairs({"links": {"3": ["B", "E"], "4": ["E", "C"], "5": ["E", "D"]}},
        ...               {"B", "C", "D"})
        ('B', 'E', 'E_5', 'C', 'D')
        """
        links = cls._links(spec)
        if links is None:
            return ()
        listing = _listing(links)
        if placed is None:
            placed = {p for p, ls in listing.items() if len(ls) == 1}
        return tuple(j.name for j in _pairs(listing, placed))

    @classmethod
    def problems(cls, spec: dict, placed: Collection[str]) -> list[str]:
        """A link pinned to two placed points, a pose that does not give every joint (or
        gives another point), no point joining two of its links, or as many distance
        equations as unknown coordinates not (an Assur group has as many).

        Examples
        --------
        >>> spec = {"links": {"3": ["B", "E"], "5": ["E", "F"]},
        ...         "pose": {"B": [0, 0], "E": [1, 0], "F": [1, 1], "X": [0, 1]}}
        >>> for problem in Closure.problems(spec, {"B"}):
        ...     print(problem)
        pose X: is listed by no link
        links: 2 distance equations for 4 unknown coordinates (x and y of E, F): an Assur group has
        as many
        """
        links = cls._links(spec)
        pose = spec.get("pose")
        if links is None or not isinstance(pose, Mapping):
            return []  # each field's own check says what is wrong
        found = []
        listing = _listing(links)
        for link, joints in links.items():
            fixed = [p for p in joints if p in placed]
            if len(fixed) >= 2:
                found.append(f"links: link {link!r} is pinned to the placed points "
                             f"{fixed[0]} and {fixed[1]}: their distance is not the "
                             "group's to keep")
        for p, links_at in listing.items():
            if p not in pose:
                found.append(f"pose: no [x, y] for {p}, a joint of link {links_at[0]!r}")
        for p in pose:
            if p not in listing:
                found.append(f"pose {p}: is listed by no link")
        new = [p for p in listing if p not in placed]
        if new and not any(len(listing[p]) > 1 for p in new):
            found.append("links: no point the group places joins two of its links: they "
                         "are not one group")
        equations = sum(2 * len(js) - 3 for js in links.values() if len(js) >= 2)
        if equations != 2 * len(new):
            found.append(f"links: {equations} distance equations for {2 * len(new)} unknown "
                         f"coordinates (x and y of {', '.join(new) or 'no new point'}): an "
                         "Assur group has as many")
        return found

    # -- positions ----------------------------------------------------------------------
    def attach(self, before: tuple, frame_points: dict) -> None:
        """Keep the groups ``before`` and the frame points, to place the needed points
        at the continuation's angles; on floats, check that the drawn pose has them
        where those groups place them at the drawn angle (to 1e-9 of the group's
        largest length), refuse a pose drawn at a singular position (its assembly mode
        is undefined) and warn where it is drawn near one (:data:`NEAR_SINGULAR`)."""
        self.before, self.frame_points = tuple(before), dict(frame_points)
        self._drawn = None
        numbers = [self.theta0, *self.lengths, *(v for xy in self.pose.values() for v in xy)]
        if any(hasattr(v, "traced") for v in numbers):
            return  # checked when built on the parameters' values
        st = KinematicState(float(self.theta0), SCALAR)
        st.p.update(self.frame_points)
        try:
            for grp in self.before:
                grp.position(st)
        except ValueError as err:
            raise InputError(f"{self.name}: the linkage cannot be assembled at the drawn angle "
                             f"theta = {fmt(self.theta0)} rad: {err}") from None
        size = max([1e-300, *self.lengths])
        for p in self.needs:
            (x, y), (px, py) = st.p[p], self.pose[p]
            if hasattr(x, "traced") or hasattr(y, "traced"):
                continue
            off = math.hypot(x - px, y - py)
            if not off <= 1e-9 * size:
                raise InputError(
                    f"{self.name}: pose {p} = [{fmt(px)}, {fmt(py)}] is not where the groups "
                    f"before it place {p} at the drawn angle theta = {fmt(self.theta0)} rad, "
                    f"[{fmt(x)}, {fmt(y)}] ({off:.3g} m away)")
        cond = self.drawn_condition()
        if not math.isfinite(cond):
            raise InputError(f"{self.name}: its pose is drawn at a singular position (its "
                             "equations have no unique solution there): the drawing does "
                             "not fix its assembly mode; draw it in another pose")
        if cond > NEAR_SINGULAR:
            warnings.warn(f"{self.name} is drawn near a singular position: the condition "
                          f"number of its equations there is {cond:.3g} (above "
                          f"{NEAR_SINGULAR:g}), so the drawing barely fixes its assembly "
                          "mode; draw it farther from a limit or singular position",
                          NearSingularWarning, stacklevel=2)
        self._drawn = self._start(SCALAR)

    def drawn_condition(self) -> float:
        """The 2-norm condition number of the group's equations in the drawn pose, each
        row over its distance: 1 for links at right angles, infinite at a singular
        position (where the drawing does not fix the assembly mode).

        Examples
        --------
        >>> g = Closure({"2": ("B", "C"), "3": ("D", "C")},
        ...             {"B": (0.0, 0.0), "C": (0.3, 0.3), "D": (0.6, 0.0)}, 0.0, {"B", "D"})
        >>> round(g.drawn_condition(), 12)
        1.0
        """
        x = [float(v) for p in self.places for v in self.pose[p]]
        J, _ = self._equations(SCALAR, x, {p: self.pose[p] for p in self.needs})
        rows = np.array(J, float) / np.array([[L] for L in self.lengths], float)
        with np.errstate(all="ignore"):
            cond = float(np.linalg.cond(rows))
        return cond if math.isfinite(cond) else math.inf

    def _upstream(self, st: KinematicState, angle, order: int = 0) -> KinematicState:
        """The groups before this one at the crank angle ``angle``, on a state of their
        own (its failures are ``st``'s), their positions (and with ``order`` 1, their
        first-order coefficients)."""
        def fail(condition: str, what: str = ""):
            st.on_invalid(f"{self.name} is continued from the drawn angle "
                          f"{fmt(self.theta0)} rad through {fmt(angle)} rad, where "
                          f"{condition}", what)

        sub = KinematicState(angle, st.xp, fail)
        zero = (0.0, 0.0)
        for p, xy in self.frame_points.items():
            sub.p[p], sub.d1[p] = xy, zero
        for grp in self.before:
            grp.position(sub)
        if order:
            for grp in self.before:
                grp.first(sub)
        if sub.invalid is not None:
            st.mark(sub.invalid)
        return sub

    def _equations(self, xp, x: list, known: dict) -> tuple[list, list]:
        """The Jacobian (rows of the distances, columns of the unknowns) and the values
        ``(|Pi - Pj|^2 - L^2) / 2`` of the distance equations at the unknowns ``x``."""
        P = dict(known)
        for p, c in self.column.items():
            P[p] = (x[c], x[c + 1])
        n = len(x)
        J, f = [], []
        for i, j, L2 in self.constraints:
            (xi, yi), (xj, yj) = P[i], P[j]
            dx, dy = xi - xj, yi - yj
            f.append(0.5 * ((dx * dx + dy * dy) - L2))
            row = [0.0] * n
            if i in self.column:
                row[self.column[i]], row[self.column[i] + 1] = dx, dy
            if j in self.column:
                row[self.column[j]], row[self.column[j] + 1] = -dx, -dy
            J.append(row)
        return J, f

    @staticmethod
    def _solve(xp, J: list, f: list) -> tuple[list, object]:
        """``J^-1 f`` and the sign of ``det J``; on floats, NaN and 0 where ``J`` is exactly
        singular (as a kernel's division by 0 gives)."""
        if xp.scalar:
            try:
                return linalg.solve_signed(xp, J, f)
            except ZeroDivisionError:
                return [math.nan] * len(f), 0.0
        return linalg.solve_signed(xp, J, f)

    def _start(self, xp) -> tuple[list, object]:
        """The drawn pose's tangent ``dX/dtheta`` (of the points it places) and the sign
        of its Jacobian's determinant: where the continuation starts."""
        if self._drawn is not None and (xp is SCALAR or not xp.scalar):
            return self._drawn  # floats: computed once, when attached
        sub = self._upstream(KinematicState(self.theta0, xp), self.theta0, order=1)
        J, r = self._rate_equations(xp, self.pose, sub.d1, None)
        tangent, sign = self._solve(xp, J, r)
        tape = newton.tape_of(sign)
        if tape is not None:  # parameters draw it: the parameter step checks it
            tape.check(tape.compare("gt", xp.abs(sign), 0.0), True,
                       Reason("parameter", f"{self.name} is drawn at a singular position"))
        return tangent, sign

    def _correct(self, xp, x: list, known: dict, tape, tol: float = SETTLED,
                 maximum: int = CORRECTIONS) -> tuple[list, object, object, object]:
        """Newton from ``x`` on the distances, the needed points at ``known``, until an
        iteration moves at most ``tol`` of the coordinates' size, at most ``maximum``
        iterations, stopped where one moves more than half the one before (it would not
        converge in time, or it is at rounding): the position, whether it converged,
        the sign of the Jacobian's determinant there, and whether it contracted fast
        (its second iteration moved at most :data:`KAPPA` times its first)."""
        n = len(x)
        compare, select, both = newton.compare, newton.select, newton.both

        def body(c):
            x, count, first, second, last = c[:n], c[n + 1], c[n + 2], c[n + 3], c[n + 4]
            J, f = self._equations(xp, x, known)
            d, sign = self._solve(xp, J, f)
            x = [a - b for a, b in zip(x, d)]
            moved, size = sum(xp.abs(b) for b in d), sum(xp.abs(a) for a in x)
            first = select(xp, compare(xp, "lt", count, 0.5), moved, first)
            second = select(xp, both(xp, compare(xp, "gt", count, 0.5),
                                     compare(xp, "lt", count, 1.5)), moved, second)
            settled = compare(xp, "le", moved, tol * size)
            contracting = newton.either(xp, compare(xp, "lt", count, 0.5),
                                        compare(xp, "le", moved, 0.5 * last))
            return ([*x, sign, count + 1.0, first, second, moved, settled],
                    both(xp, compare(xp, "gt", moved, tol * size), contracting))

        c, _ = newton.repeat(xp, [*x, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0], body, 1, maximum, tape)
        size = sum(xp.abs(a) for a in c[:n])
        fast = compare(xp, "le", c[n + 3], KAPPA * c[n + 2] + newton.tolerance(xp) * size)
        return c[:n], c[n + 5], c[n], fast

    def _continue(self, st: KinematicState, delta) -> tuple[list, object, object]:
        """The continuation from the drawn pose (fraction 0 of the way) to the drawn
        angle plus ``delta`` (fraction 1): the position it ends at, the fraction of the
        way it reached, and the sign of the drawn pose's determinant."""
        xp, t0, n = st.xp, self.theta0, 2 * len(self.places)
        tangent, sign0 = self._start(xp)
        x0 = [v for p in self.places for v in self.pose[p]]
        v0 = [delta * t for t in tangent]  # d/d(fraction of the way)
        longest = -xp.maximum(-1.0, -LONGEST / xp.maximum(xp.abs(delta), 1e-300))
        tape = newton.tape_of(st.theta, delta, *v0, *x0)
        compare, select, both = newton.compare, newton.select, newton.both

        def body(c):
            u, h, x, v = c[0], c[1], c[2:2 + n], c[2 + n:]
            last = compare(xp, "ge", h, 1.0 - u)
            step = select(xp, last, 1.0 - u, h)
            reach = select(xp, last, 1.0, u + h)
            known = self._upstream(st, t0 + delta * reach).p
            guess = [a + step * b for a, b in zip(x, v)]
            y, converged, sign, fast = self._correct(
                xp, guess, {p: known[p] for p in self.needs}, tape)
            drift = sum(xp.abs(a - b) for a, b in zip(y, guess))
            ahead = step * sum(xp.abs(b) for b in v)
            # converged, on the drawn mode, and not far: Newton contracted fast, or its
            # correction is small beside the predictor's move
            near = newton.either(xp, fast, compare(xp, "le", drift, DRIFT * ahead))
            taken = both(xp, both(xp, converged, compare(xp, "gt", sign * sign0, 0.0)), near)
            u = select(xp, taken, reach, u)
            x = [select(xp, taken, a, b) for a, b in zip(y, x)]
            v = [select(xp, taken, (a - b) / step, w) for a, b, w in zip(y, c[2:2 + n], v)]
            h = select(xp, taken, -xp.maximum(-2.0 * step, -longest), 0.5 * step)
            return ([u, h, *x, *v], both(xp, compare(xp, "lt", u, 1.0),
                                          compare(xp, "ge", h, SHORTEST)))

        c, _ = newton.repeat(xp, [0.0, longest, *x0, *v0], body, 1, TRIALS, tape)
        return c[2:2 + n], c[0], sign0

    def _close(self, st: KinematicState, x: list, known: dict, sign0) -> list:
        """The last step, at the state's own needed points ``known``: Newton from ``x``
        (the continuation's end) on the distances to :func:`linkage_fmu.newton.tolerance`,
        or until it moves no closer (rounding, near a limit position); then the checks
        that the distances hold and that it is on the drawn assembly mode (the
        determinant's sign ``sign0``)."""
        xp = st.xp
        tape = newton.tape_of(st.theta, *x, *(v for xy in known.values() for v in xy))
        x, _, sign, _ = self._correct(xp, x, known, tape, newton.tolerance(xp),
                                      newton.MAX_ITERATIONS)
        _, f = self._equations(xp, x, known)
        worst = _largest(xp, [xp.abs(v) / L2 for v, (_, _, L2) in zip(f, self.constraints)])

        def condition() -> str:
            return (f"{self._cannot_close}: continued from its drawn pose (at theta = "
                    f"{fmt(self.theta0)} rad), Newton's method reaches no position that "
                    f"keeps its links' lengths on its drawn assembly mode at theta = "
                    f"{fmt(st.theta)} rad")

        # where the distances hold, on the drawn mode: NaN (a singular Jacobian, an
        # overflow) fails here too
        held = st.positive(RESIDUAL - worst, condition, self._cannot_close)
        mode = st.positive(sign * sign0, condition, self._cannot_close)
        if not xp.scalar:
            x = [v + 0.0 * held + 0.0 * mode for v in x]
        return x

    def _reached(self, st: KinematicState, x: list, reached, delta) -> list:
        """``x``, where the continuation reached the state (``reached``, the fraction of
        the way, is 1); else the state cannot be assembled (NaN on arrays)."""
        xp = st.xp
        tape = newton.tape_of(reached)
        if tape is not None:
            tape.check(tape.compare("ge", reached, 1.0), True,
                       Reason("assembly", self._unreached))
            return x
        if xp.scalar:
            if not reached >= 1.0:
                at = self.theta0 + delta * reached
                st.on_invalid(
                    f"{self._unreached}: continued from its drawn pose (at theta = "
                    f"{fmt(self.theta0)} rad) towards theta = {fmt(st.theta)} rad the shorter "
                    f"way round, its drawn assembly mode goes no further than theta = "
                    f"{fmt(at)} rad, a limit position (the crank turns no further on that "
                    "mode) or a singular one; a linkage whose crank cannot turn fully "
                    "reaches only the states on the side of its drawn pose that way: draw "
                    "it nearer to them", self._unreached)
            return x
        bad = ~(reached >= 1.0)
        if bad.any():
            st.mark(bad)
            x = [np.where(bad, np.nan, v) for v in x]
        return x

    def position(self, st: KinematicState) -> None:
        xp = st.xp
        t0 = self.theta0
        delta = xp.atan2(xp.sin(st.theta - t0), xp.cos(st.theta - t0))
        with np.errstate(all="ignore"):  # arrays: the states that fail are NaN
            x, reached, sign0 = self._continue(st, delta)
            x = self._reached(st, x, reached, delta)
            x = self._close(st, x, {p: st.p[p] for p in self.needs}, sign0)
        for p, c in self.column.items():
            st.p[p] = (x[c], x[c + 1])
        for link, js in self.link_joints.items():
            (ax, ay), (bx, by) = st.p[js[0]], st.p[js[1]]
            L = self.spans[link]
            st.u[link] = ((bx - ax) / L, (by - ay) / L)

    # -- derivatives --------------------------------------------------------------------
    def _rates(self, st: KinematicState, d: dict, quadratic: dict | None) -> None:
        """Solve ``J X = r`` for the derivative coefficients of the points it places
        into ``d`` (``st.d1`` or ``st.d2``): ``r`` from the needed points' own, and for
        the second order the terms ``|Pi' - Pj'|^2`` (``quadratic``: ``st.d1``)."""
        J, r = self._rate_equations(st.xp, st.p, d, quadratic)
        X, _ = linalg.solve(st.xp, J, r)
        for p, c in self.column.items():
            d[p] = (X[c], X[c + 1])

    def _rate_equations(self, xp, points: dict, d: dict, quadratic: dict | None):
        """``(J, r)`` of the derivative coefficients of the points it places, at the
        positions ``points``: ``r`` from the needed points' coefficients in ``d``, and for
        the second order the terms ``|Pi' - Pj'|^2`` (``quadratic``: the first's)."""
        x = [v for p in self.places for v in points[p]]
        J, _ = self._equations(xp, x, {p: points[p] for p in self.needs})
        zero = (0.0, 0.0)
        r = []
        for i, j, _ in self.constraints:
            (xi, yi), (xj, yj) = points[i], points[j]
            (ai, bi) = zero if i in self.column else d[i]
            (aj, bj) = zero if j in self.column else d[j]
            v = -((xi - xj) * (ai - aj) + (yi - yj) * (bi - bj))
            if quadratic is not None:
                (vi, wi), (vj, wj) = quadratic[i], quadratic[j]
                v = v - ((vi - vj) * (vi - vj) + (wi - wj) * (wi - wj))
            r.append(v)
        return J, r

    def _turn(self, st: KinematicState, d: dict, w: dict) -> None:
        """``phi'`` (or ``phi''``) of each link from its first two joints' ``d``."""
        for link, js in self.link_joints.items():
            (c, s) = st.u[link]
            (ax, ay), (bx, by) = d[js[0]], d[js[1]]
            w[link] = (c * (by - ay) - s * (bx - ax)) / self.spans[link]

    def first(self, st: KinematicState) -> None:
        self._rates(st, st.d1, None)
        self._turn(st, st.d1, st.w1)

    def second(self, st: KinematicState) -> None:
        self._rates(st, st.d2, st.d1)
        self._turn(st, st.d2, st.w2)

    # -- statics ------------------------------------------------------------------------
    def _matrix(self, st: KinematicState, scale) -> list:
        """The group's equilibrium: per link (in order), forces x, y and the moment
        about its first joint divided by ``scale``; per pair (in order), the two
        components of its reaction (of its body a on its body b)."""
        n = 2 * len(self.joints)
        A = [[0.0] * n for _ in range(3 * len(self.links))]
        for row, link in enumerate(self.links):
            r = 3 * row
            ox, oy = st.p[self.link_joints[link][0]]
            for k, j in enumerate(self.joints):
                if link not in (j.a, j.b):
                    continue
                sign = 1.0 if j.b == link else -1.0
                px, py = st.p[j.point]
                ax, ay = (px - ox) / scale, (py - oy) / scale
                A[r][2 * k] = A[r][2 * k] + sign
                A[r + 1][2 * k + 1] = A[r + 1][2 * k + 1] + sign
                A[r + 2][2 * k] = A[r + 2][2 * k] - sign * ay
                A[r + 2][2 * k + 1] = A[r + 2][2 * k + 1] + sign * ax
        return A

    def statics(self, mech, st, W, R):
        L = mech.length_scale
        b = []
        for link in self.links:
            fx, fy, m = moment_about(mech, st, W, link, self.link_joints[link][0])
            b += [-fx, -fy, -m / L]
        x, _ = linalg.solve(st.xp, self._matrix(st, L), b)
        for k, j in enumerate(self.joints):
            R[j.name] = (x[2 * k], x[2 * k + 1])
            if j.a == OWNER:  # the group's link acts on the owner with the opposite
                push(mech, st, W, mech.owner[j.point], j.point, -x[2 * k], -x[2 * k + 1])

    def transmission(self, st, scale):
        """``(gamma, kappa)``: ``gamma`` the angle in [0, pi] at the key joint (the first
        point it places that joins two links) between its first two links, each seen
        from the joint towards its first other joint (for a dyad, the angle between its
        links at the middle joint, as :class:`~linkage_fmu.groups.RRR` has it);
        ``kappa`` the 1-norm condition number ``|A|_1 |A^-1|_1`` of the group's
        equilibrium matrix ``A`` (forces, moments divided by ``scale``), infinite where
        it is singular."""
        xp = st.xp
        kx, ky = st.p[self.key]
        arms = []
        for link in self.listing[self.key][:2]:
            other = next(p for p in self.link_joints[link] if p != self.key)
            ox, oy = st.p[other]
            arms.append((ox - kx, oy - ky))
        (ax, ay), (bx, by) = arms
        gamma = xp.atan2(xp.abs(ax * by - ay * bx), ax * bx + ay * by)
        A = self._matrix(st, scale)
        n = len(A)
        norm = _largest(xp, [sum(xp.abs(A[r][c]) for r in range(n)) for c in range(n)])
        unit = [[1.0 if r == c else 0.0 for r in range(n)] for c in range(n)]
        try:
            columns, pivots = linalg.solve_many(xp, A, unit)  # of A^-1
        except ZeroDivisionError:  # floats or mpmath, exactly singular
            return gamma, math.inf
        small = _smallest(xp, pivots)
        with np.errstate(all="ignore"):
            kappa = norm * _largest(xp, [sum(xp.abs(v) for v in x) for x in columns])
        if xp.scalar:
            apart = small > 0.0
            numerics.label(small, Reason("singular", self.singular))
            return gamma, (kappa if apart else math.inf)
        return gamma, np.where(small > 0.0, kappa, np.inf)

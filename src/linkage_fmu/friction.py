"""Coulomb friction in the joints: the friction of each pair, solved with the reactions.

A revolute pair of pin radius ``r`` and coefficient ``mu`` resists the relative rotation
of its two links with a moment ``mu * r * |R|``; a prismatic pair resists their relative
sliding with a force ``mu * |N|``, or, for a slider of length ``l``, ``mu * (|N1| +
|N2|)`` with ``N1, N2 = N/2 -+ M/l`` its two end contacts (the two coincide with
``mu * |N|`` until the couple ``M`` cocks the slider). Each friction value is reported
as the action of the pair's body ``a`` on its body ``b``: a moment (revolute) or a force
along the pair's tangent ``t`` (prismatic, ``t`` the direction whose left normal is the
pair's normal), applied at the pair's point.

The friction opposes the relative motion ``c * omega``, ``c`` the first-order
coefficient of the relative rotation or sliding; where the crank stands (``omega = 0``,
a static scene) it opposes the motion the crank would start in its drive direction
``drive`` (+1 counter-clockwise, -1 clockwise); a pair with no relative motion (``c =
0``) has none.

The friction values depend on the reactions, which depend on them: the equations are
nonlinear. :func:`closed_form` keeps the frictionless solution's structure, group by
group from the last back to the crank: a group's reactions are affine in the friction of
its own joints (its statics is linear in its links' wrenches), so each group solves a
Newton iteration on its own friction values (at most three) from the frictionless
solution, and then its statics once with them. A balancing effort away from the crank
is found by a secant iteration on the virtual power balance over those group solves.
:func:`direct` is the reference: Newton on the whole assembled system of equations.
Every path takes the same :data:`ITERATIONS` steps first (a group's Newton iteration on
its friction values :data:`GROUP_ITERATIONS`), then continues up to
:data:`MAX_ITERATIONS` while they do not settle, so that the floats are the same
everywhere; in a traced kernel the iterations are loops of the generated code, every
sign of motion and branch of the friction law decided in them at run time. A position
at which the iteration has no solution reached from the frictionless one (the Jacobian's
determinant falls to zero on the way: the reactions grow without bound) is
self-locking: :class:`~linkage_fmu.errors.SelfLockingError` for one state, NaN and
:attr:`KinematicState.locked <linkage_fmu.groups.KinematicState>` for arrays (a state
without outputs, as one that cannot be assembled: ``sol.valid`` False, its status
:data:`~linkage_fmu.solver.LOCKED`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from . import kinetostatics, linalg, newton
from .errors import LinkageError
from .groups.base import KinematicState, push
from .kernels.trace import Reason, Sym

# the iterations, shared with the closure of class III groups, under this module's names;
# its constants are read here at each call (a test may change them on this module)
from .newton import ITERATIONS, MAX_ITERATIONS, TINY, TOLERANCE, inverse, not_  # noqa: F401
from .newton import loop as _loop
from .newton import tape_of as _tape
from .newton import tolerance as _tolerance
from .numerics import ARRAY
from .pairs import Pair

#: Newton steps a group's friction iteration (:func:`solve_group`) takes before it tests
#: whether its last step settled, on every path (then on, to :data:`MAX_ITERATIONS`,
#: while not): from the frictionless solution the steps of almost every state settle
#: by the fourth (the later steps would move the floats by rounding only)
GROUP_ITERATIONS = 4


def iterate(xp, x: list, step, fail, first=None, memory: tuple = ()) -> list:
    """:func:`linkage_fmu.newton.iterate` with this module's :data:`ITERATIONS` and
    :data:`MAX_ITERATIONS` (read at each call)."""
    return newton.iterate(xp, x, step, fail, first, memory, ITERATIONS, MAX_ITERATIONS)


@dataclass(frozen=True)
class Friction:
    """The friction of the pair ``joint`` as declared: its coefficient ``mu`` (>= 0), and
    for a revolute pair the pin ``radius`` (>= 0), for a prismatic pair optionally the
    slider's ``length`` (> 0). Values may be traced numbers (kernel parameters)."""

    joint: str
    mu: float
    radius: float | None = None
    length: float | None = None


class JointFriction(NamedTuple):
    """A friction resolved on the linkage: the pair, its values, the output's name."""

    joint: Pair
    mu: float
    radius: float
    length: float | None

    @property
    def output(self) -> str:
        """``Mf_<joint>`` (a moment, N.m) or ``Ff_<joint>`` (a force, N): the pair's
        ``friction_prefix``."""
        return f"{self.joint.friction_prefix}_{self.joint.name}"


class Declared(NamedTuple):
    """The friction a linkage is built with: each pair's (:class:`Friction`), the crank's
    ``drive`` direction, whether it is ``active`` (False: every ``mu`` is 0, and the
    linkage is solved without it, its outputs zero), and the ``parameters`` that only
    the friction uses (constants of the kernels while it is not active)."""

    frictions: tuple = ()
    drive: float = 1.0
    active: bool = False
    parameters: frozenset = frozenset()


class LinkageFriction(NamedTuple):
    """The friction of a linkage: every pair's, per group the pairs it closes, whether
    it is solved (``active``) and the crank's ``drive`` direction."""

    joints: tuple  # JointFriction
    groups: tuple  # per group of the mechanism: tuple of JointFriction
    active: bool = False
    drive: float = 1.0


NONE = LinkageFriction((), ())


def resolve(mech, declared: Declared) -> LinkageFriction:
    """The friction ``declared`` on ``mech``'s resolved joints.

    Raises
    ------
    ValueError
        A friction of a pair the linkage does not have, declared twice, or with values
        that do not fit its pair (a radius on a prismatic pair, a length on a revolute).
    """
    if not declared.frictions:
        return NONE
    joints = {j.name: j for j in mech.joints}
    by_name = {}
    for f in declared.frictions:
        j = joints.get(f.joint)
        if j is None:
            raise LinkageError(mech.name, f"friction of {f.joint!r}, which is no pair of the "
                               f"linkage; its pairs are: {', '.join(joints)}")
        if f.joint in by_name:
            raise LinkageError(mech.name, f"the friction of {f.joint} is given twice")
        wrong = j.friction_rule(f.radius, f.length)
        if wrong:
            raise LinkageError(mech.name, f"friction of {f.joint}: {wrong}")
        by_name[f.joint] = JointFriction(j, f.mu, f.radius, f.length)
    groups, k = [], 0
    for grp in mech.groups:
        n = len(grp.joints)
        groups.append(tuple(by_name[j.name] for j in mech.joints[k:k + n] if j.name in by_name))
        k += n
    return LinkageFriction(tuple(by_name[j.name] for j in mech.joints if j.name in by_name),
                           tuple(groups), declared.active, declared.drive)


class Reactions(dict):
    """Reactions by joint name (as :mod:`~linkage_fmu.kinetostatics` gives them), with
    the friction: ``friction`` (joint name -> moment or force of body a on body b),
    ``P_loss`` (the power it dissipates), ``ideal`` (the balancing effort without it,
    by virtual power) and ``direction`` (the sign of the crank's motion); where ``eta``
    is asked for, ``sources``: the power of each known load per unit of crank speed
    (:func:`~linkage_fmu.loads.powers`)."""

    __slots__ = ("friction", "P_loss", "ideal", "direction", "sources")


# -- the pieces, on any kind of number ---------------------------------------------------
def sign(xp, x):
    """-1, 0 or +1 as ``x`` (``xp.sign``: :func:`linkage_fmu.kernels.trace.sign`, no branch
    in the kernels, and no derivative, also at 0)."""
    return xp.sign(x)


def direction(drive, omega, static: bool, xp):
    """The sign of the crank's motion: of ``omega``, or ``drive`` where it is 0."""
    if static:
        return drive
    s = sign(xp, omega)
    return s + (1.0 - xp.abs(s)) * drive


def _velocity(mech, st: KinematicState, body: str, point: str):
    """First-order coefficient of the velocity of ``body``'s material point at ``point``."""
    if body == mech.frame:
        return 0.0, 0.0
    cg = mech.cg[body]
    (vx, vy), (px, py), (sx, sy) = st.d1[cg], st.p[point], st.p[cg]
    w = st.w1[body]
    return vx - w * (py - sy), vy + w * (px - sx)


def _omega(mech, st: KinematicState, body: str):
    return 0.0 if body == mech.frame else st.w1[body]


def coefficient(mech, st: KinematicState, jf: JointFriction):
    """First-order coefficient of the relative motion of the pair: ``phi_b' - phi_a'``
    (revolute), or the sliding of ``b`` on ``a`` along the tangent (prismatic)."""
    return jf.joint.relative_motion(st, lambda body: _omega(mech, st, body),
                                    lambda body, point: _velocity(mech, st, body, point))


def apply(mech, st: KinematicState, W: dict, jf: JointFriction, f) -> None:
    """Add the friction ``f`` of the pair (on body b; ``-f`` on body a) to the wrenches."""

    def couple(body, v):
        if body != mech.frame:
            W[body][2] = W[body][2] + v

    jf.joint.apply_friction(st, f, couple,
                            lambda body, point, fx, fy: push(mech, st, W, body, point, fx, fy))


def law(xp, jf: JointFriction, s, reaction):
    """The friction of the pair for its reaction (``(Fx, Fy)`` or ``(N, M)``) and
    motion sign ``s``, and its derivatives by the reaction's two components (the pair's
    :meth:`~linkage_fmu.pairs.Pair.friction_law`)."""
    return jf.joint.friction_law(xp, jf.mu, jf.radius, jf.length, s, reaction, TINY)


def _nothing(value) -> bool:
    """Whether ``value`` is 0 whatever the state: a traced constant 0, or a number (an
    array: each of its values) equal to 0; not a traced value computed at run time."""
    if isinstance(value, Sym):
        node = value.tape.nodes[value.index]
        return node.op == "const" and node.value == 0.0
    return not np.any(np.asarray(value) != 0.0)


def _scratch(W: dict | None, links) -> dict:
    """Wrenches for a trial solve of a group: its links' (copies, or zeros), and zeros
    for the bodies its statics pushes reactions onto."""
    out = _Zeros()
    for link in links:
        out[link] = list(W[link]) if W is not None else [0.0, 0.0, 0.0]
    return out


class _Zeros(dict):
    def __missing__(self, key):
        value = self[key] = [0.0, 0.0, 0.0]
        return value


def unit_responses(mech, st: KinematicState, grp, pairs: tuple) -> list:
    """``K[k][i]``: the reaction at pair ``i`` of ``grp`` to a unit friction value at its
    pair ``k`` alone (one trial solve each, on no other wrench: it does not depend on
    the loads, so one computation serves every solve of the group at a state)."""
    names = [jf.joint.name for jf in pairs]
    K = []
    for jf in pairs:
        unit, trial = _scratch(None, grp.links), {}
        apply(mech, st, unit, jf, 1.0)
        grp.statics(mech, st, unit, trial)
        K.append([trial[n] for n in names])
    return K


def solve_group(mech, st: KinematicState, grp, pairs: tuple, W: dict, R: dict,
                s: dict, K: list | None = None) -> object:
    """The statics of ``grp`` with the friction of its ``pairs`` (signs of motion ``s``
    by joint name): its reactions are ``R0 + K m`` in the friction values ``m`` (``K``
    from :func:`unit_responses`, computed here if not given), ``m`` solves
    ``m = law(R0 + K m)`` by Newton from 0, then the statics runs once with the
    friction applied. Returns what the statics returns."""
    if not pairs:
        return grp.statics(mech, st, W, R)
    xp = st.xp
    names = [jf.joint.name for jf in pairs]
    trial: dict = {}
    grp.statics(mech, st, _scratch(W, grp.links), trial)
    r0 = [trial[n] for n in names]
    if K is None:
        K = unit_responses(mech, st, grp, pairs)
    n = len(pairs)

    def step(m, flag=None):
        # the first step, from m = 0 without its products (-d is the first iterate): on
        # numbers where m[0] is None; in a kernel's loop, where the flag it carries is 1
        if flag is None:
            first = m[0] is None
            pick = lambda a, b: a if first else b  # noqa: E731
        else:
            first = False
            pick = lambda a, b: tape.select(flag, a, b)  # noqa: E731
        laws = []
        for i, jf in enumerate(pairs):
            a, b = r0[i]
            if not first:
                a0, b0 = a, b
                for k in range(n):
                    a, b = a + m[k] * K[k][i][0], b + m[k] * K[k][i][1]
                a, b = pick(a0, a), pick(b0, b)
            laws.append(law(xp, jf, s[jf.joint.name], (a, b)))
        g = [f[0] if first else pick(f[0], m[i] - f[0]) for i, f in enumerate(laws)]
        J = [[(1.0 if i == k else 0.0) - (laws[i][1] * K[k][i][0] + laws[i][2] * K[k][i][1])
              for k in range(n)] for i in range(n)]
        d, det = linalg.solve_adjugate(J, g)
        return [pick(-v, v) for v in d], det

    what = _locks(grp, pairs)
    fail = _failure(mech, st, what)
    tape = _tape(st.theta, *(v for r in r0 for v in r))
    if all(_nothing(v) for row in K for r in row for v in r):
        # the friction does not change the group's reactions (a crank's pin, its moment
        # taken by the balancing effort): the law at the reactions is the solution, what
        # the iteration's first step gives and its next ones keep (J = I, det 1)
        m = [0.0 + law(xp, jf, s[jf.joint.name], r0[i])[0] for i, jf in enumerate(pairs)]
    elif tape is not None:  # every step a run of one loop, the first by the flag it carries
        m = _loop(tape, xp, [0.0] * n, 1.0, (1.0,),
                  lambda m, memory: (*step(m, memory[0]), (0.0,)), fail,
                  Reason("locking", what), GROUP_ITERATIONS, MAX_ITERATIONS)
    else:
        m = newton.iterate(xp, [0.0] * n, lambda m, memory: (*step(m), memory), fail,
                           lambda m, memory: (*step([None] * n), memory), (),
                           GROUP_ITERATIONS, MAX_ITERATIONS)
    for jf, v in zip(pairs, m):
        apply(mech, st, W, jf, v)
        R.friction[jf.joint.name] = v
    return grp.statics(mech, st, W, R)


# -- the solutions --------------------------------------------------------------------------
def motion_signs(mech, st: KinematicState, omega, static: bool) -> tuple[dict, dict]:
    """Per pair with friction: its relative motion's coefficient ``c`` and the sign
    ``s`` of its motion (of ``c * omega``, or ``c * drive`` where ``omega = 0``)."""
    xp = st.xp
    fr = mech.friction
    d = direction(fr.drive, omega, static, xp)
    c = {jf.joint.name: coefficient(mech, st, jf) for jf in fr.joints}
    return c, {name: sign(xp, v) * d for name, v in c.items()}


def _failure(mech, st: KinematicState, what: str):
    """What :func:`iterate` calls where it fails: raise for one state, or mark ``bad``."""
    def fail(bad=None):
        if bad is None:
            from .errors import SelfLockingError
            raise SelfLockingError(mech.name, _where(mech, st), what)
        st.locked = bad if st.locked is None else st.locked | bad
    return fail


def _where(mech, st: KinematicState):
    """The state of an error: the crank angle, or each driver's coordinate by name."""
    if not mech.rates:
        return st.theta
    return {d.inputs[0]: float(np.asarray(q).reshape(-1)[0])
            for d, q in zip(mech.drivers, st.theta)}


def solve(mech, st: KinematicState, W: dict, plan, omega, xp):
    """Reactions and balancing effort with the friction in the joints, as the ``plan``
    asks (its method); ``W`` is consumed. The effort alone still needs the reactions; it
    is then taken from the virtual power balance ``e = e0 - sum(f c) / q'``, which is
    ``e0`` itself where every friction value is 0. A linkage without active friction is
    solved by :func:`linkage_fmu.evaluation.reactions` alone.
    """
    if plan.method == "direct":
        return direct(mech, st, W, omega, plan.static, xp,
                      kinetostatics.state_count(mech, st))
    R, effort = closed_form(mech, st, W, omega, plan.static)
    if not plan.reactions and not mech.rates:
        c, _ = motion_signs(mech, st, omega, plan.static)
        q1 = kinetostatics.effort_coefficient(mech, st)
        effort = R.ideal - virtual_power(R.friction, c) / q1
    return R, effort


def closed_form(mech, st: KinematicState, W: dict, omega, static: bool):
    """Reactions (a :class:`Reactions`) and balancing effort with friction, group by
    group from the last back to the crank; ``W`` is consumed.

    With the effort on the crank, the crank's moment equation gives it last. Elsewhere,
    the effort ``e`` solves ``e = e0 - sum(f c) / q'`` (the virtual power of the loads
    and of the friction values ``f`` over the relative motions ``c``; ``e0`` the
    frictionless effort) by a Newton step then secants from ``e0``, each of its values
    solved through the groups.
    """
    xp = st.xp
    fr = mech.friction
    c, s = motion_signs(mech, st, omega, static)

    order = list(zip(reversed(mech.groups), reversed(fr.groups)))
    # computed once: the effort's iteration below solves the groups several times
    responses = [unit_responses(mech, st, grp, pairs) for grp, pairs in order]

    def through(Wc: dict):
        R = Reactions()
        R.friction = {}
        moment, efforts = None, [None] * len(mech.drivers)
        for (grp, pairs), K in zip(order, responses):
            moment = solve_group(mech, st, grp, pairs, Wc, R, s, K)
            if mech.rates and grp.DRIVER:  # each driver's effort, from its own group
                efforts[grp.index] = moment
        return R, (tuple(efforts) if mech.rates else moment)

    if mech.effort_on_crank:
        R, effort = through(W)
    else:
        ideal = kinetostatics.virtual_effort(mech, st, W)
        q1 = kinetostatics.effort_coefficient(mech, st)

        def run(e):
            Wc = {k: list(v) for k, v in W.items()}
            kinetostatics.add_effort(mech, st, Wc, e)
            R, _ = through(Wc)
            return R, ideal - virtual_power(R.friction, c) / q1

        def first(x, memory):
            # a Newton step first (its slope from a probe 1e-6 away), then secants: the
            # fixed-point step overshoots where |dphi/de| > 1 and can reach a solution
            # that does not continue the frictionless one
            _, phi = run(x[0])
            h = phi - x[0]
            delta = 1e-6 * (xp.abs(x[0]) + xp.abs(h))
            _, probe = run(x[0] + delta)
            return [h * delta * _inverse(xp, probe - (x[0] + delta) - h)], None, (x[0], h)

        def step(x, memory):  # a secant through the last two values of the effort
            e_prev, h_prev = memory
            _, phi = run(x[0])
            h = phi - x[0]
            return [h * (x[0] - e_prev) * _inverse(xp, h - h_prev)], None, (x[0], h)

        what = "friction locks the linkage against its driver"
        fail = _failure(mech, st, what)
        tape = _tape(st.theta, ideal)
        if tape is None:
            effort = iterate(xp, [ideal], step, fail, first=first)[0]
            W = {k: list(v) for k, v in W.items()}
            kinetostatics.add_effort(mech, st, W, effort)
            R, _ = through(W)
        else:  # one loop of the kernel, one solve through the groups per run
            effort, R = _effort_loop(tape, xp, run, ideal, fail, Reason("locking", what))
    R.ideal = None if mech.rates else frictionless(mech, st, effort, R.friction, c)
    R.direction = direction(fr.drive, omega, static, xp)
    R.P_loss = 0.0 if static else -omega * virtual_power(R.friction, c)
    return R, effort


def _effort_loop(tape, xp, run, ideal, fail, reason: Reason):
    """The effort's iteration of :func:`closed_form` on traced numbers: one loop of the
    kernel, one solve through the groups (``run``) per run, the same operations on the
    same values as on floats. Its runs, by their ``phase``: 0, the solve at the
    frictionless effort ``ideal`` (no step); 1, at the probe, taking the Newton step;
    2, the secant steps, until they converge (tested after :data:`ITERATIONS` steps,
    as on floats); 3, the solve at the effort found, whose reactions the loop hands
    out. Returns the effort and the :class:`Reactions` there."""
    tol = _tolerance(xp)
    shape = []

    def body(carried):
        e, e_prev, h_prev, phase, count = carried
        starting, probing = tape.compare("eq", phase, 0.0), tape.compare("eq", phase, 1.0)
        final = tape.compare("eq", phase, 3.0)
        delta = 1e-6 * (xp.abs(e_prev) + xp.abs(h_prev))  # after run 0: of its solve
        point = tape.select(probing, e_prev + delta, e)
        R, phi = run(point)
        h = phi - point
        inverse = _inverse(xp, h - h_prev)
        d = tape.select(probing, h_prev * delta * inverse, h * (e - e_prev) * inverse)
        d = tape.select(starting, 0.0, tape.select(final, 0.0, d))
        x = e - d
        moved, size = sum(xp.abs(b) for b in [d]), sum(xp.abs(a) for a in [x])
        settled = tape.apply("min", min, tape.compare("ge", count, float(ITERATIONS)),
                             1.0 - tape.compare("gt", moved, tol * size))
        following = tape.apply("min", min, phase + 1.0, 2.0)
        phase = tape.select(final, 3.0, tape.select(settled, 3.0, following))
        shape[:] = [(k, len(v)) for k, v in R.items()] + list(R.friction)
        last = [v for k in R for v in R[k]] + list(R.friction.values())
        return ([x, e, tape.select(probing, h_prev, h), phase, count + 1.0],
                tape.compare("ne", final, 1), last)

    # MAX_ITERATIONS steps at most, after the first solve, and the last solve
    carried, converged = tape.loop([ideal, ideal, 0.0, 0.0, 0.0], body, 0,
                                   MAX_ITERATIONS + 2)
    if not tape.check(converged, True, reason):
        fail()
    values = iter(carried[5:])
    R = Reactions()
    for item in shape:
        if isinstance(item, tuple):
            R[item[0]] = tuple(next(values) for _ in range(item[1]))
    R.friction = {name: next(values) for name in shape if not isinstance(name, tuple)}
    return carried[0], R


def frictionless(mech, st: KinematicState, effort, friction: dict, c: dict):
    """The effort without friction, ``e0 = e + sum(f c) / q'`` from the power balance at
    the solution: equal to the frictionless solve to rounding, and to ``e`` itself where
    every friction value is 0."""
    return effort + virtual_power(friction, c) / kinetostatics.effort_coefficient(mech, st)


def _locks(grp, pairs) -> str:
    names = ", ".join(jf.joint.name for jf in pairs)
    return f"friction at {names} locks the group of link {grp.links[0]}"


def virtual_power(friction: dict, c: dict):
    """``sum(f c)``: the virtual power of the friction values over the relative motions."""
    total = 0.0
    for name, f in friction.items():
        total = total + f * c[name]
    return total


def _inverse(xp, x):
    """``1 / x``, and 0 for ``x = 0``: :func:`linkage_fmu.newton.inverse`."""
    return inverse(xp, x)


def direct(mech, st: KinematicState, W: dict, omega, static: bool, xp, n_states: int = 1):
    """Reactions and balancing effort with friction by Newton on the whole assembled
    system ``A x + w(x) = b`` (``w`` the friction's wrenches, the rows of
    :func:`~linkage_fmu.kinetostatics.equilibrium_entries`), from its frictionless
    solution: the reference for :func:`closed_form`, which shares only the friction
    law and the signs of motion with it. The floats go through numpy (batched over
    states), mpmath numbers (``xp.lu_solve``) through mpmath. Self-locking where it
    does not converge or the determinant of the Jacobian changes sign from ``A``'s."""
    fr = mech.friction
    c, s = motion_signs(mech, st, omega, static)
    n, entries, rhs = kinetostatics.equilibrium_entries(mech, st, W)
    L = mech.length_scale
    rows = {b.name: 3 * i for i, b in enumerate(mech.bodies)}
    column = {j.name: 2 * k for k, j in enumerate(mech.joints)}
    pattern = []  # per pair: its column, and the rows of its unit friction
    for jf in fr.joints:
        unit = {b.name: [0.0, 0.0, 0.0] for b in mech.bodies}
        apply(mech, st, _Zeros(unit), jf, 1.0)
        u = [(rows[b] + i, v / L if i == 2 else v) for b, w in unit.items()
             for i, v in enumerate(w)]
        pattern.append((jf, column[jf.joint.name], u))

    def scale(jf):  # of the pair's second column
        return jf.joint.column_scale(L)

    precise = getattr(xp, "lu_solve", None) is not None
    on = xp if precise else ARRAY

    def friction(x):
        """f per pair at the unknowns ``x``, and its derivatives by its two columns."""
        return [law(on, jf, s[jf.joint.name], (x[col], x[col + 1] * scale(jf)))
                for jf, col, _ in pattern]

    if precise:
        import mpmath
        A, B = mpmath.zeros(n, n), mpmath.zeros(n, 1)
        for r, k, v in entries:
            A[r, k] = v
        for r, v in rhs:
            B[r] = v
        x = mpmath.lu_solve(A, B)
        tol = xp.eps()
    else:
        A = np.zeros((n_states, n, n))
        for r, k, v in entries:
            A[:, r, k] = v
        B = np.empty((n_states, n))
        for r, v in rhs:
            B[:, r] = v
        x = linalg.solve_batch(A, B).T  # x[k]: unknown k over states (NaN: singular)
        tol = TOLERANCE
    sign_A = _det_sign(A, precise)
    done = np.zeros(n_states, bool)
    held = np.ones(n_states, bool)
    for k in range(MAX_ITERATIONS):
        laws = friction(x)
        if precise:
            G, J = A * x - B, A.copy()
            for (jf, col, u), f in zip(pattern, laws):
                for r, v in u:
                    G[r] += f[0] * v
                    J[r, col] += f[1] * v
                    J[r, col + 1] += f[2] * v * scale(jf)
            d = mpmath.lu_solve(J, G)
            x = x - d
            held[:] = _det_sign(J, True) == sign_A
            if k + 1 >= ITERATIONS and mpmath.norm(d, 1) <= tol * mpmath.norm(x, 1):
                done[:] = True
                break
            continue
        G = np.einsum("sij,js->si", A, x) - B
        J = A.copy()
        for (jf, col, u), (f0, fa, fb) in zip(pattern, laws):
            for r, v in u:  # scalars or one value per state: numpy broadcasts them
                G[:, r] += f0 * v
                J[:, r, col] += fa * v
                J[:, r, col + 1] += fb * v * scale(jf)
        with np.errstate(all="ignore"):
            d = linalg.solve_batch(J, G).T  # NaN where J is singular (an overflow)
            held = np.where(done, held, _det_sign(J, False) == sign_A)
            x = np.where(done, x, x - d)
            if k + 1 >= ITERATIONS:
                done |= np.abs(d).sum(axis=0) <= tol * np.abs(x).sum(axis=0)
                if done.all():
                    break
    ok = done & held
    if not precise:  # NaN or inf: an overflow or a singular position, named by the solver
        ok |= ~np.isfinite(x).all(axis=0)
    if xp.scalar and not ok[0]:
        from .errors import SelfLockingError
        raise SelfLockingError(mech.name, _where(mech, st), "friction locks the linkage")
    if not precise and not ok.all():
        _failure(mech, st, "friction locks the linkage")(~ok)
        x = np.where(ok, x, np.nan)
    if precise:
        x = [x[k] for k in range(n)]
    R, effort = kinetostatics.unknowns(mech, x)
    out = Reactions(R)
    out.friction = {jf.joint.name: f[0] for (jf, _, _), f in zip(pattern, friction(x))}
    if xp.scalar and not precise:  # one state: floats
        out.update({k: (float(a[0]), float(b[0])) for k, (a, b) in R.items()})
        out.friction = {k: float(np.asarray(v).reshape(-1)[0]) for k, v in out.friction.items()}
        effort = tuple(float(np.asarray(e).reshape(-1)[0]) for e in effort) if mech.rates \
            else float(effort[0])
    out.ideal = None if mech.rates else frictionless(mech, st, effort, out.friction, c)
    out.direction = direction(fr.drive, omega, static, xp)
    out.P_loss = 0.0 if static else -omega * virtual_power(out.friction, c)
    return out, effort


def _det_sign(A, precise: bool):
    if precise:
        import mpmath
        return mpmath.sign(mpmath.det(A))
    return np.sign(np.linalg.det(A))


# -- outputs ----------------------------------------------------------------------------------
@dataclass(frozen=True)
class FrictionOutput:
    """Output: the friction of ``pair``, the action of its body a on its body b: a moment
    (a pin, N.m, counter-clockwise positive) or a force along its sliding direction (a
    slider, N); as the pair says (:meth:`~linkage_fmu.pairs.Pair.friction_description`).
    Body b acts on body a with its opposite.

    Examples
    --------
    >>> from linkage_fmu.pairs import Revolute
    >>> out = FrictionOutput("Mf_B", Revolute("B", "B", "2", "3"))
    >>> out.unit, out.description[:40]
    ('N.m', 'friction moment in the pin B of link 2 o')
    """

    name: str
    pair: Pair

    @property
    def unit(self) -> str:
        return self.pair.friction_unit

    @property
    def description(self) -> str:
        return self.pair.friction_description()

    def bind(self, mech):
        return lambda R, E, st, name=self.pair.name: R.friction[name]


@dataclass(frozen=True)
class LossOutput:
    """Output: ``P_loss``, the power the friction dissipates (>= 0, 0 in a static
    scene), or ``eta``, the instantaneous efficiency ``1 - P_loss / P_in``.

    ``P_in`` is the power that enters the linkage at the instant: the sum, over every
    source, of its power where it is positive: the balancing effort's, each load's,
    gravity's, and the kinetic energy the links give up (``-dT/dt``, the power of the
    d'Alembert inertia wrenches). The power balance (virtual power) says that the
    powers of the sources add up to ``P_loss``; so ``P_in = P_out + P_loss``, ``P_out``
    the power the other sources take (their negative powers), and ``eta`` is
    computed as ``P_out / (P_out + P_loss)``: in ``[0, 1]`` also in rounding, exactly 1
    without friction, NaN where no power enters (``P_in = 0``). Every power is
    ``omega`` times a first-order coefficient; the ratio is taken of the coefficients
    times the sign of the crank's motion, which is the same where ``omega != 0``, and
    at ``omega = 0`` (a static scene) is the limit as the crank starts in its drive
    direction: the efficiency of the motion friction opposes there."""

    name: str

    unit = property(lambda self: "W" if self.name == "P_loss" else "1")
    #: eta has no value where no power enters, at states that have outputs
    finite = property(lambda self: self.name == "P_loss")

    @property
    def description(self) -> str:
        if self.name == "P_loss":
            return "power dissipated by friction in the joints"
        return ("instantaneous efficiency 1 - P_loss / P_in, P_in the power entering the "
                "linkage: the sum of the powers that are positive among the balancing "
                "effort's, each load's, gravity's and the kinetic energy the links give "
                "up (-dT/dt); in [0, 1], NaN where no power enters")

    def bind(self, mech):
        if self.name == "P_loss":
            return lambda R, E, st: R.P_loss

        def eta(R, E, st):
            # no comparison (the kernels trace it as it is): max(x, 0) picks the powers
            # that enter (d: the sign of the crank's motion makes coefficients powers)
            xp, d = st.xp, R.direction
            if mech.rates:  # each driver's effort times its speed
                rates = [e * rate[0] for e, rate in zip(E, st.rates)] + list(R.sources)
            else:
                rates = [E * kinetostatics.effort_coefficient(mech, st), *R.sources]
            taken = 0.0  # P_out: what the sources whose power is negative take
            for r in rates:
                taken = taken + xp.maximum(-d * r, 0.0)
            c = {jf.joint.name: coefficient(mech, st, jf) for jf in mech.friction.joints}
            loss = -d * virtual_power(R.friction, c)
            total = taken + loss  # P_in
            none = 1.0 - xp.abs(sign(xp, total))  # 1 where no power enters
            return taken / (total + none) + xp.nan_where(none)

        return eta


def outputs(mech) -> tuple:
    """The friction outputs of ``mech``: each pair's, ``P_loss`` and ``eta``."""
    if not mech.friction.joints:
        return ()
    return tuple(FrictionOutput(jf.output, jf.joint) for jf in mech.friction.joints) + (
        LossOutput("P_loss"), LossOutput("eta"))


def unsolved(mech, st: KinematicState, R: dict, effort, omega, static: bool) -> Reactions:
    """The frictionless reactions ``R`` as :class:`Reactions` with no friction: what a
    linkage whose every ``mu`` is 0 reports."""
    out = Reactions(R)
    # NaN where the state has no outputs: of the efforts, for a linkage driven by time
    zero = sum(0.0 * e for e in effort) if mech.rates else 0.0 * effort
    out.friction = dict.fromkeys((jf.joint.name for jf in mech.friction.joints), zero)
    out.P_loss, out.ideal = zero, None if mech.rates else effort
    out.direction = direction(mech.friction.drive, omega, static, st.xp)
    return out

"""A mechanism: a crank, ordered Assur groups, link inertia, loads and named outputs.

:class:`Mechanism` holds what a linkage *is*, as data: its topology (which link owns which
point, its pairs), its drivers, the names and units of its inputs and outputs, its length
scales; and it is the facade users call. The one sequence of formulas that computes a
plan's outputs on any kind of number (floats, arrays, mpmath, traced) is
:mod:`~linkage_fmu.evaluation`, a call's inputs :mod:`~linkage_fmu.inputs`; solving,
which path serves which call, lives in :mod:`~linkage_fmu.solver`, which reads the
mechanism's data and calls none of its methods. A mechanism is usually
built from a :class:`~linkage_fmu.descriptions.Description` (a description file, or a preset's).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from types import MappingProxyType

from . import diagnostics, evaluation, flywheel, inertia, motion, numerics
from . import effort_places as balancing
from . import equations as equilibrium
from .bodies import Body, Effort
from .errors import InputTypeError, LinkageError
from .friction import Declared
from .friction import outputs as friction_outputs
from .friction import resolve as resolve_friction
from .groups import FRAME, OWNER, Group, KinematicState
from .inputs import LEAN, InputTable, floats
from .loads import Load
from .outputs import SHAKING, EffortOutput, Shaking, shaking_pivot
from .pairs import Pair
from .solver import METHODS, Solution, Solver

__all__ = ["Mechanism", "Body", "Effort", "Solution", "METHODS"]


class Mechanism:
    """A crank-driven planar linkage composed of a crank and Assur groups.

    Parameters
    ----------
    name : str
        Used in messages.
    frame : str
        Name of the frame body in output names (e.g. '4').
    frame_points : dict
        Frame point name -> (x, y).
    groups : sequence of Group
        A driver first, then groups and link points in an order in which each one's
        points are already placed; several drivers (or a motor, a cylinder): see
        :data:`~linkage_fmu.drivers.KINDS` for the inputs and efforts then named.
    bodies : sequence of Body
        One per moving link.
    effort : Effort or None
        Where the balancing effort acts; None for a linkage driven by time, whose
        drivers apply the efforts.
    outputs : sequence
        Output declarations (:mod:`linkage_fmu.outputs`), in output order; the shaking
        force and moment (:data:`~linkage_fmu.outputs.SHAKING`) follow them.
    loads : sequence of Load
        The input loads, each an input of :meth:`solve` by its name.
    g : float
        Gravity along -y.
    parameters : dict, optional
        The parameter values it was built from.
    description : Description, optional
        What it was built from (for FMUs and the command line).
    rebuild : callable, optional
        ``rebuild(symbols)``: this linkage built again with the parameters named in
        ``symbols`` as the traced numbers there, so that its kernels take them as
        arguments (:mod:`~linkage_fmu.kernels`); None: the parameters are constants.
    start : dict, optional
        Input name -> start value: what an input not given takes (default 0).
    friction : Declared, optional
        The friction in its joints (:mod:`~linkage_fmu.friction`); none by default.
    """

    def __init__(self, name: str, frame: str, frame_points: dict, groups: Sequence,
                 bodies: Sequence[Body], effort: Effort | None, outputs: Sequence,
                 loads: Sequence[Load], g: float, parameters: dict | None = None,
                 description=None, rebuild: Callable[[dict], "Mechanism"] | None = None,
                 start: dict | None = None, friction: Declared = Declared()):
        self.name, self.frame = name, frame
        self.g = numerics.real(g)
        self.frame_points = {k: (numerics.real(x), numerics.real(y))
                             for k, (x, y) in frame_points.items()}
        self.bodies = tuple(bodies)
        self.effort = effort
        self.loads = tuple(loads)
        self._parameters = dict(parameters or {})
        self.description = description
        self.rebuild = rebuild
        for grp in groups:
            if not isinstance(grp, Group):
                raise InputTypeError(f"{name}: {grp!r} is not a group (a subclass of "
                                     "linkage_fmu.groups.Group)")
        if not groups or not groups[0].DRIVER:
            raise LinkageError(name, "the first group must be a driver (a Crank)")
        driving = [grp for grp in groups if grp.DRIVER]
        #: driven by time: several drivers, or one whose kinematics take its speed
        #: (:attr:`KinematicState.rates <linkage_fmu.groups.KinematicState>`)
        self.rates = len(driving) > 1 or driving[0].by_time
        _check_drivers(name, groups, effort, loads, self.rates)
        owner = _place(name, frame, self.frame_points, groups)
        links = [link for grp in groups for link in grp.links]
        body_names = [b.name for b in self.bodies]
        if sorted(links) != sorted(body_names):
            raise LinkageError(name, f"bodies {body_names} do not match the moving links {links}")
        for load in self.loads:
            if load.body not in body_names:
                raise LinkageError(name, f"load {load.name} acts on {load.body!r}, not a moving "
                                   "link")
        cg_points = [b.cg_point() for b in self.bodies if b.cg != b.ref]
        self.groups = tuple(groups) + tuple(cg_points)
        self.cg = {b.name: b.cg for b in self.bodies}
        self.owner = owner
        self.joints = tuple(_resolve(name, frame, owner, j) for grp in groups for j in grp.joints)
        _check_load_points(name, self.loads, self.bodies, owner, self.joints)
        #: the friction in its joints (:class:`~linkage_fmu.friction.LinkageFriction`)
        self.friction = resolve_friction(self, friction)
        #: what drives it: one :class:`~linkage_fmu.drivers.Driver` per degree of freedom
        self.drivers = tuple(grp.driver(effort.name) for grp in driving) if not self.rates \
            else tuple(grp.driver(None, alone=False) for grp in driving)
        #: the efforts it needs: the balancing effort, or each driver's
        self.efforts = (effort,) if not self.rates else tuple(
            _effort(frame, d.effort, grp.acts()) for d, grp in zip(self.drivers, driving))
        self.effort_on_crank = self.rates or (effort.direction is None and
                                              effort.body == groups[0].link)
        self.crank = groups[0]
        self.length_scale = _length_scale(groups, self.frame_points)
        self.offset_scale = _offset_scale(self.bodies, self.length_scale)
        self.dyads = tuple(grp for grp in groups if grp.key)
        #: its inputs: names, units, start values, a call's values
        #: (:class:`~linkage_fmu.inputs.InputTable`)
        self.input_table = table = InputTable(name, self.drivers, self.loads, start)
        #: the loads that are inputs (the others are computed over the cycle)
        self.input_loads, self.computed_loads = table.input_loads, table.computed_loads
        #: input name -> its unit (the loads over the cycle included)
        self.input_units = table.units
        # every linkage reports what its moving links put on the frame
        named = {o.name for o in outputs if isinstance(o, EffortOutput)}
        by_name = {e.name: e for e in self.efforts}
        outputs = tuple(_effort_output(by_name[o.name]) if self.rates and isinstance(
            o, EffortOutput) and not o.description and o.name in by_name else o
            for o in outputs) + tuple(  # every driver's effort is reported
            _effort_output(e) for e in self.efforts if self.rates and e.name not in named)
        outputs += friction_outputs(self) + tuple(
            Shaking(n, c) for n, c in zip(SHAKING, "xyM"))
        #: (name, fn(R, effort, st)) of every output, in output order
        self.output_functions = tuple((o.name, o.bind(self)) for o in outputs)
        #: output name -> (unit, description), diagnostics included
        self.output_info = {o.name: (o.unit, o.description) for o in outputs}
        self.effort_outputs = frozenset(o.name for o in outputs if isinstance(o, EffortOutput))
        self._output_names = tuple(o.name for o in outputs)
        #: the outputs that may be NaN at a state that has outputs (eta: no power enters)
        self.partial_outputs = frozenset(o.name for o in outputs
                                         if not getattr(o, "finite", True))
        self._diagnostic_names = tuple(f"gamma_{d.key}" for d in self.dyads) + (
            ("cond",) if self.rates else diagnostics.NAMES)
        _check_names(name, {"input": self.input_names, "parameter": tuple(self.parameters),
                            "output": self.output_names,
                            "diagnostic output": self.diagnostic_names})
        #: the real-valued parameters, its kernels' arguments (a branch, a choice, a friction
        #: with every mu 0 are structure); none for a linkage built without a description
        self.kernel_parameters = () if rebuild is None else tuple(
            n for n, v in self.parameters.items() if type(v) is float and (
                friction.active or n not in friction.parameters))
        self.output_info.update(_info(self))
        #: solves it: plans, kernels, methods (:class:`~linkage_fmu.solver.Solver`)
        self.solver = Solver(self)
        # the lean path of solve: [static, moving] hot kernels, the inputs' start values
        self._hot, self._start = self.solver.hot, table.defaults

    @property
    def output_names(self) -> tuple[str, ...]:
        """The names of its outputs, in the order :meth:`solve` returns them: each joint
        force's components (``F21x`` is the x component of the force of link 2 on link
        1, ``F4`` a force normal to a slide), the balancing effort (``Mb``, a moment on
        the crank, unless the description names another effort), the outputs the
        description declares, the friction outputs (each joint's friction moment
        ``Mf_<joint>`` or force ``Ff_<slide>``, ``P_loss``, ``eta``), and last the
        shaking force and moment of the moving links on the frame (``shake_x``,
        ``shake_y``, ``shake_M``). :attr:`diagnostic_names` follow them in a solution;
        ``output_info[name]`` is each one's ``(unit, description)``.

        Examples
        --------
        >>> from linkage_fmu import presets
        >>> yoke = presets.get("scotch_yoke")
        >>> yoke.output_names[:8]
        ('F12x', 'F12y', 'F23y', 'F4', 'F4p', 'F41x', 'F41y', 'Mb')
        >>> yoke.output_names[-3:]
        ('shake_x', 'shake_y', 'shake_M')
        >>> yoke.output_info["F12x"]
        ('N', 'force of link 1 on link 2, x component')
        >>> sol = yoke.solve(0.5, omega=10.0, load=400.0)
        >>> list(sol) == list(yoke.output_names + yoke.diagnostic_names)
        True
        """
        return self._output_names

    @property
    def diagnostic_names(self) -> tuple[str, ...]:
        """The names of the diagnostics :meth:`solve` returns after the outputs: the
        transmission angle ``gamma_<joint>`` of each dyad at its middle joint [rad]
        (0 or pi at a toggle), ``cond``, the estimated condition number of the
        outputs (their relative rounding error is about ``cond * 1e-16``; inf:
        singular), ``J_red``, the inertia reduced to the crank [kg m2], and
        ``dJ_red``, its derivative with respect to ``theta`` [kg m2/rad].

        Examples
        --------
        >>> from linkage_fmu import presets
        >>> mech = presets.get("four_bar")
        >>> mech.diagnostic_names, mech.output_info["gamma_C"][0]
        (('gamma_C', 'cond', 'J_red', 'dJ_red'), 'rad')
        """
        return self._diagnostic_names

    @property
    def input_names(self) -> tuple[str, ...]:
        """The inputs of :meth:`solve`, in the order it takes them positionally:
        ``theta`` [rad], ``omega`` [rad/s] and ``alpha`` [rad/s2] of the crank, then
        each input load by name (a preset's one load is ``load``); a load given over
        the cycle in the description (a value or a table) is computed, not an input.
        ``input_units[name]`` is each one's unit, :attr:`start` its value where none is
        given.

        Examples
        --------
        >>> import linkage_fmu
        >>> mech = linkage_fmu.load("examples/coupler_four_bar.toml")
        >>> mech.input_names
        ('theta', 'omega', 'alpha', 'F_P', 'T4')
        >>> mech.input_units["F_P"], mech.input_units["T4"]
        ('N', 'N.m')
        >>> a = mech.solve(0.6, 25.0, -40.0, 80.0, 120.0)  # positionally
        >>> b = mech.solve(0.6, omega=25.0, alpha=-40.0, F_P=80.0, T4=120.0)
        >>> a["Mb"] == b["Mb"]
        True
        """
        return self.input_table.names

    @property
    def parameters(self) -> dict:
        """Parameter name -> the value it was built with, in SI (lengths in m, angles in
        rad, masses in kg, inertias in kg m2), a branch or choice as its value: the
        description's defaults with the values given to :func:`linkage_fmu.load` or
        :func:`linkage_fmu.presets.get` in their place. Empty for a linkage built
        without a description. Building again with others:
        ``linkage_fmu.presets.get(name, **{**mech.parameters, "l_AB": 0.12})``.

        Examples
        --------
        >>> from linkage_fmu import presets
        >>> mech = presets.get("four_bar", l_AB="120 mm")
        >>> mech.parameters["l_AB"], mech.parameters["l_BC"]
        (0.12, 0.35)
        >>> list(mech.parameters)[:4]
        ['l_AB', 'l_BC', 'l_CD', 'l_AD']
        """
        return self._parameters

    @property
    def start(self) -> MappingProxyType:
        """Input name -> the value it takes where none is given; read-only (the lean path
        of :meth:`solve` keeps the input loads' start values): other start values are
        its description's ``[inputs]`` and the loads' ``start``."""
        return self.input_table.start

    def __repr__(self) -> str:
        params = ", ".join(f"{k}={v!r}" for k, v in self.parameters.items())
        return f"<Mechanism {self.name}({params})>"

    # -- kinematics -------------------------------------------------------------
    def kinematics(self, theta, order: int = 2, xp=None, rates=None) -> KinematicState:
        """Positions and their derivatives to ``order`` at the crank angle(s) ``theta`` (or
        drivers' coordinates and ``rates``): :func:`linkage_fmu.evaluation.kinematics`."""
        return evaluation.kinematics(self, theta, order, xp, rates)

    def reduced_inertia(self, theta, xp=None) -> tuple:
        """J_red and dJ_red/dtheta: :func:`linkage_fmu.inertia.reduced_inertia`."""
        return inertia.reduced_inertia(self, theta, xp)

    def mass_matrix(self, q):
        """The mass matrix reduced to the drivers: :func:`linkage_fmu.inertia.mass_matrix`."""
        return inertia.mass_matrix(self, q)

    def equations(self, *inputs, **named):
        """``A x = b`` at one state, labelled: :func:`linkage_fmu.equations.equations`."""
        return equilibrium.equations(self, *inputs, **named)

    def effort_places(self, theta, *inputs, **named):
        """The balancing effort's places: :func:`linkage_fmu.effort_places.effort_places`."""
        return balancing.effort_places(self, theta, *inputs, **named)

    def simulate(self, tau, t, theta0=None, omega0=None, **options):
        """The motion under the crank torque ``tau``: :func:`linkage_fmu.motion.simulate`."""
        return motion.simulate(self, tau, t, theta0, omega0, **options)

    def flywheel(self, omega_mean, Cs, **options):
        """The flywheel for ``Cs`` at ``omega_mean``: :func:`linkage_fmu.flywheel.flywheel`."""
        return flywheel.flywheel(self, omega_mean, Cs, **options)

    # -- inputs -----------------------------------------------------------------
    def inputs(self, omega=None, alpha=None, loads: Sequence = (),
               named: dict | None = None) -> tuple[list, tuple]:
        """``[omega, alpha, *loads]`` of a call, and the loads over the cycle it gives:
        :meth:`InputTable.values <linkage_fmu.inputs.InputTable.values>`.

        Examples
        --------
        >>> from linkage_fmu import presets
        >>> presets.get("four_bar").inputs(alpha=2.0, named={"load": 3.0})
        ([10.0, 2.0, 3.0], ())
        """
        return self.input_table.values(omega, alpha, loads, named)

    # -- solving (the solver's public interface, here for convenience) -----------
    def solve(self, theta=None, omega=None, alpha=None, *loads, method: str = "closed_form",
              outputs: Iterable[str] | None = None, **named_loads) -> Solution:
        """Joint reactions, balancing effort and diagnostics at one or many states.

        Each input is a float, text with a unit (one state) or an array; the
        parameters, what it returns and what it raises are those of
        :meth:`Solver.solve <linkage_fmu.solver.Solver.solve>`, which serves every call
        this method's fast path (a hot compiled kernel, plain numbers) does not. A
        linkage driven by time takes its :attr:`input_names` positionally or by name.

        Examples
        --------
        >>> import math
        >>> from linkage_fmu import presets
        >>> yoke = presets.get("scotch_yoke")
        >>> sol = yoke.solve(math.radians(60), omega=10.0, load=400.0)
        >>> round(sol["Mb"], 4), round(sol["F23y"], 4)
        (15.6699, 313.3975)
        >>> yoke.solve([0.0, math.pi / 2], omega=10.0, load=400.0)["F23y"].round(4)
        array([400., 300.])
        """
        if outputs is None and method == "closed_form" and not self.rates:
            # the lean path, the one fast path: plain numbers, every output, the compiled
            # kernel once hot (Solver.hot). It returns only the kernel's Solution, the
            # floats the general path returns for the same inputs; anything else (text,
            # arrays, a state without outputs, a kernel not yet hot, no compiler) goes on
            # to the solver, which decides and raises
            w = self._start["omega"] if omega is None else omega
            a = self._start["alpha"] if alpha is None else alpha
            hot = None
            if type(w) in LEAN and type(a) in LEAN:  # the kernel checks every input
                hot = self._hot[1] if w != 0.0 or a != 0.0 else self._hot[0]
            if hot is not None:
                table = self.input_table
                if named_loads and len(named_loads) == 1 and not loads and table.one_load:
                    # a linkage's one load by name (None for another name: the kernel
                    # refuses it, the general path says why)
                    r = hot(theta, w, a, named_loads.get(table.one_load))
                else:
                    x = loads if not named_loads and len(loads) == table.n_loads else \
                        table.lean_loads(loads, named_loads)
                    r = None if x is None else \
                        hot(theta, w, a, x[0]) if len(x) == 1 else hot(theta, w, a, *x)
                if type(r) is Solution:
                    return r
                if r is None:  # ints or numpy floats, taken as floats
                    x = table.lean_loads(loads, named_loads)
                    x = None if x is None else floats((theta, w, a, *x))
                    if x is not None and type(r := hot(*x)) is Solution:
                        return r
        return self.solver.solve(theta, omega, alpha, *loads, method=method, outputs=outputs,
                                 **named_loads)

    def table(self, theta, omega=None, alpha=None, *loads, method: str = "closed_form",
              outputs: Iterable[str] | None = None, **named_loads):
        """:meth:`solve` as a DataFrame: :meth:`Solver.table <linkage_fmu.solver.Solver.table>`."""
        return self.solver.table(theta, omega, alpha, *loads, method=method, outputs=outputs,
                                 **named_loads)

    def kernel(self, outputs: Iterable[str] | None = None, static: bool = False):
        """The traced kernel of the plan ``(outputs, static)``: :meth:`.Solver.kernel`."""
        return self.solver.kernel(outputs, static)


def _info(mech) -> dict:
    """(unit, description) of the diagnostics of ``mech``, and of its shaking moment
    where it is driven by time (about its first frame point)."""
    out = {k: v for k, v in diagnostics.info(mech).items() if k in mech.diagnostic_names}
    if mech.rates:
        out["shake_M"] = ("N.m", f"shaking moment: moment about {shaking_pivot(mech)} of "
                          "what the moving links exert on the frame (joints and drivers), "
                          "counter-clockwise positive")
    return out


def _check_drivers(name: str, groups: Sequence, effort, loads: Sequence[Load],
                   rates: bool) -> None:
    """Refuse a linkage driven by one crank without its balancing effort, and what a
    linkage driven by time (several drivers, a motor, a cylinder) cannot take: a
    balancing effort besides its drivers', a load given over a crank's cycle, and a
    class III group (whose continuation follows one crank)."""
    if not rates:
        if effort is None:
            raise LinkageError(name, "it is driven by one crank: give its balancing effort "
                               "(an Effort: a moment on the crank, Effort(\"Mb\", link), or "
                               "another)")
        return
    drivers = ", ".join(f"{type(g).__name__} at {g.driver(None, False).name}"
                        for g in groups if g.DRIVER)
    head = f"it is driven by time ({drivers}):"
    if effort is not None:
        raise LinkageError(name, f"{head} each driver applies its own effort (Mb_<j>, "
                           f"Fb_<j>), so it takes no balancing effort {effort.name!r}")
    computed = [ld.name for ld in loads if ld.computed]
    if computed:
        raise LinkageError(name, f"{head} a load over a crank's cycle ({', '.join(computed)}) "
                           "has no crank angle to follow; give it as an input")
    closures = [g.key or type(g).__name__ for g in groups if g.kind == "closure"]
    if closures:
        raise LinkageError(name, f"{head} a class III group (at {', '.join(closures)}) is "
                           "solved for linkages driven by one crank only, so far")


def _effort(frame: str, name: str, acts: tuple) -> Effort:
    """A driver's effort, where its group says it acts (:meth:`Group.acts
    <linkage_fmu.groups.Group.acts>`), its base the frame by name."""
    body, point, direction, base = acts
    return Effort(name, body, point, direction, frame if base == FRAME else base)


def _effort_output(e: Effort) -> EffortOutput:
    """The output of a driver's effort ``e``."""
    if e.direction is None:
        return EffortOutput(e.name, "N.m", f"moment the driver applies to link {e.body} "
                            f"(its reaction on {e.base}), counter-clockwise positive")
    return EffortOutput(e.name, "N", f"force the cylinder applies to its rod {e.body} "
                        "along its axis, from its barrel's pin to its rod's (> 0 pushes "
                        "them apart)")


def _place(name: str, frame: str, frame_points: dict, groups: Sequence) -> dict:
    """Point -> the link that owns it, the groups taken in order: each needs only
    points placed before it, and fits those before it (:meth:`Group.attach
    <linkage_fmu.groups.Group.attach>`)."""
    placed = set(frame_points)
    owner = {p: frame for p in frame_points}
    for grp in groups:
        missing = [p for p in grp.needs if p not in placed]
        if missing:
            raise LinkageError(name, f"{type(grp).__name__} needs {missing} placed before it")
        placed.update(grp.places)
        owner.update(grp.owners)
    for k, grp in enumerate(groups):  # a group that re-places what is before it
        try:
            grp.attach(tuple(groups[:k]), frame_points)
        except ValueError as err:
            raise LinkageError(name, str(err)) from None
    return owner


def _length_scale(groups: Sequence, frame_points: dict):
    """A length of the linkage's size: its fixed link lengths, and, where a group's size
    is not a fixed length (a slotted lever), the distances of the frame points."""
    sizes = [v for grp in groups for v in grp.lengths]
    if not all(grp.fixed_size for grp in groups):
        points = list(frame_points.values())
        sizes += [numerics.hypot(p[0] - q[0], p[1] - q[1])
                  for i, p in enumerate(points) for q in points[:i]]
    return numerics.largest(sizes)


def _offset_scale(bodies: Sequence[Body], length_scale):
    """The factor of ``cond`` for centres of mass far from their joints: the largest
    ``offset / length_scale`` of the bodies, at least 1 (exactly 1 while every centre of
    mass is within ``length_scale`` of its point ``ref``).

    The equations take moments about the centres of mass, so a joint force on a link
    whose centre of mass lies ``d`` away gets an arm of about ``d``: the closed form
    cancels terms of that size and the direct method's moment rows get entries ``d /
    L``. Both lose about the largest ``d / L`` in relative accuracy, not the product of
    them (measured; tests/test_stability.py).
    """
    return numerics.largest([1.0] + [b.offset / length_scale for b in bodies])


def _resolve(name: str, frame: str, owner: dict, j: Pair) -> Pair:
    """The pair ``j`` between the links it joins: the frame by its name, and the link
    that owns its point where the group left that to the linkage (``OWNER``)."""
    a = frame if j.a == FRAME else j.a
    if a == OWNER:
        if j.point not in owner:
            raise LinkageError(name, f"joint {j.name} is shared by two links; "
                               "attach to a point that belongs to one link")
        a = owner[j.point]
    return j.between(a)


def _check_load_points(name: str, loads: Sequence[Load], bodies: Sequence[Body],
                       owner: dict, joints: Sequence[Pair]) -> None:
    """Refuse a force load whose point ``at`` is not on its body: a point a group placed
    on it (a crank's tip, a point fixed on the link), its centre of mass or its ``ref``,
    or the point of one of its joints. Elsewhere the force would act on a point of the
    plane the body does not reach, with another body's (or the frame's) point named.

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> from linkage_fmu.loads import Load
    >>> mech = presets.get("four_bar")
    >>> F = Load("F", "2", "force", at="D", direction=(0.0, -1.0))
    >>> _check_load_points(mech.name, [F], mech.bodies, mech.owner, mech.joints)
    Traceback (most recent call last):
    ...
    linkage_fmu.errors.LinkageError: four_bar: load F acts on body 2 at point D, which is not a
    point of body 2 (its points: B, C, S2)
    """
    points = {b.name: {b.ref, b.cg} for b in bodies}
    for point, link in owner.items():
        points.get(link, set()).add(point)
    for j in joints:
        for link in (j.a, j.b):
            points.get(link, set()).add(j.point)
    for load in loads:
        if load.kind == "force" and load.at not in points.get(load.body, {load.at}):
            on = ", ".join(sorted(points[load.body]))
            raise LinkageError(name, f"load {load.name} acts on body {load.body} at point "
                               f"{load.at}, which is not a point of body {load.body} (its "
                               f"points: {on})")


def _check_names(name: str, kinds: dict) -> None:
    """Refuse a name given to two things (a parameter named as a transmission angle, an
    output named as an input): an FMU has one variable per name, and a solution one
    value per name."""
    seen: dict = {}
    for kind, names in kinds.items():
        for n in names:
            if n in seen:
                raise LinkageError(name, f"the name {n!r} is both {_article(seen[n])} and "
                                   f"{_article(kind)}")
            seen[n] = kind


def _article(kind: str) -> str:
    return ("an " if kind[0] in "aeiou" else "a ") + kind


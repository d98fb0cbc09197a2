"""A mechanism: a crank, ordered Assur groups, link inertia, loads and named outputs.

:class:`Mechanism` holds what a linkage *is*: its topology (which link owns which point,
the joints), names and units of its inputs and outputs, its length scales, its
kinematics, and one sequence of formulas, :meth:`Mechanism.evaluate`, that computes a
plan's outputs on any kind of number (floats, arrays, mpmath, traced). Solving, which
path serves which call, lives in :mod:`~linkage_fmu.solver`. A mechanism is usually
built from a :class:`~linkage_fmu.descriptions.Description` (a description file, or a preset's).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from types import MappingProxyType

import numpy as np

from . import diagnostics, flywheel, friction, inertia, motion, numerics
from .bodies import Body, Effort
from .errors import AssemblyError, InputTypeError, LinkageError
from .expressions import evaluate
from .friction import Declared
from .friction import outputs as friction_outputs
from .friction import resolve as resolve_friction
from .groups import FRAME, OWNER, Group, KinematicState
from .loads import Load, powers, wrenches
from .numerics import ARRAY, SCALAR, finite_array, finite_float
from .outputs import SHAKING, EffortOutput, Shaking
from .pairs import Pair
from .solver import METHODS, Solution, Solver
from .units import MOTION_UNITS

__all__ = ["Mechanism", "Body", "Effort", "Solution", "METHODS", "MOTION"]

#: the inputs every linkage has; its loads follow them
MOTION = ("theta", "omega", "alpha")


#: the types :meth:`Mechanism.solve`'s lean path takes besides floats, as floats
#: (:func:`_floats`)
_CONVERTED = frozenset((int, np.float64))
#: the types of omega and alpha it takes (not bool: the general path refuses it)
_LEAN = _CONVERTED | {float}


def _floats(inputs: tuple) -> list | None:
    """``inputs`` with each int or numpy float64 as a float (as the general path takes
    them), or None where an int does not fit a float (the general path says why)."""
    try:
        return [float(v) if type(v) in _CONVERTED else v for v in inputs]
    except OverflowError:
        return None


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
        The :class:`~linkage_fmu.groups.Crank` first, then groups and link points in
        an order in which each one's points are already placed.
    bodies : sequence of Body
        One per moving link.
    effort : Effort
        Where the balancing effort acts.
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
                 bodies: Sequence[Body], effort: Effort, outputs: Sequence,
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
            raise LinkageError(name, "the first group must be the driver (a Crank)")
        placed = set(self.frame_points)
        owner = {p: frame for p in self.frame_points}
        for grp in groups:
            missing = [p for p in grp.needs if p not in placed]
            if missing:
                raise LinkageError(name, f"{type(grp).__name__} needs {missing} placed before it")
            placed.update(grp.places)
            owner.update(grp.owners)
        for k, grp in enumerate(groups):  # a group that re-places what is before it
            try:
                grp.attach(tuple(groups[:k]), self.frame_points)
            except ValueError as err:
                raise LinkageError(name, str(err)) from None
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
        self.joints = tuple(self._resolve(j) for grp in groups for j in grp.joints)
        _check_load_points(name, self.loads, self.bodies, owner, self.joints)
        #: the friction in its joints (:class:`~linkage_fmu.friction.LinkageFriction`)
        self.friction = resolve_friction(self, friction)
        self.effort_on_crank = effort.direction is None and effort.body == groups[0].link
        self.crank = groups[0]
        #: a length of the linkage's size: its fixed link lengths, and, where a group's
        #: size is not a fixed length (a slotted lever), the distances of the frame points
        sizes = [v for grp in groups for v in grp.lengths]
        if not all(grp.fixed_size for grp in groups):
            points = list(self.frame_points.values())
            sizes += [numerics.hypot(p[0] - q[0], p[1] - q[1])
                      for i, p in enumerate(points) for q in points[:i]]
        self.length_scale = numerics.largest(sizes)
        #: factor of ``cond`` for centres of mass far from their joints: the largest
        #: ``offset / length_scale`` of the bodies, at least 1 (exactly 1 while every
        #: centre of mass is within ``length_scale`` of its point ``ref``). The equations
        #: take moments about the centres of mass, so a joint force on a link whose
        #: centre of mass lies ``d`` away gets an arm of about ``d``: the closed form
        #: cancels terms of that size and the direct method's moment rows get entries
        #: ``d / L``. Both lose about the largest ``d / L`` in relative accuracy, not the
        #: product of them (measured; tests/test_stability.py)
        self.offset_scale = numerics.largest([1.0] + [b.offset / self.length_scale
                                                      for b in self.bodies])
        self.dyads = tuple(grp for grp in groups if grp.key)
        #: the loads that are inputs (the others are computed over the cycle)
        self.input_loads = tuple(load for load in self.loads if not load.computed)
        self.computed_loads = tuple(load for load in self.loads if load.computed)
        self._input_names = MOTION + tuple(load.name for load in self.input_loads)
        # the input loads by name -> position, and their start values (the lean path)
        self._load_position = {load.name: k for k, load in enumerate(self.input_loads)}
        self._start = {**dict.fromkeys(MOTION, 0.0), **{ld.name: ld.start for ld in self.loads},
                       **(start or {})}
        self._start_loads = tuple(self._start[ld.name] for ld in self.input_loads)
        self._n_loads = len(self.input_loads)
        self._load_name = self.input_loads[0].name if self.input_loads else None
        #: input name -> its unit (the loads over the cycle included)
        self.input_units = {**MOTION_UNITS, **{load.name: load.unit for load in self.loads}}
        # every linkage reports what its moving links put on the frame
        outputs = tuple(outputs) + friction_outputs(self) + tuple(
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
        self._diagnostic_names = tuple(f"gamma_{d.key}" for d in self.dyads) + \
            diagnostics.NAMES
        _check_names(name, {"input": self.input_names, "parameter": tuple(self.parameters),
                            "output": self.output_names,
                            "diagnostic output": self.diagnostic_names})
        #: the real-valued parameters, the arguments of its kernels (a branch or a choice
        #: is structure, as is a friction with every mu 0); none for a linkage built
        #: without a description
        self.kernel_parameters = () if rebuild is None else tuple(
            n for n, v in self.parameters.items() if type(v) is float and (
                friction.active or n not in friction.parameters))
        self.output_info.update(diagnostics.info(self))
        #: solves it: plans, kernels, methods (:class:`~linkage_fmu.solver.Solver`)
        self.solver = Solver(self)
        self._hot = self.solver.hot  # the lean path of solve: [static, moving]

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
        >>> mech.diagnostic_names
        ('gamma_C', 'cond', 'J_red', 'dJ_red')
        >>> sol = mech.solve(0.5, omega=10.0)

        ``gamma_C`` is the angle BCD between the coupler BC (0.35 m) and the rocker CD
        (0.3 m), by the law of cosines from the distance BD (the crank is 0.1 m, D is
        0.4 m from A along x):

        >>> import math
        >>> BD2 = (0.1 * math.cos(0.5) - 0.4) ** 2 + (0.1 * math.sin(0.5)) ** 2
        >>> BCD = math.acos((0.35**2 + 0.3**2 - BD2) / (2 * 0.35 * 0.3))
        >>> bool(abs(sol["gamma_C"] - BCD) < 1e-12), mech.output_info["gamma_C"][0]
        (True, 'rad')
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
        return self._input_names

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
        return MappingProxyType(self._start)

    def _resolve(self, j: Pair) -> Pair:
        a = self.frame if j.a == FRAME else j.a
        if a == OWNER:
            if j.point not in self.owner:
                raise LinkageError(self.name, f"joint {j.name} is shared by two links; "
                                   "attach to a point that belongs to one link")
            a = self.owner[j.point]
        return j.between(a)

    def __repr__(self) -> str:
        params = ", ".join(f"{k}={v!r}" for k, v in self.parameters.items())
        return f"<Mechanism {self.name}({params})>"

    # -- kinematics -------------------------------------------------------------
    def kinematics(self, theta, order: int = 2, xp=None) -> KinematicState:
        """The position of every point and link at the crank angle(s) ``theta``, and
        their first and second derivatives with respect to ``theta``.

        The points are named as the description names them: the frame's points, the
        joints and points the groups place, and each link's centre of mass ``S<link>``
        (``S2`` for link ``2``, ``Scrank`` for a link named ``crank``) where it is off
        the link's point ``ref``; where it is on it, the centre of mass is that point.
        ``mech.cg`` maps each moving link to its centre of mass's point.

        Parameters
        ----------
        theta : float or array_like
            Crank angle(s) [rad], finite.
        order : {0, 1, 2}
            Positions only (0), with the first derivatives (1), and the second (2).
        xp : namespace, optional
            The numbers to compute on (:data:`~linkage_fmu.numerics.SCALAR`,
            :data:`~linkage_fmu.numerics.ARRAY`, :data:`linkage_fmu.precise.MP`);
            default floats for one angle, numpy arrays for many.

        Returns
        -------
        KinematicState
            ``st.p[point]``, ``st.d1[point]``, ``st.d2[point]``: the point's position
            ``(x, y)`` [m] and its derivatives ``(dx/dtheta, dy/dtheta)`` [m/rad] and
            ``(d2x/dtheta2, d2y/dtheta2)`` [m/rad2]; ``st.u[link]``, ``st.w1[link]``,
            ``st.w2[link]``: the link's direction ``(cos phi, sin phi)`` and
            ``dphi/dtheta``, ``d2phi/dtheta2``. At crank speed ``omega`` and
            acceleration ``alpha``, a point's velocity is ``d1 omega``
            (``st.velocity(point, omega)``), its acceleration ``d2 omega**2 + d1
            alpha`` (``st.acceleration(point, omega, alpha)``), a link's angular
            speed ``w1 omega``. For arrays, ``st.invalid`` marks the angles the
            linkage cannot be assembled at (NaN there).

        Raises
        ------
        AssemblyError
            One angle the linkage cannot be assembled at.
        ValueError
            An angle that is not a finite number.

        Examples
        --------
        The four-bar (crank AB 0.1 m, coupler BC 0.35 m, rocker CD 0.3 m, D 0.4 m
        from A along x), its coupler's centre of mass ``S2`` 0.175 m from B along BC:

        >>> import math
        >>> from linkage_fmu import presets
        >>> mech = presets.get("four_bar")
        >>> st = mech.kinematics(0.5)
        >>> sorted(st.p), mech.cg
        (['A', 'B', 'C', 'D', 'S2', 'S3'], {'1': 'A', '2': 'S2', '3': 'S3'})
        >>> [round(v, 6) for v in st.p["B"]] == [round(0.1 * math.cos(0.5), 6),
        ...                                      round(0.1 * math.sin(0.5), 6)]
        True
        >>> (B, C), S2 = (st.p["B"], st.p["C"]), st.p["S2"]
        >>> [round(s - (b + c) / 2, 12) for s, b, c in zip(S2, B, C)]  # mid BC
        [0.0, 0.0]
        >>> [round(v, 6) for v in st.velocity("B", 10.0)]  # B turns at 1 m/s
        [-0.479426, 0.877583]
        >>> round(st.w1["1"], 12), [round(v, 6) for v in st.u["1"]]
        (1.0, [0.877583, 0.479426])
        >>> [round(v, 6) for v in mech.kinematics(0.0, order=0).p["C"]]
        [0.304167, 0.284282]
        """
        if xp is None:
            if np.ndim(theta) == 0:
                xp = SCALAR
                theta = finite_float("theta", theta.item() if isinstance(theta, np.ndarray)
                                     else theta)
            else:
                xp = ARRAY
                theta = finite_array("theta", theta)

        def fail(condition: str, what: str = ""):
            raise AssemblyError(self.name, theta, condition, what)

        st = KinematicState(theta, xp, fail)
        zero = (0.0, 0.0)
        for p, xy in self.frame_points.items():
            st.p[p], st.d1[p], st.d2[p] = xy, zero, zero
        for grp in self.groups:
            grp.position(st)
        if order >= 1:
            for grp in self.groups:
                grp.first(st)
        if order >= 2:
            for grp in self.groups:
                grp.second(st)
        return st

    def reduced_inertia(self, theta, xp=None) -> tuple:
        """The moment of inertia of the whole linkage reduced to the crank and its
        derivative with respect to the crank angle, at the crank angle(s) ``theta``
        [rad; one angle may be text with a unit, ``"30 deg"``]: the kinetic energy of
        the moving links is ``J(theta) * omega**2 / 2``, and with no loads the
        balancing moment is ``J * alpha + dJ / 2 * omega**2``. ``J`` [kg m2] and
        ``dJ`` [kg m2/rad] are floats for a scalar ``theta`` and arrays of its shape
        otherwise (NaN where the linkage cannot be assembled); ``xp`` evaluates on
        another namespace's numbers. The method is
        :func:`linkage_fmu.inertia.reduced_inertia`, which says how.

        Returns
        -------
        J, dJ : float or ndarray
            The reduced inertia [kg m2] and its derivative ``dJ/dtheta`` [kg m2/rad].

        Examples
        --------
        The scotch yoke's block (4 kg) at the end of its 0.1 m crank and its yoke
        (10 kg, at ``0.1 sin(theta)``) give ``J = (4 + 10 cos(theta)**2) 0.1**2`` and
        ``dJ = -10 0.1**2 sin(2 theta)``:

        >>> import math
        >>> from linkage_fmu import presets
        >>> yoke = presets.get("scotch_yoke")
        >>> J, dJ = yoke.reduced_inertia([0.0, math.pi / 4])
        >>> J.round(12).tolist(), dJ.round(12).tolist()
        ([0.14, 0.09], [0.0, -0.1])
        >>> J, dJ = yoke.reduced_inertia("30 deg")
        >>> round(J, 12), round(dJ, 12)
        (0.115, -0.086602540378)
        """
        return inertia.reduced_inertia(self, theta, xp)

    def simulate(self, tau, t, theta0=None, omega0=None, **options):
        """The motion under the crank torque ``tau``: :func:`linkage_fmu.motion.simulate`."""
        return motion.simulate(self, tau, t, theta0, omega0, **options)

    def flywheel(self, omega_mean, Cs, **options):
        """The flywheel for ``Cs`` at ``omega_mean``: :func:`linkage_fmu.flywheel.flywheel`."""
        return flywheel.flywheel(self, omega_mean, Cs, **options)

    # -- the formulas -----------------------------------------------------------
    def evaluate(self, plan, theta, omega, alpha, loads, xp) -> tuple[dict, KinematicState]:
        """The outputs of ``plan`` (and whatever it computes besides) on numbers of the
        namespace ``xp``, and the kinematic state: the one sequence of formulas behind
        every path, floats, arrays, mpmath and the traced kernels.

        ``plan`` (:class:`~linkage_fmu.solver.Plan`) says which outputs, whether the
        scene is static (``omega = alpha = 0``: no derivative kinematics, no inertia)
        and the method (``direct``: the assembled linear system; otherwise group by
        group); the effort alone needs no reactions (virtual power). ``solve`` and
        ``table`` make the plan (``mech.solver.plan``) and call this; use them.

        Examples
        --------
        >>> from linkage_fmu import presets
        >>> from linkage_fmu.numerics import SCALAR
        >>> yoke = presets.get("scotch_yoke")
        >>> plan = yoke.solver.plan(("Mb",), False, "closed_form")
        >>> out, state = yoke.evaluate(plan, 0.5, 10.0, 0.0, [100.0], SCALAR)
        >>> out["Mb"] == yoke.solve(0.5, 10.0, 0.0, 100.0)["Mb"]
        True
        """
        order = 0
        if plan.reactions or plan.effort:
            if not plan.static:
                order = 2
            elif not plan.reactions or self.friction.active or "eta" in plan.outputs or (
                    plan.method != "direct" and not self.effort_on_crank):
                order = 1
        order = max(order, diagnostics.order(self, plan.outputs))
        st = self.kinematics(theta, order, xp)
        R, effort = {}, 0.0
        if plan.reactions or plan.effort:
            if self.computed_loads:  # each computed load: given, or None (computed)
                given = dict(zip(plan.given, loads[len(self.input_loads):]))
                inputs = iter(loads)
                loads = [given.get(ld.name) if ld.computed else next(inputs)
                         for ld in self.loads]
            W = wrenches(self, st, omega, alpha, loads, plan.static)
            R, effort = friction.solve(self, st, W, plan, omega, xp)
            if "eta" in plan.outputs and self.friction.joints:  # what each source puts in
                R.sources = powers(self, st, omega, alpha, loads, plan.static)
        out = {}
        for name, fn in self.output_functions:
            if name in plan.outputs:
                out[name] = fn(R, effort, st)
        if plan.diagnostics:
            out.update(diagnostics.values(self, st, plan.outputs))
        return out, st

    # -- inputs -----------------------------------------------------------------
    def inputs(self, omega=None, alpha=None, loads: Sequence = (),
               named: dict | None = None) -> tuple[list, tuple]:
        """``[omega, alpha, *input loads, *given computed loads]`` from the values given
        (the input loads positionally in :attr:`input_loads` order, or by name; a load
        over the cycle by name to override it), each input not given taking its start
        value (:attr:`start`), text (a number with a unit, an expression: ``"1800 rpm"``,
        ``"2 * pi * 30 rad/s"``) taken in SI (:func:`~.expressions.evaluate`); and the
        names of the computed loads given.

        Examples
        --------
        >>> from linkage_fmu import presets
        >>> presets.get("four_bar").inputs(alpha=2.0, named={"load": 3.0})
        ([10.0, 2.0, 3.0], ())
        """
        if not named and len(loads) == len(self.input_loads) and omega is not None and \
                alpha is not None:
            out, given = [omega, alpha, *loads], ()
        else:
            out, given = self._named(omega, alpha, loads, named or {})
        for k, value in enumerate(out):
            if isinstance(value, str):  # a number with a unit, an expression
                name = (self.input_names[1:] + given)[k]
                out[k] = evaluate(value, self.input_units[name], name)
        return out, given

    def _named(self, omega, alpha, loads: Sequence, named: dict) -> tuple[list, tuple]:
        names = [load.name for load in self.input_loads]
        if len(loads) > len(names):
            raise InputTypeError(f"{self.name} has {len(names)} input load(s) "
                                 f"({', '.join(names)}), got {len(loads)} positional load "
                                 "values")
        values = dict(zip(names, loads))
        known = {load.name for load in self.loads}
        for key, value in named.items():
            if key not in known:
                raise InputTypeError(f"{self.name} has no input {key!r}; its inputs are: "
                                     + ", ".join(self.input_names + tuple(
                                         ld.name for ld in self.computed_loads)))
            if key in values:
                raise InputTypeError(f"load {key} is given twice")
            values[key] = value
        given = tuple(ld.name for ld in self.computed_loads if ld.name in values)
        return [self.start["omega"] if omega is None else omega,
                self.start["alpha"] if alpha is None else alpha,
                *(values.get(n, self.start[n]) for n in names),
                *(values[n] for n in given)], given

    # -- solving (the solver's public interface, here for convenience) -----------
    def solve(self, theta, omega=None, alpha=None, *loads, method: str = "closed_form",
              outputs: Iterable[str] | None = None, **named_loads) -> Solution:
        """Joint reactions, balancing effort and diagnostics at one or many states
        (:meth:`Solver.solve <linkage_fmu.solver.Solver.solve>`).

        Parameters
        ----------
        theta : float, str or array_like
            Crank angle [rad]; one angle may be text with a unit (``"30 deg"``).
        omega, alpha : float, str or array_like, optional
            Crank speed [rad/s] and acceleration [rad/s2] (``"1800 rpm"``); default the
            start values (:attr:`start`).
        *loads : float, str or array_like
            Each input load's magnitude [N or N.m], in :attr:`input_names` order.
        method : {'closed_form', 'direct', 'interpreted'}
            ``closed_form`` (default): group by group from the last group back to the
            crank, one state by its compiled kernel; ``direct``: the assembled linear
            system of the whole linkage (the reference); ``interpreted``: the closed
            form's formulas step by step (a second reference).
        outputs : iterable of str, optional
            The names wanted, of :attr:`output_names` and :attr:`diagnostic_names`
            (default all); asking for the balancing effort alone skips the reactions.
        **named_loads : float, str or array_like
            The input loads by name (a preset's one load is ``load``), or a load given
            over the cycle by name, which replaces what it computes. A load not given
            takes its start value.

        Returns
        -------
        Solution
            Output name -> value, the outputs then the diagnostics: floats for one
            state; for arrays an :class:`~linkage_fmu.solver.ArraySolution` of the
            inputs' broadcast shape, NaN at a state without outputs, whose ``valid``
            and ``status`` say which and why.

        Raises
        ------
        AssemblyError
            One state the linkage cannot be assembled at.
        SingularPositionError
            One state at which the equations are singular (a toggle, a dead centre).
        SelfLockingError
            One state that friction locks: no finite effort moves the linkage.
        OverflowInputError
            One state of finite inputs whose outputs overflow.
        ValueError
            An unknown method or output, an input that is not a finite number (or an
            unknown unit), or inputs that do not broadcast to one shape.
        TypeError
            An unknown input name, a load given twice, or too many loads.

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
        if outputs is None and method == "closed_form":
            # the lean path: plain numbers, every output, the compiled kernel once hot
            # (Solver.hot). It returns only the kernel's Solution, the floats the general
            # path returns for the same inputs; anything else (text, arrays, a state
            # without outputs, a kernel not yet hot, no compiler) goes on to the solver,
            # which decides and raises
            w = self._start["omega"] if omega is None else omega
            a = self._start["alpha"] if alpha is None else alpha
            hot = None
            if type(w) in _LEAN and type(a) in _LEAN:  # the kernel checks every input
                hot = self._hot[1] if w != 0.0 or a != 0.0 else self._hot[0]
            if hot is not None:
                if named_loads and len(named_loads) == 1 and not loads and self._n_loads == 1:
                    # a linkage's one load by name (None for another name: the kernel
                    # refuses it, the general path says why)
                    r = hot(theta, w, a, named_loads.get(self._load_name))
                else:
                    x = loads if not named_loads and len(loads) == self._n_loads else \
                        self._lean_loads(loads, named_loads)
                    r = None if x is None else \
                        hot(theta, w, a, x[0]) if len(x) == 1 else hot(theta, w, a, *x)
                if type(r) is Solution:
                    return r
                if r is None:  # ints or numpy floats, taken as floats
                    x = self._lean_loads(loads, named_loads)
                    x = None if x is None else _floats((theta, w, a, *x))
                    if x is not None and type(r := hot(*x)) is Solution:
                        return r
        return self.solver.solve(theta, omega, alpha, *loads, method=method, outputs=outputs,
                                 **named_loads)

    def _lean_loads(self, loads: tuple, named: dict) -> tuple | list | None:
        """The input loads of :meth:`solve`'s lean path from those given positionally
        (``loads``) and by name (``named``), each not given at its start value; None
        where the general path must decide (too many, unknown names, twice given, a
        load over the cycle given)."""
        position = self._load_position
        if not named and len(loads) == len(position):
            return loads
        if not named and not loads:
            return self._start_loads
        if not loads and len(named) == len(position):  # each by name
            x = []
            for name in position:
                value = named.get(name)
                if value is None:
                    return None
                x.append(value)
            return x
        if len(loads) > len(position):
            return None
        x = list(loads) + list(self._start_loads[len(loads):])
        for name, value in named.items():
            k = position.get(name)
            if k is None or k < len(loads):
                return None
            x[k] = value
        return x

    def table(self, theta, omega=None, alpha=None, *loads, method: str = "closed_form",
              outputs: Iterable[str] | None = None, **named_loads):
        """:meth:`solve` over the crank angles ``theta`` as a pandas DataFrame, one
        column per output (:meth:`Solver.table <linkage_fmu.solver.Solver.table>`).

        Parameters
        ----------
        theta : float or array_like
            Crank angle(s) [rad], the table's index (named ``theta``).
        omega, alpha, *loads, method, outputs, **named_loads
            As for :meth:`solve`; each broadcasts against ``theta``.

        Returns
        -------
        pandas.DataFrame
            One row per angle, one column per output wanted (the outputs, then the
            diagnostics); a row the linkage has no outputs at (it cannot be assembled
            there, a singular or locked position) is NaN.

        Raises
        ------
        ValueError, TypeError
            As :meth:`solve` for the inputs; a state without outputs raises nothing
            (its row is NaN).

        Examples
        --------
        >>> import numpy as np
        >>> from linkage_fmu import presets
        >>> yoke = presets.get("scotch_yoke")
        >>> df = yoke.table(np.radians([0.0, 60.0]), omega=10.0, load=400.0,
        ...                 outputs=["Mb", "F23y"])
        >>> df.round(4)
                      Mb      F23y
        theta
        0.000000  40.0000  400.0000
        1.047198  15.6699  313.3975

        A crank too long to turn a revolution: the rows it cannot reach are NaN.

        >>> rocker = presets.get("four_bar", l_AB=0.3)
        >>> rocker.table([0.0, 3.0], omega=10.0, outputs=["Mb"])["Mb"].isna().tolist()
        [False, True]
        """
        return self.solver.table(theta, omega, alpha, *loads, method=method, outputs=outputs,
                                 **named_loads)

    def kernel(self, outputs: Iterable[str] | None = None, static: bool = False):
        """The traced kernel of the plan ``(outputs, static)``: :meth:`.Solver.kernel`."""
        return self.solver.kernel(outputs, static)


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


"""A mechanism: a crank, ordered Assur groups, link inertia, loads and named outputs.

Data flow is one way: inputs ``(theta, omega, alpha, *loads)`` -> :class:`KinematicState`
-> load wrenches -> reactions -> named outputs. :meth:`Mechanism.solve` decides what a
scene needs and computes only that. A mechanism is usually built from a
:class:`~linkage_fmu.spec.Description` (a description file, or a preset's).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Mapping
from dataclasses import dataclass
from types import SimpleNamespace
from typing import Any, Iterable, Sequence

import numpy as np

from . import kinetostatics, numerics
from .errors import AssemblyError, OverflowInputError, SingularPositionError
from .kernels import finite
from .groups import FRAME, OWNER, Crank, Group, KinematicState, LinkPoint
from .loads import Load, wrenches
from .numerics import ARRAY, SCALAR, finite_array, finite_float
from .outputs import EffortOutput

#: closed_form: the traced kernel (scalars) or the group formulas (arrays); direct: the
#: assembled linear system (the reference); interpreted: the group formulas step by step
METHODS = ("closed_form", "direct", "interpreted")
#: the inputs every linkage has; its loads follow them
MOTION = ("theta", "omega", "alpha")
#: the kernel of a plan that could not be traced: every state is interpreted
_NO_KERNEL = SimpleNamespace(call=lambda *inputs: None, checked=(), index={},
                             count=lambda: None)
#: states per block of an array solve: its temporaries stay in the CPU caches
CHUNK = 8192


@dataclass(frozen=True)
class Body:
    """A moving link: mass, moment of inertia about its centre of mass ``S``, and where
    ``S`` is in the link's own frame, measured from the link's point ``ref``: ``along``
    the link's direction and ``across`` to its left (counter-clockwise); or, with
    ``distance``, that far from ``ref`` in the direction ``angle`` counter-clockwise
    from the link's.

    Examples
    --------
    >>> Body("2", mass=2.0, inertia=0.02, ref="B", along=0.175).cg
    'S2'
    >>> Body("2", mass=-1.0, ref="B")
    Traceback (most recent call last):
    ...
    ValueError: mass of body '2' must be a finite number >= 0, got -1.0
    """

    name: str
    mass: float = 0.0
    inertia: float = 0.0
    ref: str = ""
    along: float = 0.0
    across: float = 0.0
    distance: float | None = None  # given: the centre of mass is placed by distance/angle
    angle: float = 0.0

    def __post_init__(self):
        if any(hasattr(getattr(self, a), "traced") for a in ("mass", "inertia", "along",
                                                               "across", "distance", "angle")):
            return  # traced parameters: their values were checked when they were floats
        for attr in ("mass", "inertia"):
            v = getattr(self, attr)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v >= 0):
                raise ValueError(
                    f"{attr} of body {self.name!r} must be a finite number >= 0, got {v!r}")
        for attr in ("along", "across", "distance", "angle"):
            v = getattr(self, attr)
            if v is None and attr == "distance":
                continue
            if not (isinstance(v, (int, float)) and math.isfinite(v)):
                raise ValueError(f"{attr} of the centre of mass of body {self.name!r} must be "
                                 f"a finite number, got {v!r}")
        if self.distance is not None and (self.along or self.across):
            raise ValueError(f"body {self.name!r}: give the centre of mass as along/across or "
                             "as distance/angle, not both")
        if not self.ref:
            raise ValueError(f"body {self.name!r} needs the point 'ref' its centre of mass is measured from")

    @functools.cached_property
    def offset(self) -> float:
        """Distance of the centre of mass from ``ref``."""
        if self.distance is not None:
            return abs(self.distance)
        return numerics.hypot(self.along, self.across)

    @functools.cached_property  # read for every body at every state
    def cg(self) -> str:
        """Name of the point at the centre of mass."""
        return self.ref if self.offset == 0.0 else f"S{self.name}"

    def cg_point(self) -> LinkPoint:
        """The centre of mass as a point fixed on the link."""
        if self.distance is not None:
            return LinkPoint(self.name, self.ref, self.cg, distance=self.distance,
                             angle=self.angle)
        return LinkPoint(self.name, self.ref, self.cg, self.along, self.across)


@dataclass(frozen=True)
class Effort:
    """The balancing effort: a moment on link ``body`` (``direction=None``), or a force
    on ``body`` at ``point`` along the unit vector ``direction``."""

    name: str
    body: str
    point: str = ""
    direction: tuple | None = None


class Solution(Mapping):
    """Outputs of :meth:`Mechanism.solve`: name -> float (scalar inputs) or ndarray.

    Attributes
    ----------
    valid : bool or ndarray of bool
        Which states could be assembled (always True for scalar inputs, which raise
        :class:`~linkage_fmu.AssemblyError` instead).
    """

    __slots__ = ("_values", "_index", "valid")

    def __init__(self, values, valid, index: dict | None = None):
        # a dict, or a tuple with the name -> position map its kernel shares
        if index is None:
            index = {name: i for i, name in enumerate(values)}
            values = tuple(values.values())
        self._values, self._index, self.valid = values, index, valid

    def __getitem__(self, name: str):
        return self._values[self._index[name]]

    def __iter__(self):
        return iter(self._index)

    def __len__(self) -> int:
        return len(self._index)

    def __eq__(self, other):
        return dict(self) == dict(other) if isinstance(other, Mapping) else NotImplemented

    def __repr__(self) -> str:
        body = ", ".join(f"{k}={v!r}" for k, v in self.items())
        return f"Solution({body})"


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
        Output declarations (:mod:`linkage_fmu.outputs`), in output order.
    loads : sequence of Load
        The input loads, each an input of :meth:`solve` by its name.
    g : float
        Gravity along -y.
    parameters : dict, optional
        The parameter values it was built from.
    description : Description, optional
        What it was built from (for FMUs and the command line).
    """

    def __init__(self, name: str, frame: str, frame_points: dict, groups: Sequence,
                 bodies: Sequence[Body], effort: Effort, outputs: Sequence,
                 loads: Sequence[Load], g: float, parameters: dict | None = None,
                 description=None):
        self.name, self.frame = name, frame
        self.g = numerics.real(g)
        self.frame_points = {k: (numerics.real(x), numerics.real(y))
                             for k, (x, y) in frame_points.items()}
        self.bodies = tuple(bodies)
        self.effort = effort
        self.loads = tuple(loads)
        self.parameters = dict(parameters or {})
        self.description = description
        for grp in groups:
            if not isinstance(grp, Group):
                raise TypeError(f"{name}: {grp!r} is not a group (a subclass of "
                                "linkage_fmu.groups.Group)")
        if not groups or not isinstance(groups[0], Crank):
            raise ValueError(f"{name}: the first group must be the Crank")
        placed = set(self.frame_points)
        owner = {p: frame for p in self.frame_points}
        for grp in groups:
            missing = [p for p in grp.needs if p not in placed]
            if missing:
                raise ValueError(f"{name}: {type(grp).__name__} needs {missing} placed before it")
            placed.update(grp.places)
            owner.update(grp.owners)
        links = [link for grp in groups for link in grp.links]
        body_names = [b.name for b in self.bodies]
        if sorted(links) != sorted(body_names):
            raise ValueError(f"{name}: bodies {body_names} do not match the moving links {links}")
        for load in self.loads:
            if load.body not in body_names:
                raise ValueError(f"{name}: load {load.name} acts on {load.body!r}, not a moving link")
        cg_points = [b.cg_point() for b in self.bodies if b.cg != b.ref]
        self.groups = tuple(groups) + tuple(cg_points)
        self.cg = {b.name: b.cg for b in self.bodies}
        self.owner = owner
        self.joints = tuple(self._resolve(j) for grp in groups for j in grp.joints)
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
        #: the inputs of :meth:`solve`: theta, omega, alpha, then each load by name
        self.input_names = MOTION + tuple(load.name for load in self.loads)
        self._outputs = tuple((o.name, o.bind(self)) for o in outputs)
        #: output name -> (unit, description), diagnostics included
        self.output_info = {o.name: (o.unit, o.description) for o in outputs}
        self._effort_outputs = {o.name for o in outputs if isinstance(o, EffortOutput)}
        self.output_names = tuple(o.name for o in outputs)
        self.diagnostic_names = tuple(f"mu_{d.key}" for d in self.dyads) + ("cond",)
        self._all_names = self.output_names + self.diagnostic_names  # one object: fast keys
        self._plans: dict = {}  # wanted outputs -> what they need (see _plan)
        self._finite_names: dict = {}  # wanted outputs -> those that must be finite
        self._kernels: dict = {}  # (wanted outputs, static) -> Kernel, or _NO_KERNEL
        self._kernel_errors: dict = {}  # (wanted outputs, static) -> why it has none
        #: (static, moving): the compiled kernel of all outputs and its index, once hot
        self._fast: list = [None, None]
        for d in self.dyads:
            self.output_info[f"mu_{d.key}"] = (
                "rad", f"transmission angle of the dyad at {d.key} (0 or pi: toggle)")
        self.output_info["cond"] = (
            "1", "estimated condition number of the outputs, including the scale of the "
            "centre-of-mass offsets: relative rounding error about cond x 1e-16 (inf: singular)")

    def _resolve(self, j):
        a = self.frame if j.a == FRAME else j.a
        if a == OWNER:
            if j.point not in self.owner:
                raise ValueError(f"{self.name}: joint {j.name} is shared by two links; "
                                 "attach to a point that belongs to one link")
            a = self.owner[j.point]
        return j._replace(a=a)

    def __repr__(self) -> str:
        params = ", ".join(f"{k}={v!r}" for k, v in self.parameters.items())
        return f"<Mechanism {self.name}({params})>"

    # -- kinematics -------------------------------------------------------------
    def kinematics(self, theta, order: int = 2) -> KinematicState:
        """Positions (``order=0``), plus first (1) and second (2) derivative coefficients.

        Examples
        --------
        >>> from linkage_fmu import presets
        >>> st = presets.get("four_bar").kinematics(0.0, order=1)
        >>> [round(v, 6) for v in st.p["C"]]
        [0.304167, 0.284282]
        """
        if np.ndim(theta) == 0:
            xp = SCALAR
            theta = finite_float("theta", _item(theta))
        else:
            xp = ARRAY
            theta = finite_array("theta", theta)
        return self._kinematics(theta, xp, order)

    def _kinematics(self, theta, xp, order: int) -> KinematicState:
        """Kinematics to ``order`` on numbers of the namespace ``xp``."""
        groups = self.groups

        def fail(condition):
            raise AssemblyError(self.name, theta, condition)

        st = KinematicState(theta, xp, fail)
        zero = (0.0, 0.0)
        for p, xy in self.frame_points.items():
            st.p[p], st.d1[p], st.d2[p] = xy, zero, zero
        for grp in groups:
            grp.position(st)
        if order >= 1:
            for grp in groups:
                grp.first(st)
        if order >= 2:
            for grp in groups:
                grp.second(st)
        return st

    # -- solving ----------------------------------------------------------------
    def solve(self, theta, omega=0.0, alpha=0.0, *loads, method: str = "closed_form",
              outputs: Iterable[str] | None = None, **named_loads) -> Solution:
        """Joint reactions, balancing effort and diagnostics at one or many states.

        Parameters
        ----------
        theta, omega, alpha : float or array_like
            Crank angle [rad], speed [rad/s] and acceleration [rad/s2].
        *loads, **named_loads : float or array_like
            The magnitude of each load [N or N.m], in the order of :attr:`loads` or by
            name (a preset's single load is ``load``); a load not given is zero.
        method : {'closed_form', 'direct', 'interpreted'}
            The closed form, group by group from the last group back to the crank (for
            one state, its traced kernel: :meth:`kernel`); the assembled linear system
            (the reference); or the closed form's group formulas run step by step (a
            second reference).
        outputs : iterable of str, optional
            Names wanted (default: all of :attr:`output_names` and
            :attr:`diagnostic_names`). Asking only for the balancing effort skips the
            reactions; a static scene skips velocities and accelerations.

        Returns
        -------
        Solution
            Floats for scalar inputs; arrays of the broadcast input shape otherwise.

        Raises
        ------
        AssemblyError
            Scalar ``theta`` at which the linkage cannot be assembled.
        SingularPositionError
            Scalar state at which the equations are exactly singular.

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
        if outputs is None and method == "closed_form" and type(omega) is float and \
                type(alpha) is float and not named_loads and len(loads) == len(self.loads):
            fast = self._fast[omega != 0.0 or alpha != 0.0]
            if fast is not None:  # a compiled kernel that checks its inputs: FMU steps
                r = fast[0](theta, omega, alpha, *loads)
                if r is not None:
                    return Solution(r, True, fast[1])
        if method not in METHODS:
            raise ValueError(f"method must be one of {METHODS}, got {method!r}")
        wanted = self._wanted(outputs)
        args = (theta, omega, alpha, *self.load_values(loads, named_loads))
        names = self.input_names
        if type(theta) is float and type(omega) is float and type(alpha) is float and \
                all(type(a) is float for a in args[3:]) and math.isfinite(sum(args)):
            return self._one_state(args, method, wanted)  # finite floats: FMU steps
        if all(np.ndim(a) == 0 for a in args):
            values = [finite_float(n, _item(a)) for n, a in zip(names, args)]
            return self._one_state(values, method, wanted)
        given = [finite_array(n, a) for n, a in zip(names, args)]
        try:
            arrays = np.broadcast_arrays(*given)
        except ValueError:
            raise ValueError(", ".join(names) + " must broadcast to one shape, got "
                             + ", ".join(str(np.shape(a)) for a in given)) from None
        shape = arrays[0].shape
        flat = [a.reshape(-1) for a in arrays]  # views where possible: no scalar copied n times
        n = flat[0].size
        if method == "closed_form" and n:
            solved = self._compiled_arrays(given, flat, shape, n, wanted)
            if solved is not None:
                return solved
            method = "interpreted"  # no C compiler: numpy
        out = {name: np.empty(n) for name in wanted}
        valid = np.empty(n, dtype=bool)
        self._interpreted_arrays(flat, method, wanted, out, valid, slice(0, n))
        return Solution({k: v.reshape(shape) for k, v in out.items()}, valid.reshape(shape))

    def _interpreted_arrays(self, flat, method, wanted, out, valid, rows) -> None:
        """The group formulas on numpy arrays over the states ``rows`` of ``flat``
        (a slice, or an index array), in blocks that stay in the CPU caches (the
        formulas make many temporaries per state); results into ``out`` and ``valid``."""
        if isinstance(rows, slice):
            parts = (slice(i, min(i + CHUNK, rows.stop)) for i in range(rows.start, rows.stop, CHUNK))
        else:
            parts = (rows[i:i + CHUNK] for i in range(0, rows.size, CHUNK))
        with np.errstate(divide="ignore", invalid="ignore"):
            for part in parts:
                values = self._solve(*(a[part] for a in flat[:3]), [a[part] for a in flat[3:]],
                                     ARRAY, method, wanted)
                valid[part] = values.pop(" valid")
                for name, v in values.items():
                    out[name][part] = v

    def _compiled_arrays(self, given, flat, shape, n, wanted):
        """The compiled kernel of the plan over every state, the interpreted formulas
        for the states it hands back; None without a compiled kernel."""
        omega, alpha = flat[1], flat[2]
        static = not (omega.any() or alpha.any())
        k = self._kernels.get((wanted, static)) or self._kernel_or_none(wanted, static)
        array = k.array() if k is not _NO_KERNEL else None
        if array is None:
            return None
        # one value, or the whole flat array: a broadcast scalar is never copied n times
        inputs = [g.reshape(1) if g.size == 1 else f for g, f in zip(given, flat)]
        values, valid = array(inputs, n)
        back = np.flatnonzero(~valid)
        if back.size:  # cannot be assembled, singular, or another branch: the formulas decide
            out = dict(zip(wanted, values))
            self._interpreted_arrays(flat, "interpreted", wanted, out, valid, back)
        return Solution({name: v.reshape(shape) for name, v in zip(wanted, values)},
                        valid.reshape(shape))

    def load_values(self, positional: tuple, named: dict, start: bool = False) -> list:
        """The load values in :attr:`loads` order from positional and named arguments; a
        load not given is 0, or with ``start`` its start value.

        Examples
        --------
        >>> from linkage_fmu import presets
        >>> presets.get("four_bar").load_values((), {"load": 2.0})
        [2.0]
        """
        if not named and len(positional) == len(self.loads):
            return positional
        names = [load.name for load in self.loads]
        if len(positional) > len(names):
            raise TypeError(f"{self.name} has {len(names)} load(s) ({', '.join(names)}), got "
                            f"{len(positional)} positional load values")
        values = dict(zip(names, positional))
        for key, value in named.items():
            if key not in names:
                raise TypeError(f"{self.name} has no input {key!r}; its inputs are: "
                                + ", ".join(self.input_names))
            if key in values:
                raise TypeError(f"load {key} is given twice")
            values[key] = value
        return [values.get(load.name, load.start if start else 0.0) for load in self.loads]

    def table(self, theta, omega=0.0, alpha=0.0, *loads, method: str = "closed_form",
              outputs: Iterable[str] | None = None, **named_loads):
        """:meth:`solve` over ``theta`` as a pandas DataFrame, one column per output.

        Examples
        --------
        >>> from linkage_fmu import presets
        >>> df = presets.get("scotch_yoke").table([0.0, 1.0], omega=10.0, load=400.0,
        ...                                       outputs=("Mb",))
        >>> list(df.columns), df.index.name
        (['Mb'], 'theta')
        """
        import pandas as pd

        theta = np.atleast_1d(np.asarray(theta, dtype=float))
        sol = self.solve(theta, omega, alpha, *loads, method=method, outputs=outputs,
                         **named_loads)
        index = pd.Index(np.broadcast_to(theta, np.shape(next(iter(sol.values())))).ravel(),
                         name="theta")
        return pd.DataFrame({k: np.ravel(v) for k, v in sol.items()}, index=index)

    def _wanted(self, outputs) -> tuple:
        names = self._all_names
        if outputs is None:
            return names
        if type(outputs) is tuple and outputs in self._plans:  # validated before
            return outputs
        wanted = (outputs,) if isinstance(outputs, str) else tuple(outputs)
        for name in wanted:
            if name not in names:
                raise ValueError(f"{self.name} has no output {name!r}; its outputs are: "
                                 + ", ".join(names))
        return wanted

    def _checked_outputs(self, wanted: tuple) -> tuple:
        """The names in ``wanted`` that must be finite: the outputs, not the diagnostics
        (``cond`` is infinite at a toggle)."""
        names = self._finite_names.get(wanted)
        if names is None:
            names = self._finite_names[wanted] = tuple(
                n for n in wanted if n in self.output_info and n not in self.diagnostic_names)
        return names

    def _plan(self, wanted: tuple) -> tuple:
        """What ``wanted`` needs: (effort, reactions, diagnostics), worked out once."""
        plan = self._plans.get(wanted)
        if plan is None:
            diag = set(self.diagnostic_names)
            plan = (any(n in self._effort_outputs for n in wanted),
                    any(n not in diag and n not in self._effort_outputs for n in wanted),
                    bool(diag.intersection(wanted)))
            self._plans[wanted] = plan
        return plan

    def kernel(self, outputs: Iterable[str] | None = None, static: bool = False):
        """The traced kernel of the plan ``(outputs, static)``, made on first use.

        ``kernel(theta, omega, alpha, *loads)`` returns the outputs as a tuple of floats,
        or None at a state it does not take (see :class:`~linkage_fmu.kernels.Kernel`).
        """
        wanted = self._wanted(outputs)
        self._plan(wanted)  # remember the validated names
        k = self._kernels.get((wanted, static))
        if k is None or k is _NO_KERNEL:
            if k is _NO_KERNEL:  # traced before, without a witness: say so at once
                raise self._kernel_errors[(wanted, static)]
            from .kernels import trace_kernel

            try:
                k = self._kernels[(wanted, static)] = trace_kernel(self, wanted, static)
            except ValueError as err:
                self._kernels[(wanted, static)] = _NO_KERNEL
                self._kernel_errors[(wanted, static)] = err
                raise
        return k

    def _one_state(self, values, method: str, wanted: tuple) -> Solution:
        """One state of finite floats: the kernel's tuple, or the interpreted formulas."""
        if method == "closed_form":
            static = values[1] == 0.0 and values[2] == 0.0
            k = self._kernels.get((wanted, static)) or self._kernel_or_none(wanted, static)
            try:
                r = k.call(*values)
            except (ArithmeticError, ValueError):  # a division by zero, math range error
                r = None
            k.count()  # a hot plan is compiled
            if wanted is self._all_names and k is not _NO_KERNEL and k.compiled:
                self._fast[not static] = (k.call, k.index)
            if r is not None and (math.isfinite(sum(r)) or finite([r[i] for i in k.checked])):
                return Solution(r, True, k.index)
            # the interpreted formulas decide: they raise the exact error, or compute
            # the state the trace did not take
            method = "interpreted"
        return Solution(self._solve_scalar(values, method, wanted), True)

    def _kernel_or_none(self, wanted: tuple, static: bool):
        try:
            return self.kernel(wanted, static)
        except ValueError:  # no witness state: this plan stays interpreted
            return _NO_KERNEL

    def _solve_scalar(self, values, method: str, wanted: tuple) -> dict:
        """One state of finite floats ``(theta, omega, alpha, *loads)``; names in
        ``wanted`` must be outputs of this mechanism (not checked here)."""
        try:
            return self._solve(values[0], values[1], values[2], values[3:], SCALAR, method,
                               wanted)
        except ZeroDivisionError:
            pass
        theta = values[0]
        try:  # a finite condition: the position is fine, the inputs overflow
            st = self._kinematics(theta, SCALAR, 0 if self.effort_on_crank else 1)
            cond = self._diagnostics(st, ("cond",))["cond"]
        except ZeroDivisionError:
            cond = math.inf
        if math.isfinite(cond):
            inputs = ", ".join(f"{n} = {v!r}" for n, v in zip(self.input_names, values))
            raise OverflowInputError(self.name, f"the outputs overflow float64 at {inputs}: "
                                     "an input is too large in magnitude")
        raise SingularPositionError(self.name, theta, self._singular_detail(theta))

    def _solve(self, theta, omega, alpha, loads, xp, method, wanted) -> dict:
        static = (omega == 0.0 and alpha == 0.0) if xp.scalar else not (omega.any() or alpha.any())
        out, st = self._compute(theta, omega, alpha, loads, xp, method, wanted, static)
        if xp.scalar:
            # one finite sum: every term is finite (a sum that overflows is checked term
            # by term); a non-finite output means singular or overflowing: _solve_scalar
            if not math.isfinite(sum(out[n] for n in self._checked_outputs(wanted))) and \
                    not all(math.isfinite(out[n]) for n in self._checked_outputs(wanted)):
                raise ZeroDivisionError
            return {n: float(out[n]) for n in wanted}
        valid = ~st.invalid if st.invalid is not None else np.ones(theta.shape, bool)
        out = {n: out[n] for n in wanted}
        out[" valid"] = valid
        return out

    def _compute(self, theta, omega, alpha, loads, xp, method, wanted,
                 static) -> tuple[dict, KinematicState]:
        """The outputs ``wanted`` (and whatever the plan computes besides) on numbers of
        the namespace ``xp``, and the kinematic state; ``static`` says omega = alpha = 0.
        The one sequence of formulas behind every path: floats, arrays, mpmath and the
        traced kernels (:mod:`linkage_fmu.kernels`)."""
        need_effort, need_reactions, need_diagnostics = self._plan(wanted)
        # kinematic order the scene needs
        order = 0
        if need_reactions or need_effort:
            if not static:
                order = 2
            elif not need_reactions or (method == "closed_form" and not self.effort_on_crank):
                order = 1
        if "cond" in wanted and not self.effort_on_crank:
            order = max(order, 1)
        st = self._kinematics(theta, xp, order)
        R, effort = {}, 0.0
        if need_reactions or need_effort:
            W = wrenches(self, st, omega, alpha, loads, static)
            if need_reactions and method == "direct":
                R, effort = kinetostatics.direct(self, st, W, 1 if xp.scalar else theta.size)
                if xp.scalar:
                    R = {k: (float(a[0]), float(b[0])) for k, (a, b) in R.items()}
                    effort = float(effort[0])
            elif need_reactions:
                R, effort = kinetostatics.closed_form(self, st, W)
            else:
                effort = kinetostatics.virtual_effort(self, st, W)
        out = {}
        for name, fn in self._outputs:
            if name in wanted:
                out[name] = fn(R, effort, st)
        if need_diagnostics:
            out.update(self._diagnostics(st, wanted))
        return out, st

    def _diagnostics(self, st: KinematicState, wanted) -> dict:
        out = {}
        cond = self.offset_scale  # 1.0 unless a centre of mass lies beyond length_scale
        for d in self.dyads:
            mu, kappa = d.transmission(st, self.length_scale)
            out[f"mu_{d.key}"] = mu
            # kappa twice: the dyad's position amplifies rounding by kappa, and its
            # equilibrium (whose forces grow like kappa) amplifies that angle error again
            cond = cond * kappa * kappa
        if not self.effort_on_crank:
            # effort on another link/slider: its own motion q' divides the power balance
            q = st.xp.abs(kinetostatics.effort_coefficient(self, st))
            scale = 1.0 if self.effort.direction is None else self.crank.length
            if st.xp.scalar:
                cond = cond * scale / q if q else math.inf
            else:
                cond = cond * scale / q
        if not st.xp.scalar and st.invalid is not None:
            cond = np.where(st.invalid, np.nan, cond)
        out["cond"] = cond
        return {k: v for k, v in out.items() if k in wanted}

    def _singular_detail(self, theta: float) -> str:
        st = self._kinematics(theta, SCALAR, 0)
        parts = [f"mu_{d.key} = {d.transmission(st, self.length_scale)[0]:.3g} rad"
                 for d in self.dyads]
        return ("the equations have no unique solution (transmission angles: "
                + ", ".join(parts) + "); the balancing effort or reactions are unbounded")


def _item(x: Any) -> Any:
    return x.item() if isinstance(x, np.ndarray) else x

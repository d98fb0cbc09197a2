"""The errors the package raises, all of them a :class:`LinkageFmuError`: for states a
linkage cannot take, each with its :class:`Reason`, for a linkage or a part of it that
cannot be as given (an output, a load, a parameter), which name the linkage or the part
as data (a description says where in its file the part is), and for a value or a type
it cannot take, a computation it cannot finish, a package it cannot import.

Each is also the builtin error it has always been (a ``ValueError``, a ``TypeError``, a
``RuntimeError``, an ``ImportError``), so that ``except ValueError`` still catches it.
The module imports nothing of the package, so that every module, the kernels included,
can raise its errors.
"""

from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class Reason:
    """Why a guard fails: ``kind`` is ``'assembly'`` (the state cannot be assembled),
    ``'singular'`` (the reactions are unbounded), ``'locking'`` (friction locks the
    linkage: no finite balancing effort), ``'parameter'`` (a check of the
    parameter step) or ``'branch'`` (the state takes a branch the trace did not), and
    ``what`` says which condition, without numbers.

    Examples
    --------
    >>> Reason("assembly", "the dyad B-C-D cannot close").text
    'the linkage cannot be assembled: the dyad B-C-D cannot close'
    """

    kind: str
    what: str = ""

    @property
    def text(self) -> str:
        """The reason as the FMUs log it, the same words in every flavour."""
        head = {"assembly": "the linkage cannot be assembled",
                "singular": "the linkage is at a singular position",
                "parameter": "the parameter set is invalid",
                "branch": "the state takes another branch than the kernel was traced on",
                "locking": "friction locks the linkage",
                "overflow": "the outputs overflow float64"}[self.kind]
        return f"{head}: {self.what}" if self.what else head


class LinkageFmuError(Exception):
    """The base of every error the package raises: one ``except`` catches them all, and
    leaves the errors of other code alone.

    Examples
    --------
    >>> from linkage_fmu import presets, LinkageFmuError
    >>> mech = presets.get("four_bar", l_AB=0.3)   # crank too long to turn fully
    >>> try:
    ...     mech.solve(3.1)
    ... except LinkageFmuError as err:
    ...     print(type(err).__name__, isinstance(err, ValueError))
    AssemblyError True
    """


class InputError(LinkageFmuError, ValueError):
    """A value given to the package that it cannot take: an argument, an option or a
    value of a file out of its range or not of its kind; the message names it and says
    why.

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> try:
    ...     presets.get("no_such_linkage")
    ... except InputError as err:
    ...     print(isinstance(err, ValueError))
    True
    """


class InputTypeError(LinkageFmuError, TypeError):
    """A value of a type the package cannot take (a string where a number is expected,
    an unknown keyword); the message names it."""


class ComputationError(LinkageFmuError, RuntimeError):
    """A computation that could not finish: an integration or a search that failed or
    did not converge, a generated kernel or an FMU that cannot run as asked."""


class DependencyError(LinkageFmuError, ImportError):
    """A package that cannot be imported as needed: an optional dependency that is not
    installed (the message says how to install it), or an FMU's bundled copy of this
    package that differs from the one the process runs."""


def _angle(theta: float | dict) -> str:
    """The state in words: the crank angle, or each driver's coordinate by its name (a
    dict: an angle ``theta_<j>`` in rad, a travel in m).

    Examples
    --------
    >>> _angle({"theta_A": 0.5, "s_P": 0.02})
    'theta_A = 0.5 rad (28.65 deg), s_P = 0.02 m'
    """
    if isinstance(theta, dict):
        return ", ".join(f"{n} = {v:.6g} rad ({math.degrees(v):.4g} deg)"
                         if n.startswith("theta") else f"{n} = {v:.6g} m"
                         for n, v in theta.items())
    return f"theta = {theta:.6g} rad ({math.degrees(theta):.4g} deg)"


class AssemblyError(LinkageFmuError, ValueError):
    """The linkage cannot be assembled at the requested crank angle.

    Raised for scalar inputs only; array inputs get NaN in the affected states and
    ``valid = False`` on the solution instead.

    Examples
    --------
    >>> from linkage_fmu import presets, AssemblyError
    >>> mech = presets.get("four_bar", l_AB=0.3)   # crank too long to turn fully
    >>> try:
    ...     mech.solve(3.1)
    ... except AssemblyError as err:
    ...     print(str(err).split(":")[0])
    four_bar cannot be assembled at theta = 3.1 rad (177.6 deg)
    """

    def __init__(self, mechanism: str, theta: float, condition: str, what: str = ""):
        self.mechanism = mechanism
        self.theta = theta
        self.condition = condition
        #: why, as the FMUs say it (the same words as the kernels' guards, no numbers)
        self.reason = Reason("assembly", what)
        super().__init__(f"{mechanism} cannot be assembled at {_angle(theta)}: {condition}")


class SingularPositionError(LinkageFmuError, ValueError):
    """The equations are exactly singular (a toggle or dead-centre position).

    The position exists but the reactions or the balancing effort are unbounded there.
    Raised for scalar inputs; array inputs get ``inf``/NaN in those states and a
    condition estimate of ``inf``.
    """

    def __init__(self, mechanism: str, theta: float, detail: str, what: str = ""):
        self.mechanism = mechanism
        self.theta = theta
        #: why, as the FMUs say it (the same words as the kernels' guards, no numbers)
        self.reason = Reason("singular", what)
        super().__init__(f"{mechanism} is singular at {_angle(theta)}: {detail}")


class SelfLockingError(LinkageFmuError, ValueError):
    """Friction locks the linkage: no finite balancing effort moves it at this position.

    Raised for scalar inputs; array inputs get NaN in those states and
    ``status == LOCKED`` (:data:`linkage_fmu.solver.LOCKED`).

    Examples
    --------
    >>> from linkage_fmu import presets, SelfLockingError
    >>> mech = presets.get("slider_crank", mu_guide=5.0)  # a load on the piston:
    >>> try:
    ...     mech.solve(1.2, omega=10.0, load=-50.0)
    ... except SelfLockingError as err:
    ...     print(str(err).split(":")[0])
    slider_crank locks at theta = 1.2 rad (68.75 deg)
    """

    def __init__(self, mechanism: str, theta: float, what: str = ""):
        self.mechanism = mechanism
        self.theta = theta
        #: why, as the FMUs say it (the same words as the kernels' guards, no numbers)
        self.reason = Reason("locking", what)
        super().__init__(f"{mechanism} locks at {_angle(theta)}: {what}" if what else
                         f"{mechanism} locks at {_angle(theta)}")


class OverflowInputError(LinkageFmuError, ValueError):
    """Finite inputs or parameters whose magnitudes make the outputs overflow float64
    (``omega = 1e160``, ``l_CD = 1e308``), any output, the diagnostics included.

    Raised for scalar inputs, naming the largest input or parameter; over arrays those
    states have the status :data:`~linkage_fmu.solver.OVERFLOW`.

    Examples
    --------
    >>> from linkage_fmu import presets, OverflowInputError
    >>> try:
    ...     presets.get("four_bar").solve(0.3, omega=1e160)
    ... except OverflowInputError as err:
    ...     print(str(err).split(":")[0])
    four_bar
    >>> try:
    ...     presets.get("four_bar", l_CD=1e308).solve(0.3, omega=10.0)
    ... except OverflowInputError as err:
    ...     print(str(err).split("magnitude ")[1])
    (the largest: parameter l_CD = 1e+308)
    """

    def __init__(self, mechanism: str, detail: str):
        self.mechanism = mechanism
        #: why, as the FMUs say it
        self.reason = Reason("overflow", "an input or a parameter is too large in magnitude")
        super().__init__(f"{mechanism}: {detail}")


class LinkageError(LinkageFmuError, ValueError):
    """A linkage that cannot be put together as given: ``linkage`` is its name,
    ``problem`` says what is wrong (a body that is no moving link, a load off its body,
    a name given twice).

    Examples
    --------
    >>> from linkage_fmu import Mechanism, presets
    >>> m = presets.get("four_bar")  # built again without the body of link 3:
    >>> try:
    ...     Mechanism("demo", m.frame, m.frame_points, m.groups, m.bodies[:2], m.effort,
    ...               [], [], 0.0)
    ... except LinkageError as err:
    ...     print(err.linkage, "|", err.problem)
    demo | bodies ['1', '2'] do not match the moving links ['1', '2', '3']
    """

    def __init__(self, linkage: str, problem: str):
        self.linkage, self.problem = linkage, problem
        super().__init__(f"{linkage}: {problem}")

    def __reduce__(self):
        return type(self), (self.linkage, self.problem)


class OutputError(LinkageFmuError, ValueError):
    """An output a linkage cannot report: ``output`` is its name, ``problem`` says why.

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> from linkage_fmu.outputs import Force
    >>> try:
    ...     Force("F13x", "1", "3", "x").bind(presets.get("four_bar"))
    ... except OutputError as err:
    ...     print(err.output, "|", err.problem, "|", err)
    F13x | no joint between bodies '1' and '3' | output F13x: no joint between bodies '1' and '3'
    """

    def __init__(self, output: str, problem: str):
        self.output, self.problem = output, problem
        super().__init__(f"output {output}: {problem}")

    def __reduce__(self):  # pickled as made (a sweep's worker sends its errors back)
        return type(self), (self.output, self.problem)


class LoadError(LinkageFmuError, ValueError):
    """A load a linkage cannot take: ``load`` is its name, ``problem`` says why.

    Examples
    --------
    >>> from linkage_fmu.loads import Load
    >>> try:
    ...     Load("F", "2", "force", at="P", direction=(0.0, 0.0))
    ... except LoadError as err:
    ...     print(err.load, "|", err.problem)
    F | direction (0.0, 0.0) has no length
    """

    def __init__(self, load: str, problem: str):
        self.load, self.problem = load, problem
        super().__init__(f"load {load}: {problem}")

    def __reduce__(self):
        return type(self), (self.load, self.problem)


class ParameterError(LinkageFmuError, ValueError):
    """A parameter declared as it cannot be: ``parameter`` is its name, ``problem`` says
    why.

    Examples
    --------
    >>> from linkage_fmu.parameters import Parameter
    >>> try:
    ...     Parameter("mu_A", 0.1, "friction", "friction in A", maximum=2000.0)
    ... except ParameterError as err:
    ...     print(err.parameter, "|", err.problem)
    mu_A | max = 2000 is above the largest coefficient of friction taken (1000)
    """

    def __init__(self, parameter: str, problem: str):
        self.parameter, self.problem = parameter, problem
        super().__init__(f"{parameter}: {problem}")

    def __reduce__(self):
        return type(self), (self.parameter, self.problem)


class NearSingularWarning(UserWarning):
    """A linkage drawn near a singular or limit position: the group named is drawn where
    its equations are ill-conditioned (the condition number is said), so the drawing
    barely fixes which assembly mode it takes, and a slightly different drawing may
    take another. Draw it farther from the position where its links line up or its
    crank turns no further.

    Examples
    --------
    >>> import warnings
    >>> from linkage_fmu.groups import Closure
    >>> g = Closure({"2": ("B", "C"), "3": ("D", "C")},
    ...             {"B": (0.0, 0.0), "C": (0.3, 1e-6), "D": (0.6, 0.0)}, 0.0, {"B", "D"})
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     g.attach((), {"B": (0.0, 0.0), "D": (0.6, 0.0)})
    >>> print(caught[0].category.__name__, caught[0].message)
    NearSingularWarning the group of joints B, C, D is drawn near a singular position: the
    condition number of its equations there is 3e+05 (above 1000), so the drawing barely fixes
    its assembly mode; draw it farther from a limit or singular position
    """

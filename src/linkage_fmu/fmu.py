"""The FMI 2.0 co-simulation slave of a preset, built with pythonfmu.

One generic :class:`LinkageSlave`; each FMU's script subclasses it with ``PRESET`` set
(``build_fmu.py`` writes those scripts). The slave has no state of its own: outputs are
a direct feedthrough of the latest inputs, computed when a getReal call asks for them,
only the ones asked for, at most once per change of inputs.

Nothing escapes to the host: a Python exception in a pythonfmu callback becomes
fmi2Fatal and kills the instance, so every callback catches, logs (naming variable,
value and reason) and answers with NaN outputs and fmi2Discard from doStep until the
inputs are valid again.
"""

from __future__ import annotations

import atexit
import ctypes
import functools
import hashlib
import math
import sys
import weakref
from pathlib import Path

from pythonfmu import (DefaultExperiment, Fmi2Causality, Fmi2Slave, Fmi2Variability, Integer,
                       String)
from pythonfmu.enums import Fmi2Status
from pythonfmu.osutil import get_lib_extension, get_platform

from . import __version__, presets
from .mechanism import INPUTS, METHODS
from .model_description import RealWithUnit, complete
from .numerics import SCALAR

_INPUT_INFO = {
    "theta": ("rad", "deg", "crank angle from +x, counter-clockwise"),
    "omega": ("rad/s", "", "crank angular speed"),
    "alpha": ("rad/s2", "", "crank angular acceleration"),
}
_REAL_KINDS = {"length", "distance", "coordinate", "angle", "mass", "inertia", "density",
               "gravity"}


def fingerprint(package_dir: str | Path) -> str:
    """SHA-256 of the package's Python sources (relative names and contents).

    Examples
    --------
    >>> import linkage_fmu
    >>> len(fingerprint(Path(linkage_fmu.__file__).parent))
    64
    """
    root = Path(package_dir)
    h = hashlib.sha256()
    for f in sorted(root.rglob("*.py")):
        h.update(f.relative_to(root).as_posix().encode() + b"\0" + f.read_bytes() + b"\0")
    return h.hexdigest()


@functools.lru_cache(maxsize=1)
def _loaded_fingerprint() -> str:
    # Once per process, while the files are there: fmpy deletes the folder an FMU was
    # extracted to after simulate_fmu, but this package stays imported from it.
    return fingerprint(Path(__file__).parent)


def check_bundle(expected: str) -> None:
    """Refuse to run a ``linkage_fmu`` other than the one this FMU bundles.

    The host process may have imported ``linkage_fmu`` before loading the FMU; Python
    then hands the FMU the host's copy instead of the bundled one.
    """
    found = _loaded_fingerprint()
    if found != expected:
        raise ImportError(
            f"this FMU bundles linkage_fmu with source fingerprint {expected[:12]}, but the "
            f"process already imported linkage_fmu {__version__} from "
            f"{Path(__file__).parent} (fingerprint {found[:12]}); load the FMU in a process "
            "that has not imported another linkage_fmu, or rebuild it with that version")


def hold_namespace(module_name: str) -> None:
    """Take one reference to a slave script module's namespace, for pythonfmu 0.7's wrapper.

    The generated slave script calls this at module level. The wrapper releases one
    reference to the script's ``__dict__`` per ``fmi2Instantiate`` that it never took,
    and runs the script's code once per instantiation to find the slave class (measured
    with pythonfmu 0.7.0). Left alone, the very first instantiation frees the namespace
    of a module that is still in use: the next instance fails with ``module has no
    attribute 'FourBar'`` or Python's heap is corrupted and the host crashes later, at
    exit at the latest. One reference per run of the script balances each release; a
    wrapper that does not release merely leaves a module that lives until exit anyway
    with a few references more.

    Examples
    --------
    >>> import sys
    >>> before = sys.getrefcount(vars(sys.modules[__name__]))
    >>> hold_namespace(__name__)
    >>> sys.getrefcount(vars(sys.modules[__name__])) - before
    1
    """
    ctypes.pythonapi.Py_IncRef(ctypes.py_object(vars(sys.modules[module_name])))


@functools.lru_cache(maxsize=None)  # once per wrapper library and process
def _release_wrapper_at_exit(library: str) -> None:
    """Keep pythonfmu 0.7's wrapper ``library`` loaded and release its interpreter state
    at interpreter exit, before the C runtime's exit handlers run.

    The wrapper holds its interpreter state in a static ``shared_ptr``. At process exit
    (or dlclose) the C++ runtime destroys that pointer, and then the library's own
    finaliser, ``finalizePythonInterpreter``, releases the same pointer a second time:
    a double free, after which the host aborts at exit (measured: 10 of 20 runs of a
    Python host). ``finalizePythonInterpreter`` empties the pointer before it releases
    it, so calling it first makes both later releases no-ops. The ``ctypes`` handle
    taken here pins the library, so it is still there when ``atexit`` runs.

    Parameters
    ----------
    library : str
        Path of the FMU's binary, already loaded by the host.
    """
    atexit.register(ctypes.CDLL(library).finalizePythonInterpreter)


class LinkageSlave(Fmi2Slave):
    """Co-simulation slave for the preset named by the subclass attribute ``PRESET``.

    Variables: inputs ``theta, omega, alpha, load``; every preset parameter (same name,
    SI unit); ``method`` ('closed_form' or 'direct'); outputs: the preset's outputs and
    diagnostics.
    """

    PRESET = ""

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        if "logger" in kwargs:  # created by the FMU's wrapper, not by the builder
            binary = (Path(self.resources).parent / "binaries" / get_platform()
                      / f"{type(self).__name__}.{get_lib_extension()}")
            try:
                _release_wrapper_at_exit(str(binary))
            except (OSError, AttributeError) as err:
                self.log(f"the host may crash at exit: cannot pin the FMU binary {binary} "
                         f"({err})", Fmi2Status.warning)
        spec = presets.preset(self.PRESET)
        mech = presets.get(self.PRESET)
        self.author = "linkage_fmu"
        self.version = __version__
        self.description = f"{spec.title}: joint reactions and balancing effort (kinetostatics)"
        start = spec.inputs
        w0 = abs(start.omega)
        stop = 2.0 * math.pi / w0 if w0 else 1.0
        self.default_experiment = DefaultExperiment(0.0, stop, stop / 360.0)

        self._params = {p.name: p.default for p in spec.parameters}
        self._method = "closed_form"
        self._mech = mech
        self._problem = ""  # why the parameters are unusable ('' = fine)
        self._u = [float(getattr(start, n)) for n in INPUTS]
        self._cache: dict = {}
        self._positions = None  # positions at the current theta, from doStep
        self._names = mech.output_names + mech.diagnostic_names
        self._time = 0.0

        # The variables' getters and setters reach the slave through a weak proxy: a
        # reference cycle would keep the slave alive until a later garbage collection,
        # after fmpy may have unloaded pythonfmu's wrapper library, and crash the host.
        me = weakref.proxy(self)
        self._vr_input = {}
        for i, name in enumerate(INPUTS):
            unit, display, text = _INPUT_INFO.get(
                name, (start.load_unit, "", start.load_description))
            self.register_variable(RealWithUnit(
                name, unit, display, description=text, causality=Fmi2Causality.input,
                variability=Fmi2Variability.continuous, start=self._u[i],
                getter=lambda i=i: me._u[i], setter=lambda v, i=i: me._set_input(i, v)))
            self._vr_input[len(self.vars) - 1] = i
        for p in spec.parameters:
            common = dict(description=p.description, causality=Fmi2Causality.parameter,
                          variability=Fmi2Variability.fixed, start=p.default,
                          getter=lambda n=p.name: me._params[n],
                          setter=lambda v, n=p.name: me._set_param(n, v))
            if p.kind in _REAL_KINDS:
                self.register_variable(RealWithUnit(p.name, p.unit, **common))
            elif p.kind == "branch":
                self.register_variable(Integer(p.name, **common))
            else:
                common["description"] += f" (one of {', '.join(p.choices)})"
                self.register_variable(String(p.name, **common))
        self.register_variable(String(
            "method", description="solver: 'closed_form' (fast) or 'direct' (reference LU)",
            causality=Fmi2Causality.parameter, variability=Fmi2Variability.fixed,
            start="closed_form", getter=lambda: me._method,
            setter=lambda v: me._set_param("method", v)))
        self._vr_output = {}
        for name in self._names:
            unit, text = mech.output_info[name]
            self.register_variable(RealWithUnit(
                name, unit, "deg" if unit == "rad" else "", description=text,
                causality=Fmi2Causality.output, variability=Fmi2Variability.continuous,
                getter=lambda n=name: me._outputs((n,))[0]))
            self._vr_output[len(self.vars) - 1] = name

    # -- model description (build time) ---------------------------------------------
    def to_xml(self, model_options=dict()):
        root = super().to_xml(model_options)
        deps = {n: (("theta",) if n in self._mech.diagnostic_names else INPUTS)
                for n in self._names}
        return complete(root, deps)

    def log(self, msg, status=Fmi2Status.ok, category=None, debug=None):
        # the host's logger takes the message as a printf format string
        super().log(str(msg).replace("%", "%%"), status, category)

    # -- setters and getters: never raise -------------------------------------------
    def _set_input(self, i: int, value: float) -> None:
        self._u[i] = value
        self._cache, self._positions = {}, None

    def _set_param(self, name: str, value) -> None:
        if name == "method":
            self._method = value
        else:
            self._params[name] = value
        self._cache, self._positions = {}, None
        self._mech, self._problem = None, ""

    def set_real(self, vrs, values):
        try:
            for vr, value in zip(vrs, values):
                i = self._vr_input.get(vr)
                if i is None:
                    self.vars[vr].setter(value)
                else:
                    self._u[i] = value
            self._cache, self._positions = {}, None
        except Exception as err:  # pragma: no cover - defensive: never reach the host
            self.log(f"setReal failed: {err!r}", Fmi2Status.error)

    def get_real(self, vrs):
        try:
            names = [self._vr_output.get(vr) for vr in vrs]
            if None not in names:
                return self._outputs(names)
            out = []
            for vr, name in zip(vrs, names):
                out.append(self._outputs((name,))[0] if name else float(self.vars[vr].getter()))
            return out
        except Exception as err:  # pragma: no cover - defensive: never reach the host
            self.log(f"getReal failed: {err!r}", Fmi2Status.error)
            return [math.nan] * len(vrs)

    def _mechanism(self):
        """The mechanism for the current parameters, or None (reason in _problem)."""
        if self._mech is None and not self._problem:
            try:
                if self._method not in METHODS:
                    raise ValueError(f"method must be one of {METHODS}, got {self._method!r}")
                self._mech = presets.get(self.PRESET, **self._params)
            except (TypeError, ValueError) as err:
                self._problem = f"invalid parameter: {err}"
        return self._mech

    def _input_problem(self) -> str:
        for name, value in zip(INPUTS, self._u):
            if not math.isfinite(value):
                return f"input {name} = {value!r} is not a finite number"
        return ""

    def _outputs(self, names) -> list:
        cache = self._cache
        missing = [n for n in names if n not in cache]
        if missing:
            cache.update(self._solve(missing))
        return [cache[n] for n in names]

    def _solve(self, names) -> dict:
        mech = self._mechanism()
        problem = self._problem or self._input_problem()
        if not problem:
            try:
                return mech._solve_scalar(self._u, self._method, tuple(names), self._positions)
            except ValueError as err:  # AssemblyError, SingularPositionError
                problem = str(err)
        self.log(f"outputs {', '.join(names)} are NaN at t = {self._time!r}: {problem}",
                 Fmi2Status.warning)
        return dict.fromkeys(names, math.nan)

    # -- life cycle -----------------------------------------------------------------
    def setup_experiment(self, start_time, stop_time=None, tolerance=None):
        self._time = start_time

    def exit_initialization_mode(self):
        self._problem = ""
        if self._mechanism() is None:
            self.log(self._problem + "; every doStep will be discarded", Fmi2Status.error)

    def do_step(self, current_time, step_size):
        try:
            if self._mechanism() is None:
                self.log(f"doStep at t = {current_time!r} discarded: {self._problem}",
                         Fmi2Status.discard)
                return False
            problem = self._input_problem()
            if not problem and self._positions is None:
                try:  # can it be assembled? (the outputs then start from these positions)
                    self._positions = self._mech._kinematics(self._u[0], SCALAR, 0)
                except ValueError as err:
                    problem = str(err)
            if problem:
                self._cache = dict.fromkeys(self._names, math.nan)  # nothing stale
                self.log(f"doStep at t = {current_time!r} discarded: {problem}",
                         Fmi2Status.discard)
                return False
            self._time = current_time + step_size
            return True
        except Exception as err:  # pragma: no cover - defensive: never reach the host
            self.log(f"doStep failed: {err!r}", Fmi2Status.error)
            return False

    # -- FMU state: inputs, parameters and time (the cache is rebuilt on demand) -----
    def _get_fmu_state(self):
        return {"u": list(self._u), "params": dict(self._params), "method": self._method,
                "time": self._time}

    def _set_fmu_state(self, state):
        self._u = [float(v) for v in state["u"]]
        self._params = dict(state["params"])
        self._method = state["method"]
        self._time = state["time"]
        self._cache, self._mech, self._problem, self._positions = {}, None, "", None
        self._mechanism()

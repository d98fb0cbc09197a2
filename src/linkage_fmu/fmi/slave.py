"""The FMI 2.0 co-simulation slave of a linkage, built with pythonfmu.

One generic :class:`LinkageSlave`; each FMU's script subclasses it with ``DESCRIPTION``
set to the linkage's description file, bundled beside it (:mod:`linkage_fmu.fmi.build`
writes those scripts). The slave has no state of its own: outputs are
a direct feedthrough of the latest inputs, computed when a getReal call asks for them,
only the ones asked for, at most once per change of inputs.

The FMU's binary is the guard of :mod:`linkage_fmu.fmi.guard` in front of pythonfmu's
wrapper: it enforces the FMI state machine and checks every argument, so the slave only
sees valid calls. The status of a call is the worst status the slave logs during it:

* inputs that cannot be solved (not finite, an angle at which the linkage cannot be
  assembled, a singular position, arithmetic that overflows): fmi2Warning from doStep or
  getReal, every output NaN until the inputs change, a log naming the variable, value and
  reason. The step itself succeeds (the slave has no state to lose), so a master's run
  goes on and returns every row; Discard, which fmpy answers by ending the run or by
  retrying the same inputs forever, is never used;
* an invalid parameter set: fmi2Error from exitInitializationMode, naming each problem;
  the instance stays in initialisation mode until the parameters are fixed.

Nothing escapes to the host: a Python exception in a pythonfmu callback is fmi2Fatal
there, so every callback catches, logs with fmi2Error and answers NaN.
"""

from __future__ import annotations

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

from .. import __version__
from ..mechanism import METHODS
from ..spec import Description
from .model_description import RealWithUnit, complete
from .variables import variables

#: the linkage_fmu package this module belongs to
PACKAGE = Path(__file__).parents[1]

def fingerprint(package_dir: str | Path) -> str:
    """SHA-256 of the package's Python sources (relative names and contents).

    Examples
    --------
    >>> len(fingerprint(PACKAGE))
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
    return fingerprint(PACKAGE)


def check_bundle(expected: str, script: str | Path) -> None:
    """Refuse to run a ``linkage_fmu`` other than the one this FMU bundles.

    The host process may have imported ``linkage_fmu`` before loading the FMU; Python
    then hands the FMU the host's copy instead of the bundled one. Or the copy bundled
    in the FMU (beside the slave ``script``, in ``resources/``) was edited after the
    build. The message says which.
    """
    found = _loaded_fingerprint()
    if found == expected:
        return
    loaded = PACKAGE.resolve()
    if loaded.parent == Path(script).resolve().parent:
        raise ImportError(
            f"the linkage_fmu bundled in this FMU ({loaded}) was changed after the FMU was "
            f"built (source fingerprint {found[:12]}, built as {expected[:12]}); rebuild the "
            "FMU instead of editing its resources")
    raise ImportError(
        f"this FMU bundles linkage_fmu with source fingerprint {expected[:12]}, but the "
        f"process already imported linkage_fmu {__version__} from {loaded} (fingerprint "
        f"{found[:12]}); load the FMU in a process that has not imported another "
        "linkage_fmu, or rebuild it with that version")


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


class LinkageSlave(Fmi2Slave):
    """Co-simulation slave for the linkage described by the file named ``DESCRIPTION`` (a
    subclass attribute: the description file bundled in the FMU's resources).

    Variables: :func:`~linkage_fmu.fmi.variables.variables` of the linkage, whose
    parameter defaults in the file are the FMU's start values.
    """

    DESCRIPTION = ""

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self._logged: list = []  # attributes of queued log messages (see log)
        self._cause = None  # cause of the latest warning, while it repeats
        self._repeats = 0
        # An instance finds the file in its own resources folder: the script module stays
        # imported from the folder the first instance was extracted to, which the host
        # may have deleted since (fmpy does after simulate_fmu). At build time there is
        # no resources folder, and the file is beside the script.
        folder = (Path(self.resources) if self.resources else
                  Path(sys.modules[type(self).__module__].__file__).parent)
        self._desc = Description.read(folder / self.DESCRIPTION)
        mech = self._desc.build()
        table = variables(mech)
        self.author = "linkage_fmu"
        self.version = __version__
        self.description = (f"{self._desc.title or self._desc.name}: joint reactions and "
                            "balancing effort (kinetostatics)")
        w0 = abs(self._desc.inputs.get("omega", 0.0))
        stop = 2.0 * math.pi / w0 if w0 else 1.0
        self.default_experiment = DefaultExperiment(0.0, stop, stop / 360.0)

        self._params = {v.name: v.start for v in table
                        if v.causality == "parameter" and v.name != "method"}
        self._method = "closed_form"
        self._mech = mech
        self._problem = ""  # why the parameters are unusable ('' = fine)
        self._inputs = mech.input_names
        self._u = [v.start for v in table if v.causality == "input"]
        self._cache: dict = {}
        self._unsolvable = ()  # (cause, message) while the cache holds NaN for a reason
        self._names = mech.output_names + mech.diagnostic_names
        self._depends = {v.name: v.depends for v in table if v.causality == "output"}
        self._time = 0.0

        # The variables' getters and setters reach the slave through a weak proxy: a
        # reference cycle would keep the slave alive until a later garbage collection,
        # after fmpy may have unloaded pythonfmu's wrapper library, and crash the host.
        me = weakref.proxy(self)
        self._vr_input, self._vr_output = {}, {}
        kinds = {"Real": RealWithUnit, "Integer": Integer, "String": String}
        for v in table:
            common = dict(description=v.description, causality=Fmi2Causality[v.causality],
                          variability=Fmi2Variability[v.variability])
            if v.type == "Real":
                common.update(unit=v.unit, display_unit=v.display_unit)
            if v.causality == "input":
                i = len(self._vr_input)
                common.update(start=v.start, getter=lambda i=i: me._u[i],
                              setter=lambda x, i=i: me._set_input(i, x))
            elif v.causality == "parameter":
                common.update(start=v.start, getter=lambda n=v.name: me._parameter(n),
                              setter=lambda x, n=v.name: me._set_param(n, x))
            else:
                common.update(getter=lambda n=v.name: me._outputs((n,))[0])
            self.register_variable(kinds[v.type](v.name, **common))
            if v.causality == "input":
                self._vr_input[len(self.vars) - 1] = len(self._vr_input)
            elif v.causality == "output":
                self._vr_output[len(self.vars) - 1] = v.name

    # -- model description (build time) ---------------------------------------------
    def to_xml(self, model_options=dict()):
        return complete(super().to_xml(model_options), self._depends)

    # -- logging: statuses for the guard, no leak, repeated warnings counted ---------
    def log(self, msg, status=Fmi2Status.ok, category=None, debug=None):
        # the host's logger takes the message as a printf format string
        super().log(str(msg).replace("%", "%%"), status, category)
        queued = self.log_queue[-1]
        self._logged += (queued.msg, queued.category, queued.status)

    def _release_logged(self) -> None:
        """Drop the references pythonfmu 0.7's wrapper leaks per log message.

        When the wrapper passes the queued messages to the logger, it reads each one's
        ``msg``, ``category`` and ``status`` with ``PyObject_GetAttr`` and never releases
        what it got (measured: about 211 bytes per message, kept until exit). Once the
        wrapper has emptied the queue, every object listed in ``_logged`` holds exactly
        one such reference, which is released here. Called at the start of every
        callback; nothing is released while a message is still queued.
        """
        if self._logged and not self.log_queue:
            for obj in self._logged:
                ctypes.pythonapi.Py_DecRef(ctypes.py_object(obj))
            self._logged.clear()

    def __del__(self):
        try:
            self._release_logged()
        except Exception:  # pragma: no cover - interpreter shutting down
            pass

    def _warn(self, cause: tuple, message: str) -> None:
        """Log ``message`` as a warning, or, while the same ``cause`` repeats, only the
        status (the guard turns it into the call's fmi2Warning; the host sees nothing)."""
        if cause == self._cause:
            self._repeats += 1
            self.log("", Fmi2Status.warning)  # a status the guard does not pass on
            return
        self._end_repeats()
        self._cause = cause
        self.log(message, Fmi2Status.warning)

    def _end_repeats(self) -> None:
        if self._repeats:
            self.log(f"the warning above repeated {self._repeats} more times, the last at "
                     f"t = {self._time!r}", Fmi2Status.ok, "logAll")
        self._cause, self._repeats = None, 0

    def _error(self, call: str, err: BaseException) -> None:
        self.log(f"{call} failed: {err!r}", Fmi2Status.error)

    # -- setters and getters: the guard has checked references, types and states ----
    def _invalidate(self) -> None:
        """Forget everything computed from the inputs and parameters."""
        self._cache, self._unsolvable = {}, ()

    def _set_input(self, i: int, value: float) -> None:
        self._u[i] = value
        self._invalidate()

    def _parameter(self, name: str):
        return self._method if name == "method" else self._params[name]

    def _set_param(self, name: str, value) -> None:
        if name == "method":
            self._method = value
        else:
            self._params[name] = value
        self._invalidate()
        self._mech, self._problem = None, ""

    def set_real(self, vrs, values):
        self._release_logged()
        self._invalidate()  # whatever happens below
        try:
            for vr, value in zip(vrs, values):
                i = self._vr_input.get(vr)
                if i is None:
                    self.vars[vr].setter(value)
                else:
                    self._u[i] = value
        except Exception as err:
            self._error("setReal", err)

    def _set_other(self, call: str, vrs, values) -> None:
        self._release_logged()
        self._invalidate()
        try:
            for vr, value in zip(vrs, values):
                self.vars[vr].setter(value)
        except Exception as err:
            self._error(call, err)

    def set_integer(self, vrs, values):
        self._set_other("setInteger", vrs, values)

    def set_boolean(self, vrs, values):
        self._set_other("setBoolean", vrs, values)

    def set_string(self, vrs, values):
        self._set_other("setString", vrs, values)

    def get_real(self, vrs):
        self._release_logged()
        try:
            names = [self._vr_output.get(vr) for vr in vrs]
            if None not in names:
                return self._outputs(names)
            out = []
            for vr, name in zip(vrs, names):
                out.append(self._outputs((name,))[0] if name else float(self.vars[vr].getter()))
            return out
        except Exception as err:
            self._error("getReal", err)
            return [math.nan] * len(vrs)

    def _get_other(self, call: str, vrs, convert, default) -> list:
        self._release_logged()
        try:
            return [convert(self.vars[vr].getter()) for vr in vrs]
        except Exception as err:
            self._error(call, err)
            return [default] * len(vrs)

    def get_integer(self, vrs):
        return self._get_other("getInteger", vrs, int, 0)

    def get_boolean(self, vrs):
        return self._get_other("getBoolean", vrs, bool, False)

    def get_string(self, vrs):
        return self._get_other("getString", vrs, str, "")

    def _mechanism(self):
        """The mechanism for the current parameters, or None (reason in _problem)."""
        if self._mech is None and not self._problem:
            try:
                if self._method not in METHODS:
                    raise ValueError(f"method must be one of {METHODS}, got {self._method!r}")
                self._mech = self._desc.build(**self._params)
            except (TypeError, ValueError) as err:
                self._problem = f"invalid parameter: {err}"
        return self._mech

    def _input_problem(self) -> tuple:
        """``(cause, message)`` if the inputs are not all finite, else ``()``."""
        for name, value in zip(self._inputs, self._u):
            if not math.isfinite(value):
                return ("input", name), f"input {name} = {value!r} is not a finite number"
        return ()

    def _outputs(self, names) -> list:
        cache = self._cache
        missing = [n for n in names if n not in cache]
        if missing:
            cache.update(self._solve(missing))
        elif self._unsolvable:  # NaN from an earlier call: this read warns too
            self._warn(*self._unsolvable)
        return [cache[n] for n in names]

    def _unsolved(self, cause: tuple, message: str) -> None:
        """The inputs cannot be solved: every output NaN until they change, and a warning."""
        self._cache = dict.fromkeys(self._names, math.nan)
        self._unsolvable = cause, message
        self._warn(cause, message)

    def _solve(self, names) -> dict:
        """Outputs ``names`` at the current inputs; all of them NaN, with a warning, if
        the inputs cannot be solved. Every output is computed at once, by one call of
        the solver: all of them share one fate."""
        mech = self._mechanism()
        if mech is None:  # the guard allows no read after a failed initialisation
            return dict.fromkeys(names, math.nan)
        problem = self._input_problem()
        if not problem:
            try:
                r = mech.solver.attempt(self._u, None, self._method)
            except (ArithmeticError, ValueError) as err:
                problem = (type(err).__name__,), str(err)
            else:
                if type(r) is tuple:
                    self._end_repeats()
                    self._cache = dict(zip(self._names, r))
                    return {n: self._cache[n] for n in names}
                problem = (r.kind, r.what), r.text
        # every output, not only those asked for: none may be read stale or half-valid
        self._unsolved(problem[0], f"outputs are NaN at t = {self._time!r}: {problem[1]}")
        return dict.fromkeys(names, math.nan)

    # -- life cycle -----------------------------------------------------------------
    def setup_experiment(self, start_time, stop_time=None, tolerance=None):
        self._release_logged()
        self._time = start_time

    def enter_initialization_mode(self):
        self._release_logged()

    def exit_initialization_mode(self):
        """Check the parameter set; an invalid one is an fmi2Error (through the guard)."""
        self._release_logged()
        try:
            self._mech, self._problem = None, ""
            if self._mechanism() is None:
                self.log(f"exitInitializationMode: {self._problem}", Fmi2Status.error)
        except Exception as err:
            self._error("exitInitializationMode", err)

    def terminate(self):
        self._release_logged()
        self._end_repeats()

    def do_step(self, current_time, step_size):
        """Check that the inputs can be solved (finite, and the linkage assembles at
        theta); the outputs are computed when read. Always True: see the module notes."""
        self._release_logged()
        try:
            self._time = current_time + step_size
            mech = self._mechanism()
            if mech is None:  # not after a successful exitInitializationMode
                self.log(f"doStep: {self._problem}", Fmi2Status.error)
                return True
            problem = self._input_problem()
            if not problem and not self._cache:
                self._outputs(self._names)  # one solve per input change
                problem = self._unsolvable
            elif self._unsolvable:
                problem = self._unsolvable
            if problem:
                self._unsolved(problem[0], f"doStep to t = {self._time!r}: outputs are NaN: "
                                           f"{problem[1]}")
            return True
        except Exception as err:
            self._error("doStep", err)
            return True

    # -- FMU state: inputs, parameters and time (the cache is rebuilt on demand) -----
    def _get_fmu_state(self):
        self._release_logged()
        return {"u": list(self._u), "params": dict(self._params), "method": self._method,
                "time": self._time}

    def _set_fmu_state(self, state):
        self._release_logged()
        try:
            u, params = state["u"], state["params"]
            if len(u) != len(self._u) or set(params) != set(self._params):
                raise ValueError("the state does not hold this model's inputs and parameters")
            self._u = [float(v) for v in u]
            self._params = dict(params)
            self._method = str(state["method"])
            self._time = float(state["time"])
        except Exception as err:
            self._error("setFMUstate", err)
        self._invalidate()
        self._mech, self._problem = None, ""
        self._mechanism()

    @staticmethod
    def _fmu_state_from_bytes(state: bytes):
        # the guard has checked the header and checksum; a state it lets through that
        # still fails here reaches _set_fmu_state as a dict it rejects with an error
        try:
            return Fmi2Slave._fmu_state_from_bytes(state)
        except Exception:
            return {}

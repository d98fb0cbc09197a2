"""The Python slave of a pythonfmu FMU: what the C framework asks of the package.

The FMU's binary is the C framework (``framework.c`` with ``backend_pythonfmu.c``) in
front of pythonfmu's wrapper, which calls this slave. The framework owns the variables'
values, the state machine, the checks, the status policy, the logs and the states; the
slave only computes, and says why it cannot:

* ``set_real`` / ``set_integer`` / ``set_string``: the framework hands over parameters
  (before a prepare) and inputs (before an evaluation), by value reference;
* ``exit_initialization_mode``: build the linkage from the parameters; an invalid set is
  logged with fmi2Error and the reason;
* ``get_real`` of the outputs: one call of the solver
  (:meth:`Solver.attempt <linkage_fmu.solver.Solver.attempt>`) at the inputs, every output
  at once; a state without outputs gives NaN and its reason, logged with fmi2Discard,
  in the words the native kernels use. Once the solver has compiled its kernel of every
  output, ``get_real`` calls that kernel itself, and the solver only where the kernel
  does not take the state.

The framework calls ``set_real`` (every input, in order) and ``get_real`` (every output,
in order) once per change of the inputs, and nothing between its steps: those two calls
are the slave's share of a step, and do no more than pass the inputs to the kernel and
its outputs back.

Nothing escapes to the wrapper: a Python exception in a callback would be its fmi2Fatal,
after which it cannot be called again; every callback logs it with fmi2Error instead.
The generated slave script (:func:`~linkage_fmu.fmi.writers.slave_script`) subclasses
:class:`LinkageSlave` with the description file bundled beside it.
"""

from __future__ import annotations

import ctypes
import functools
import hashlib
import math
import sys
from pathlib import Path

from pythonfmu import Fmi2Slave
from pythonfmu.enums import Fmi2Status

from .. import __version__
from ..descriptions import Description
from ..errors import ComputationError, DependencyError
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


def check_bundle(expected: str, resources: str | Path) -> None:
    """Refuse to run a ``linkage_fmu`` other than the one this FMU bundles.

    The host process may have imported ``linkage_fmu`` before loading the FMU; Python
    then hands the FMU the host's copy instead of the bundled one. Or the copy bundled
    in the FMU (in ``resources``) was edited after the build. The message says which.
    """
    found = _loaded_fingerprint()
    if found == expected:
        return
    loaded = PACKAGE.resolve()
    if loaded.parent == Path(resources).resolve():
        raise DependencyError(
            f"the linkage_fmu bundled in this FMU ({loaded}) was changed after the FMU was "
            f"built (source fingerprint {found[:12]}, built as {expected[:12]}); rebuild the "
            "FMU instead of editing its resources")
    raise DependencyError(
        f"this FMU bundles linkage_fmu with source fingerprint {expected[:12]}, but the "
        f"process already imported linkage_fmu {__version__} from {loaded} (fingerprint "
        f"{found[:12]}); load the FMU in a process that has not imported another "
        "linkage_fmu, or rebuild it with that version")


def hold_namespace(module_name: str) -> None:
    """Take one reference to a slave script module's namespace, for pythonfmu 0.7's wrapper.

    The generated slave script calls this at module level. The wrapper releases one
    reference to the script's ``__dict__`` per ``fmi2Instantiate`` that it never took
    (it runs the script's code once per instantiation to find the slave class). Left
    alone, an early instantiation frees the namespace of a module that is still in use,
    and the host crashes. One reference per run of the script balances each release.

    Examples
    --------
    >>> import sys
    >>> before = sys.getrefcount(vars(sys.modules[__name__]))
    >>> hold_namespace(__name__)
    >>> sys.getrefcount(vars(sys.modules[__name__])) - before
    1
    """
    ctypes.pythonapi.Py_IncRef(ctypes.py_object(vars(sys.modules[module_name])))


def drop_wrapper_path(module_name: str) -> None:
    """Remove the ``sys.path`` entry pythonfmu 0.7's wrapper inserts per instantiation
    (the FMU's resources folder, where ``slavemodule.txt`` names ``module_name``), and the
    reference to it the wrapper keeps: without this, ``sys.path`` grows by one entry per
    instance and every later import searches them all."""
    if not sys.path or not isinstance(sys.path[0], str):
        return
    try:
        ours = Path(sys.path[0], "slavemodule.txt").read_text().strip() == module_name
    except OSError:
        ours = False
    if ours:
        entry = sys.path.pop(0)
        if sys.getrefcount(entry) == 3:  # entry, the argument, the wrapper's own reference
            ctypes.pythonapi.Py_DecRef(ctypes.py_object(entry))


class LinkageSlave(Fmi2Slave):
    """The slave of the linkage described by the file named ``DESCRIPTION`` (a subclass
    attribute: the description file bundled in the FMU's resources), whose bundled
    package has the fingerprint ``FINGERPRINT``.

    Its variables are :func:`~linkage_fmu.fmi.variables.variables` of the linkage, by
    value reference; the framework sets them, and reads the outputs.
    """

    DESCRIPTION = ""
    FINGERPRINT = ""

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self._logged: list = []  # attributes of queued log messages (see log)
        # An instance finds the file in its own resources folder: the script module stays
        # imported from the folder the first instance was extracted to, which the host
        # may have deleted since (fmpy does after simulate_fmu).
        folder = Path(self.resources)
        check_bundle(self.FINGERPRINT, folder)
        self._description = Description.read(folder / self.DESCRIPTION)
        mech = self._description.build()
        table = variables(mech)
        self._values = {vr: v.start for vr, v in enumerate(table)
                        if v.causality == "parameter"}
        self._parameters = {vr: v.name for vr, v in enumerate(table)
                            if v.causality == "parameter"}
        # the backend sets the inputs, and reads the outputs, in these orders
        self._inputs = [vr for vr, v in enumerate(table) if v.causality == "input"]
        self._output_vrs = [vr for vr, v in enumerate(table) if v.causality == "output"]
        self._input_index = {vr: k for k, vr in enumerate(self._inputs)}
        self._outputs = {vr: k for k, vr in enumerate(self._output_vrs)}
        self._x = [table[vr].start for vr in self._inputs]  # the inputs in force
        self._mech, self._method = None, "closed_form"
        # the compiled kernels of every output, by static (omega = alpha = 0); None until
        # the solver has compiled them
        self._hot: list = [None, None]

    # -- logging: no leak ---------------------------------------------------------------
    def log(self, msg, status=Fmi2Status.ok, category=None, debug=None):
        # the host's logger takes the message as a printf format string
        super().log(str(msg).replace("%", "%%"), status, category)
        queued = self.log_queue[-1]
        self._logged += (queued.msg, queued.category, queued.status)

    def _release_logged(self) -> None:
        """Drop the references pythonfmu 0.7's wrapper leaks per log message.

        When the wrapper passes the queued messages to the logger, it reads each one's
        ``msg``, ``category`` and ``status`` with ``PyObject_GetAttr`` and never releases
        what it got. Once the wrapper has emptied the queue, every object listed in
        ``_logged`` holds exactly one such reference, which is released here. Called at
        the start of every callback; nothing is released while a message is queued.
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

    def _failed(self, call: str, err: BaseException) -> None:
        self.log(f"{call} failed: {err!r}", Fmi2Status.error)

    # -- what the framework asks ----------------------------------------------------------
    # set_real and get_real run once each per change of the inputs (the framework keeps the
    # outputs until an input changes), so they do no more than that needs.
    def _set(self, call: str, vrs, values) -> None:
        if self._logged:
            self._release_logged()
        try:
            x, index = self._x, self._input_index
            for vr, value in zip(vrs, values):
                k = index.get(vr)
                if k is None:
                    self._values[vr] = value
                else:
                    x[k] = value
        except Exception as err:
            self._failed(call, err)

    def set_real(self, vrs, values):
        if vrs == self._inputs:  # an evaluation's: every input in order, a list of our own
            if self._logged:
                self._release_logged()
            self._x = values
        else:
            self._set("setReal", vrs, values)

    def set_integer(self, vrs, values):
        self._set("setInteger", vrs, values)

    def set_string(self, vrs, values):
        self._set("setString", vrs, values)

    def exit_initialization_mode(self):
        """Build the linkage of the parameters set; an invalid set is an fmi2Error with
        its reason."""
        if self._logged:
            self._release_logged()
        self._mech, self._hot = None, [None, None]
        try:
            params = {self._parameters[vr]: self._values[vr] for vr in self._parameters}
            self._method = params.pop("method")
            self._mech = self._description.build(**params)
        except (TypeError, ValueError, ArithmeticError) as err:
            self.log(str(err), Fmi2Status.error)
        except Exception as err:
            self._failed("exitInitializationMode", err)

    def get_real(self, vrs):
        """The outputs ``vrs`` at the inputs set: one solve of every output; NaN and the
        reason (logged with fmi2Discard) where the state has none."""
        if self._logged:
            self._release_logged()
        x = self._x
        static = x[1] == 0.0 and x[2] == 0.0
        call = self._hot[static]
        if call is not None:
            # The compiled kernel checks what the solver would: a tuple is the outputs
            # (finite where they must be); anything else, the solver classifies.
            r = call(*x)
            if type(r) is tuple:
                if vrs == self._output_vrs:
                    return list(r)
                return self._pick(r, vrs)
        return self._solve(x, static, vrs)

    def _solve(self, x: list, static: bool, vrs) -> list:
        """The outputs ``vrs`` by the solver, which decides which kernel or formulas to
        use; NaN and the reason, logged with fmi2Discard, where the state has none."""
        try:
            if self._mech is None:
                raise ComputationError("the outputs are read before a parameter set was taken")
            solver = self._mech.solver
            r = solver.attempt(x, None, self._method)
            if self._method == "closed_form" and self._hot[static] is None:
                self._hot[static] = _compiled(solver, static)
            if type(r) is not tuple:
                self.log(r.text, Fmi2Status.discard)
                return [math.nan] * len(vrs)
            return self._pick(r, vrs)
        except Exception as err:
            self._failed("getReal", err)
            return [math.nan] * len(vrs)

    def _pick(self, r: tuple, vrs) -> list:
        try:
            outputs = self._outputs
            return [r[outputs[vr]] for vr in vrs]
        except Exception as err:
            self._failed("getReal", err)
            return [math.nan] * len(vrs)

    def do_step(self, current_time, step_size):
        return True  # the framework steps; the slave has no state of its own


def _compiled(solver, static: bool):
    """The compiled one-state kernel of every output of ``solver`` (``static``: omega =
    alpha = 0), once the solver has compiled it; else None."""
    try:
        k = solver.kernel(None, static)
    except ValueError:  # no kernel: the formulas serve every state
        return None
    return k.call if k.compiled else None

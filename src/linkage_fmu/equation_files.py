"""A linkage's equilibrium equations as a function file, in the style of the scotch yoke
worked example's MATLAB ``F(x)``: its inputs are the linkage's inputs in SI units and
in their order (``F(theta, omega, alpha, load)``), its parameters are assigned at the
top at their current values, for the user to edit, and it assembles ``A`` and ``b``
and returns ``A \\ b``, the unknowns in the order of :attr:`Equations.unknowns
<linkage_fmu.equations.Equations.unknowns>` (:func:`function_file`).

The file is the package's own formulas (kinematics, loads, equilibrium rows) traced at
one state (:mod:`linkage_fmu.kernels.trace`) and spelt in GNU Octave/MATLAB or Python
with numpy. A state that takes another branch of the formulas than the traced one (the
other assembly mode, a singular pose) stops with the reason; the assembly modes and
choices (a branch, a driver) are built in, as the header says.
"""

from __future__ import annotations

import re

from . import evaluation, kinetostatics
from .errors import InputError
from .kernels.octave_source import PICK, octave_statements
from .kernels.python_source import python_statements
from .kernels.trace import TRACE, Tape
from .loads import wrenches

#: the languages of :func:`function_file`
LANGUAGES = ("matlab", "python")


def function_name(mech) -> str:
    """The function's (and its file's) name: the linkage's, as an identifier."""
    name = re.sub(r"\W", "_", mech.name)
    return name if re.match(r"[A-Za-z]", name) else f"linkage_{name}"


def function_inputs(mech, state: dict) -> dict:
    """The inputs of the function file of ``mech`` and their values at ``state`` (each
    input of the linkage -> its value): the linkage's inputs, then each load it
    computes over the cycle (a table, an expression), which the file takes as an input.

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> function_inputs(presets.get("four_bar"), {"theta": 0.3, "omega": 1.0,
    ...                                           "alpha": 0.0, "load": 2.0})
    {'theta': 0.3, 'omega': 1.0, 'alpha': 0.0, 'load': 2.0}
    """
    if not mech.computed_loads:
        return dict(state)
    st, _, _ = evaluation.at_state(mech, *evaluation.split(mech, list(state.values()))[:3],
                                   0, None)
    return dict(state, **{ld.name: float(ld.at_state(st)) for ld in mech.loads
                          if ld.computed})


def function_file(mech, state: dict, unknowns: tuple, language: str = "matlab") -> str:
    """The function file of ``mech``'s ``A x = b``, traced at ``state`` (each input ->
    its value: :attr:`Equations.state <linkage_fmu.equations.Equations.state>`), in
    ``language`` (:data:`LANGUAGES`), returning the ``unknowns``.

    Examples
    --------
    >>> import math
    >>> from linkage_fmu import presets
    >>> from linkage_fmu.equations import equations
    >>> yoke = presets.get("scotch_yoke")
    >>> eq = equations(yoke, math.radians(60), 10.0, load=400.0)
    >>> text = eq.to("matlab")
    >>> text.splitlines()[0]
    'function x = scotch_yoke(theta, omega, alpha, load)'
    >>> namespace = {}
    >>> exec(eq.to("python"), namespace)  # our own generated code
    >>> x = namespace["scotch_yoke"](math.radians(60), 10.0, 0.0, 400.0)
    >>> round(float(x[-1]), 4)  # Mb
    15.6699
    """
    if language not in LANGUAGES:
        raise InputError(f"language {language!r}: the languages are {', '.join(LANGUAGES)}")
    if mech.friction.active:
        raise InputError(f"{mech.name}: a function file of its equations with friction is "
                         "not written (each friction depends on the reactions it is part of: "
                         "the solver iterates); its text, LaTeX and MathML are, at the "
                         "solution")
    names = [n for n in mech.kernel_parameters]
    taken = [n for n in (*names, *state) if re.fullmatch(r"t\d+|k\d+|\w+_eq|pick|sign", n)]
    if taken:
        raise InputError(f"{mech.name}: a function file names its own variables "
                         f"{', '.join(taken)}: rename the linkage's")
    state = function_inputs(mech, state)
    given = [ld.name for ld in mech.loads if ld.computed]
    tape = Tape()
    x = [tape.input(n, v) for n, v in state.items()]
    symbols = {n: tape.input(n, mech.parameters[n], parameter=True) for n in names}
    twin = mech.rebuild(symbols) if symbols else mech
    theta, omega, alpha, loads = evaluation.split(twin, x)
    st, omega, alpha = evaluation.at_state(twin, theta, omega, alpha, 2, TRACE)
    W = wrenches(twin, st, omega, alpha, evaluation.every_load(twin, tuple(given), loads),
                 False)
    about = {link: grp.moment_point(link) for grp in twin.groups for link in grp.links}
    n, entries, rhs = kinetostatics.equilibrium_entries(twin, st, W, about, 1.0)
    results = [v for _, _, v in entries] + [v for _, v in rhs]
    where = [(r, c) for r, c, _ in entries] + [(r, None) for r, _ in rhs]
    write = _matlab if language == "matlab" else _python
    own = {*names, *state}
    A, b, x = (v if v not in own else f"{v}_eq" for v in ("A", "b", "x"))
    return write(mech, tape, results, where, n, state, unknowns, (A, b, x), tuple(given))


def _header(mech, state: dict, unknowns: tuple, comment: str, given: tuple) -> list:
    units = dict(mech.input_units, **{ld.name: ld.unit for ld in mech.loads})
    specs = mech.description.parameters if mech.description is not None else {}
    fixed = [f"{k} = {v}" for k, v in mech.parameters.items()
             if k not in mech.kernel_parameters and type(v) is not float]
    at = ", ".join(f"{k} = {v!r}" for k, v in state.items())
    lines = [f"{mech.name}: the equilibrium equations A x = b, solved: x = A \\ b.",
             "Inputs, SI units: " + ", ".join(f"{k} [{units.get(k, '')}]" for k in state),
             "Returns x, the unknowns in this order (the action of each pair's first body",
             "on its second; efforts last):"]
    lines += [f"  x({i + 1}) {u}" for i, u in enumerate(unknowns)]
    lines += [f"Written by linkage_fmu, traced at {at}.",
              "A state that takes another branch of the formulas (the other assembly mode,",
              "a singular pose) stops with the reason."]
    if given:
        lines.append("The loads the linkage computes over the cycle are inputs here: "
                     + ", ".join(given) + ".")
    if fixed:
        lines.append("Built in: " + ", ".join(fixed) + ".")
    out = [f"{comment} {line}".rstrip() for line in lines]
    params = [(n, mech.parameters[n], specs.get(n, {}).get("description", ""))
              for n in mech.kernel_parameters]
    return out, params


def _matlab(mech, tape, results, where, n, state, unknowns, abx, given) -> str:
    A, b, x = abx
    name = function_name(mech)
    head, params = _header(mech, state, unknowns, "%", given)
    lines, values = octave_statements(tape, results, "  ")
    body = [f"function {x} = {name}({', '.join(state)})", *head,
            "  % parameters: edit them here",
            *(f"  {p} = {v!r};  % {d}" for p, v, d in params),
            *lines, f"  {A} = zeros({n}, {n});", f"  {b} = zeros({n}, 1);"]
    for (r, c), v in zip(where, values):
        cell = f"{A}({r + 1}, {c + 1})" if c is not None else f"{b}({r + 1})"
        body.append(f"  {cell} = {cell} + {v};")
    body += [f"  {x} = {A} \\ {b};", "end", "", *PICK, ""]
    return "\n".join(body)


def _python(mech, tape, results, where, n, state, unknowns, abx, given) -> str:
    A, b, _ = abx
    name = function_name(mech)
    head, params = _header(mech, state, unknowns, "   ", given)
    lines, values = python_statements(tape, results, "    ")
    body = ['r"""' + head[0].strip() + '"""', "", "import numpy as np",
            "from math import (acos, asin, atan, atan2, cos, degrees, hypot, inf, log, nan,",
            "                  radians, sin, sqrt, tan)", "", "",
            "def sign(x):", "    return float(x > 0.0) - float(x < 0.0)", "", "",
            f"def {name}({', '.join(state)}):", '    r"""' + head[0].strip(),
            *head[1:], '    """', "    # parameters: edit them here",
            *(f"    {p} = {v!r}  # {d}" for p, v, d in params),
            *lines, f"    {A} = np.zeros(({n}, {n}))", f"    {b} = np.zeros({n})"]
    for (r, c), v in zip(where, values):
        cell = f"{A}[{r}, {c}]" if c is not None else f"{b}[{r}]"
        body.append(f"    {cell} += {v}")
    body += [f"    return np.linalg.solve({A}, {b})", ""]
    return "\n".join(body)

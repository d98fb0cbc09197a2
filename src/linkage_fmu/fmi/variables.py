"""The FMU variables of a linkage: one table for every FMU flavour and FMI version.

Inputs first (``theta``, ``omega``, ``alpha``, then each load), then every parameter of
the linkage's description, then ``method``, then the outputs and diagnostics; value
references follow this order from 0. The drive FMU's table (:func:`drive_variables`)
has the input ``tau`` and the loads, the parameters with ``theta0``, ``omega0`` and
``tolerance``, the continuous states ``theta`` and ``omega``, the discrete state
``motion``, then ``alpha`` (the derivative of ``omega``), every output and diagnostic
(``J_red`` among them), ``der(theta)`` and the event indicators.
Everything generated for an FMU (its modelDescription, ``config.h``, the native kernels'
tables) is written from these tables (:mod:`~linkage_fmu.fmi.writers`).

Examples
--------
>>> from linkage_fmu import presets
>>> table = variables(presets.get("four_bar"))
>>> [(v.name, v.causality, v.unit) for v in table[:4]]
[('theta', 'input', 'rad'), ('omega', 'input', 'rad/s'), ('alpha', 'input', 'rad/s2'), ('load',
'input', 'N.m')]
>>> table[-1].name, table[-1].depends
('dJ_red', ('theta',))
>>> [v.options for v in variables(presets.get("four_bar"), "native") if v.name == "method"]
[('closed_form',)]
>>> drive = drive_variables(presets.get("four_bar"))
>>> [(v.name, v.causality) for v in drive[:2]], [v.name for v in drive if v.state]
([('tau', 'input'), ('load', 'input')], ['theta', 'omega'])
>>> [(v.name, v.derivative) for v in drive if v.derivative]
[('alpha', 'omega'), ('der(theta)', 'theta')]
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any

from ..drivers import one_crank
from ..errors import InputError
from ..mechanism import METHODS
from ..units import MOTION_UNITS

_MOTION_INFO = {
    "theta": (MOTION_UNITS["theta"], "deg", "crank angle from +x, counter-clockwise"),
    "omega": (MOTION_UNITS["omega"], "", "crank angular speed"),
    "alpha": (MOTION_UNITS["alpha"], "", "crank angular acceleration"),
}
#: the solvers of each flavour's ``method`` parameter, and what it says of them
FLAVOURS = {
    "pythonfmu": (METHODS, "solver: one of closed_form, direct, interpreted (closed form, or "
                           "the assembled reference LU)"),
    "native": (("closed_form",), "solver: closed_form (a native FMU computes the closed form; "
                                 "its check runs it against the direct solver)"),
}


@dataclass(frozen=True)
class Variable:
    """One FMU variable: FMI type (Real, Integer, String), causality (input, parameter,
    output), variability (continuous, fixed), units, meaning, start value, for an output
    the inputs it depends on; for a parameter the rule its value meets (``rule``: a
    Real's ``> 0``, ``>= 0`` or ``finite``, with ``minimum`` and ``maximum``; in words
    for an Integer, whose values are ``allowed``, and a String, whose are ``options``);
    ``index``: its position among the variables of its causality (a continuous state's
    among the states, a derivative's among the computed outputs); ``state``: a
    continuous state; ``derivative``: the name of the state it is the derivative of;
    ``event``: an event indicator; ``discrete``: a discrete state of the model."""

    name: str
    type: str
    causality: str
    variability: str
    unit: str = ""
    display_unit: str = ""
    description: str = ""
    start: Any = None
    depends: tuple = ()
    index: int = 0
    rule: str = "finite"
    minimum: float = -math.inf
    maximum: float = math.inf
    allowed: tuple = ()
    options: tuple = ()
    state: bool = False
    derivative: str = ""
    #: computed by the model as its outputs are, for model exchange's event indicators
    event: bool = False
    #: a discrete state the model changes itself (at events), read but never set
    discrete: bool = False


#: the smallest positive float64: the inclusive ``min`` that says ``> 0``
SMALLEST_POSITIVE = math.nextafter(0.0, 1.0)


def bounds(v: Variable) -> tuple[float | None, float | None]:
    """The ``min`` and ``max`` a modelDescription declares for ``v`` (``None``: none):
    those of the rule the FMU's validation enforces (``config.h`` holds the same
    ``rule``, ``minimum``, ``maximum`` and ``allowed``), inclusive as FMI's are: ``> 0``
    is ``min`` the smallest positive float64, ``>= 0`` is ``min`` 0, ``+1 or -1`` is
    [-1, 1] (the values between are refused too), an Integer's allowed values give
    their least and greatest; a String has none.

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> table = {v.name: v for v in drive_variables(presets.get("four_bar"))}
    >>> [bounds(table[n]) for n in ("l_AB", "m1", "mu_A", "beta1", "branch", "tolerance")]
    [(5e-324, None), (0.0, None), (0.0, 1000.0), (None, None), (-1, 1), (1e-14, 0.1)]
    """
    if v.type == "Integer" and v.allowed:
        return min(v.allowed), max(v.allowed)
    if v.type != "Real" or v.causality != "parameter":
        return None, None
    low, high = v.minimum, v.maximum
    if v.rule == "> 0":
        low = max(low, SMALLEST_POSITIVE)
    elif v.rule == ">= 0":
        low = max(low, 0.0)
    elif v.rule == "+1 or -1":
        low, high = max(low, -1.0), min(high, 1.0)
    return (low if math.isfinite(low) else None), (high if math.isfinite(high) else None)


def _one_of(options) -> str:
    return "one of " + ", ".join(repr(str(o)) for o in options)


def variables(mech, flavour: str = "pythonfmu") -> list[Variable]:
    """The variable table of the linkage ``mech`` (built from a description) in the FMU
    ``flavour`` (``pythonfmu`` or ``native``: they differ in the solvers ``method``
    offers)."""
    methods, method_text = FLAVOURS[flavour]
    d = mech.description
    table = []
    motion = mech.input_table.motion  # the driver's inputs
    for k, name in enumerate(motion):
        if mech.rates:  # each driver's coordinate, speed, acceleration
            driver = mech.drivers[k // 3]
            unit, text = driver.units[k % 3], driver.meaning(k % 3)
            display = "deg" if unit == "rad" else ""
        else:
            unit, display, text = _MOTION_INFO[name]
        table.append(Variable(name, "Real", "input", "continuous", unit, display, text,
                              float(mech.start[name]), index=k))
    # a load over the cycle is computed inside: no input
    for k, load in enumerate(mech.input_loads, len(motion)):
        text = load.description or f"{load.kind} on link {load.body}"
        table.append(Variable(load.name, "Real", "input", "continuous", load.unit, "", text,
                              float(load.start), index=k))
    table += _parameters(mech)
    table.append(Variable("method", "String", "parameter", "fixed", "", "", method_text,
                          "closed_form", index=len(d.parameters), rule=_one_of(methods),
                          options=tuple(methods)))
    inputs = mech.input_names
    for k, name in enumerate(mech.output_names + mech.diagnostic_names):
        table.append(_output(mech, name, inputs, k))
    return table


def _output(mech, name: str, inputs: tuple, index: int) -> Variable:
    """The output ``name`` of the linkage, computed from ``inputs``."""
    unit, text = mech.output_info[name]
    # a diagnostic is a function of the position only
    coordinates = tuple(d.inputs[0] for d in mech.drivers)
    depends = coordinates if name in mech.diagnostic_names else inputs
    return Variable(name, "Real", "output", "continuous", unit, "deg" if unit == "rad" else "",
                    text, None, depends, index=index)


def _parameters(mech, choices: dict | None = None, notes: dict | None = None
                ) -> list[Variable]:
    """The variables of the parameters of the linkage's description; a choice named in
    ``choices`` takes only the values listed there, and a parameter named in ``notes``
    has that note after its description."""
    table = []
    for k, p in enumerate(mech.description.parameter_specs()):
        value = mech.parameters[p.name]
        note = (notes or {}).get(p.name, "")
        if p.kind == "branch":
            table.append(Variable(p.name, "Integer", "parameter", "fixed", "", "", p.description,
                                  int(value), index=k, rule="+1 or -1", allowed=(1, -1)))
        elif p.kind == "choice":
            options = tuple(map(str, (choices or {}).get(p.name, p.choices)))
            table.append(Variable(p.name, "String", "parameter", "fixed", "", "",
                                  f"{p.description} (one of {', '.join(options)}{note})",
                                  str(value), index=k, rule=_one_of(options), options=options))
        elif note:
            table.append(Variable(p.name, "Real", "parameter", "fixed", p.unit, "",
                                  f"{p.description} ({note})", float(value), index=k,
                                  rule=p.rule, minimum=-math.inf if p.minimum is None else
                                  float(p.minimum), maximum=math.inf if p.maximum is None
                                  else float(p.maximum)))
        else:
            table.append(Variable(
                p.name, "Real", "parameter", "fixed", p.unit, "deg" if p.unit == "rad" else "",
                p.description, float(value), index=k, rule=p.rule,
                minimum=-math.inf if p.minimum is None else float(p.minimum),
                maximum=math.inf if p.maximum is None else float(p.maximum)))
    return table


#: the drive FMU's default integrator tolerance (relative and absolute), and the smallest
#: it takes: below it float64's rounding of theta and omega exceeds the error it asks for
TOLERANCE, FINEST = 1e-8, 1e-14


def crank_choices(mech) -> dict:
    """The values of each choice parameter of ``mech`` with which its balancing effort is a
    moment on its crank (the others' values as ``mech`` has them): what a drive FMU, whose
    input is that moment, can be built for.

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> crank_choices(presets.get("six_bar"))
    {'driver': ('OA',)}
    """
    d = mech.description
    return {p.name: tuple(c for c in p.choices if d.build(**{p.name: c}).effort_on_crank)
            for p in d.parameter_specs() if p.kind == "choice"}


#: the drive FMU's discrete state: how the crank moves (+1 forwards, -1 backwards, 0 stuck)
MOTION_STATE = "motion"
#: the drive FMU's event indicators (model exchange), each > 0 where the crank turns, or is
#: pushed past the friction band, that way, and never 0 on the side the motion in force is on
EVENT_INDICATORS = ("z_forwards", "z_backwards")


def drive_variables(mech) -> list[Variable]:
    """The variable table of the drive FMU of ``mech``: the linkage driven by a moment
    ``tau`` on its crank, its motion integrated from ``theta0`` and ``omega0`` (the
    linkage's start values) to the tolerance ``tolerance``, with the friction of its
    joints (its ``mu`` and radii are parameters like any other). A choice parameter
    takes only the values with which the effort stays a moment on the crank
    (:func:`crank_choices`: the six-bar's ``driver`` only ``OA``); ``drive`` is not
    used (at rest, friction opposes the motion the crank takes or is pushed to).
    Besides: the discrete state ``motion`` (+1, -1, 0: stuck in the friction band) and
    the event indicators ``z_forwards`` and ``z_backwards`` of model exchange.

    Raises
    ------
    ValueError
        The linkage's balancing effort is not a moment on its crank: it cannot be driven
        by one; a linkage driven by time (several drivers, a motor, a cylinder: so far,
        ``simulate`` moves it).
    """
    one_crank(mech, "a drive FMU")
    if not mech.effort_on_crank:
        raise InputError(f"{mech.name}: its balancing effort {mech.effort.name} is not a "
                         "moment on the crank, so it cannot be driven by a torque (a drive "
                         "FMU needs a linkage whose effort is Mb)")
    table = [Variable("tau", "Real", "input", "continuous", "N.m", "",
                      "moment of the drive on the crank, counter-clockwise positive", 0.0)]
    for k, load in enumerate(mech.input_loads, 1):
        text = load.description or f"{load.kind} on link {load.body}"
        table.append(Variable(load.name, "Real", "input", "continuous", load.unit, "", text,
                              float(load.start), index=k))
    choices = crank_choices(mech)
    notes = {name: ": a drive FMU drives the crank" for name, options in choices.items()
             if len(options) < len(mech.description.parameters[name]["choices"])}
    drive = mech.description.drive
    if drive in mech.parameters:
        notes[drive] = ("not used by the drive FMU: at rest, friction opposes the motion "
                        "the crank takes or is pushed to")
    table += _parameters(mech, choices, notes)
    n = len(mech.description.parameters)
    for k, name in enumerate(("theta", "omega")):
        unit, display, text = _MOTION_INFO[name]
        table.append(Variable(f"{name}0", "Real", "parameter", "fixed", unit, display,
                              f"{text} at the start", float(mech.start[name]), index=n + k))
    table.append(Variable("tolerance", "Real", "parameter", "tunable", "1", "",
                          "the co-simulation integrator's tolerance, relative and absolute, "
                          "on theta [rad] and omega [rad/s]; tunable: it may be set between "
                          "steps too, and holds from the next", TOLERANCE, index=n + 2,
                          rule="> 0", minimum=FINEST, maximum=0.1))
    moved = ("theta", "omega", "tau") + tuple(load.name for load in mech.input_loads)
    for k, name in enumerate(("theta", "omega")):
        unit, display, text = _MOTION_INFO[name]
        table.append(Variable(name, "Real", "output", "continuous", unit, display,
                              f"{text} (a continuous state)", None, index=k, state=True))
    table.append(Variable(MOTION_STATE, "Integer", "local", "discrete", "", "",
                          "how the crank moves: +1 forwards (counter-clockwise), -1 backwards, "
                          "0 stuck (at rest, tau inside the friction band: Mb is tau, the other "
                          "outputs those at rest with friction at its limit at the band's edge "
                          "on tau's side of its middle); a discrete state",
                          None, index=n + 3, allowed=(1, 0, -1), rule="+1, 0 or -1",
                          discrete=True))
    unit, display, text = _MOTION_INFO["alpha"]
    table.append(Variable("alpha", "Real", "output", "continuous", unit, display,
                          f"{text}: the root of tau = Mb(theta, omega, alpha) with friction; 0 "
                          "while the crank sticks", None, moved, index=0, derivative="omega"))
    names = mech.output_names + mech.diagnostic_names
    for k, name in enumerate(names, 1):
        v = _output(mech, name, moved, k)
        if name == mech.effort.name:  # the drive's: what the linkage takes from the crank
            v = replace(v, description=f"{v.description}: equal to tau, while the "
                                    "crank moves and while it sticks (the linkage holds it)")
        table.append(v)
    table.append(Variable("der(theta)", "Real", "local", "continuous", "rad/s", "",
                          "derivative of theta: omega", None, ("omega",), index=len(names) + 1,
                          derivative="theta"))
    for k, (name, way) in enumerate(zip(EVENT_INDICATORS, ("forwards", "backwards"))):
        sign = "" if way == "forwards" else "-"
        other = "backwards" if way == "forwards" else "forwards"
        edge = "Mb(drive = +1) at rest" if way == "forwards" else "Mb(drive = -1) at rest"
        text = (f"event indicator: {sign}omega while the crank turns {way} (DBL_MIN as it "
                f"leaves rest), -1 while it turns {other}, and while it sticks "
                f"{'tau - ' + edge if way == 'forwards' else edge + ' - tau'} (> 0: it breaks "
                f"away {way}; -DBL_MIN at the edge); 1 without friction")
        table.append(Variable(name, "Real", "local", "continuous", "", "", text, None,
                              moved, index=len(names) + 2 + k, event=True))
    return table

"""The FMU variables of a linkage: one table for every FMU flavour.

Inputs first (``theta``, ``omega``, ``alpha``, then each load), then every parameter of
the linkage's description, then ``method``, then the outputs and diagnostics; value
references follow this order from 0.

Examples
--------
>>> from linkage_fmu import presets
>>> table = variables(presets.get("four_bar"))
>>> [(v.name, v.causality, v.unit) for v in table[:4]]
[('theta', 'input', 'rad'), ('omega', 'input', 'rad/s'), ('alpha', 'input', 'rad/s2'), ('load', 'input', 'N.m')]
>>> table[-1].name, table[-1].depends
('cond', ('theta',))
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from ..mechanism import METHODS, MOTION

_MOTION_INFO = {
    "theta": ("rad", "deg", "crank angle from +x, counter-clockwise"),
    "omega": ("rad/s", "", "crank angular speed"),
    "alpha": ("rad/s2", "", "crank angular acceleration"),
}


@dataclass(frozen=True)
class Variable:
    """One FMU variable: FMI type (Real, Integer, String), causality (input, parameter,
    output), variability (continuous, fixed), units, meaning, start value, and for an
    output the inputs it depends on."""

    name: str
    type: str
    causality: str
    variability: str
    unit: str = ""
    display_unit: str = ""
    description: str = ""
    start: Any = None
    depends: tuple = ()


def variables(mech) -> list[Variable]:
    """The variable table of the linkage ``mech`` (built from a description)."""
    d = mech.description
    start = dict(d.inputs)
    table = []
    for name in MOTION:
        unit, display, text = _MOTION_INFO[name]
        table.append(Variable(name, "Real", "input", "continuous", unit, display, text,
                              float(start.get(name, 0.0))))
    for load in mech.loads:
        text = load.description or f"{load.kind} on link {load.body}"
        table.append(Variable(load.name, "Real", "input", "continuous", load.unit, "", text,
                              float(load.start)))
    for p in d.parameter_specs():
        value = mech.parameters[p.name]
        if p.kind == "branch":
            table.append(Variable(p.name, "Integer", "parameter", "fixed", "", "",
                                  p.description, int(value)))
        elif p.kind == "choice":
            table.append(Variable(p.name, "String", "parameter", "fixed", "", "",
                                  f"{p.description} (one of {', '.join(map(str, p.choices))})",
                                  str(value)))
        else:
            table.append(Variable(p.name, "Real", "parameter", "fixed", p.unit,
                                  "deg" if p.unit == "rad" else "", p.description, float(value)))
    table.append(Variable("method", "String", "parameter", "fixed", "", "",
                          f"solver: one of {', '.join(METHODS)} (closed form, or the "
                          "assembled reference LU)", "closed_form"))
    inputs = mech.input_names
    for name in mech.output_names + mech.diagnostic_names:
        unit, text = mech.output_info[name]
        # a diagnostic is a function of the position only
        depends = ("theta",) if name in mech.diagnostic_names else inputs
        table.append(Variable(name, "Real", "output", "continuous", unit,
                              "deg" if unit == "rad" else "", text, None, depends))
    return table

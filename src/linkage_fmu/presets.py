"""The shipped linkages: description files in ``linkage_fmu/linkages``, with the
specification's parameter and output names.

Each preset is a description file like any user's (see :mod:`linkage_fmu.descriptions`); none
has a solver of its own.

Examples
--------
>>> from linkage_fmu import presets
>>> presets.names()
('scotch_yoke', 'four_bar', 'six_bar', 'slider_crank', 'slotted_lever',
'crank_shaper')
>>> mech = presets.get("four_bar", l_AB=0.12)
>>> mech.output_names
('F21x', 'F21y', 'F32x', 'F32y', 'F43x', 'F43y', 'F14x', 'F14y', 'Mb', 'Mf_A',
'Mf_B', 'Mf_C', 'Mf_D', 'P_loss', 'eta', 'shake_x', 'shake_y', 'shake_M')
>>> presets.get("four_bar", l_ab=0.12)
Traceback (most recent call last):
...
linkage_fmu.errors.InputTypeError:
four_bar has no parameter 'l_ab'; its parameters are: l_AB, l_BC,
l_CD, l_AD, m1, J1, l_AS1, beta1, m2, J_S2, l_BS2, beta2, m3, J_S3, l_DS3,
beta3, g, branch, mu_A, r_A, mu_B, r_B, mu_C, r_C, mu_D, r_D, drive
"""

from __future__ import annotations

import functools
from pathlib import Path

from .descriptions import Description
from .errors import InputError, InputTypeError
from .mechanism import Mechanism

FOLDER = Path(__file__).with_name("linkages")
#: the presets, in the specification's order
NAMES = ("scotch_yoke", "four_bar", "six_bar", "slider_crank", "slotted_lever", "crank_shaper")


def names() -> tuple:
    """Names of the presets."""
    return NAMES


def path(name: str) -> Path:
    """The description file of the preset ``name``."""
    if name not in NAMES:
        raise InputError(f"no preset {name!r}; the presets are: {', '.join(NAMES)}")
    return FOLDER / f"{name}.toml"


@functools.cache
def preset(name: str) -> Description:
    """The description of the preset ``name`` (parameters, loads, input start values).

    The description is shared: copy it (``.copy()``) before changing it.
    """
    return Description.read(path(name)).check()


def get(name: str, **parameters) -> Mechanism:
    """Build the preset ``name`` with ``parameters`` overriding its defaults.

    Raises a ``TypeError`` for an unknown parameter name and a ``ValueError`` for an
    invalid value, naming the parameter.

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> mech = presets.get("slider_crank", e=0.01)
    >>> round(mech.solve(0.5, omega=100.0, load=1000.0)["Mb"], 3)
    -14.315
    """
    return preset(name).build(**parameters)


def linkage(source, **parameters) -> Mechanism:
    """The Mechanism of ``source``: a preset's name, a description file's path, a
    :class:`~linkage_fmu.descriptions.Description`, or a Mechanism built from a description
    (then ``parameters`` must be empty), with ``parameters`` overriding the defaults.

    Examples
    --------
    >>> linkage("four_bar", l_AB=0.12).parameters["l_AB"]
    0.12
    """
    if isinstance(source, Mechanism):
        if parameters:
            raise InputTypeError("parameters apply to a description, not to a built Mechanism")
        if source.description is None:
            raise InputError(f"{source.name} was not built from a description")
        return source
    if isinstance(source, Description):
        return source.build(**parameters)
    if str(source) in NAMES:
        return get(str(source), **parameters)
    return Description.read(source).build(**parameters)

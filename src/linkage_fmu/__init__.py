"""Kinetostatic analysis of crank-driven planar linkages.

Every joint reaction and the driving torque at any crank angle, speed, acceleration and
load, as a library (scalars or numpy arrays) and as FMI co-simulation FMUs.

Examples
--------
>>> from linkage_fmu import presets
>>> mech = presets.get("four_bar")
>>> sol = mech.solve(0.3, omega=10.0)
>>> sorted(sol)[:3]
['F14x', 'F14y', 'F21x']
"""

from pathlib import Path

from . import presets
from .descriptions import Description, DescriptionError
from .errors import (
    AssemblyError,
    LinkageFmuError,
    NearSingularWarning,
    OverflowInputError,
    SelfLockingError,
    SingularPositionError,
)
from .mechanism import Mechanism, Solution

__version__ = "0.1.0"
__all__ = ["presets", "load", "Description", "DescriptionError", "Mechanism", "Solution",
           "LinkageFmuError", "AssemblyError", "SingularPositionError", "OverflowInputError",
           "SelfLockingError", "NearSingularWarning", "__version__"]


def load(path: str | Path, **parameters) -> Mechanism:
    """Build the linkage described by the file at ``path`` (or the preset of that name),
    with ``parameters`` overriding its defaults.

    Raises
    ------
    DescriptionError
        The file has problems; all of them are listed, each with its table and key.
    TypeError, ValueError
        An unknown parameter, or an invalid value, named.

    Examples
    --------
    >>> import linkage_fmu
    >>> mech = linkage_fmu.load("four_bar", l_AB=0.12)
    >>> mech.input_names
    ('theta', 'omega', 'alpha', 'load')
    """
    return presets.linkage(str(path), **parameters)

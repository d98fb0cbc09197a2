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

from . import presets
from .errors import AssemblyError, SingularPositionError
from .mechanism import Mechanism, Solution

__version__ = "0.1.0"
__all__ = ["presets", "Mechanism", "Solution", "AssemblyError", "SingularPositionError",
           "__version__"]

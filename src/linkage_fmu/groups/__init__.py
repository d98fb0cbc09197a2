"""Group types: the crank, the Assur groups and points fixed on links, one class each.

Every type derives from :class:`~linkage_fmu.groups.base.Group`, which states the
contract (kinematics at three orders, closed-form statics, equilibrium rows through its
joints, transmission angle, construction from a description file: its ``FIELDS``, each a
:class:`~linkage_fmu.groups.base.Field`, its ``OPTIONAL`` ones, whether it is the
``DRIVER``, and the ``pairs`` its fields make; and, for a type a linkage written as
joints and links may show, its :class:`~linkage_fmu.groups.base.Drawing` and how it
recognises it). A new type is one class in one module here; importing it registers its
``kind`` for description files.

Examples
--------
>>> from linkage_fmu import groups
>>> sorted(groups.Group.registry)
['RPP', 'RPR', 'RRP', 'RRR', 'closure', 'crank', 'cylinder', 'point']
"""

from .base import (
                   FRAME,
                   OWNER,
                   ROLE_MEANINGS,
                   ROLES,
                   Drawing,
                   Field,
                   Group,
                   KinematicState,
                   LinkJoints,
)
from .closure import Closure
from .crank import Crank
from .cylinder import Cylinder
from .point import LinkPoint
from .rpp import RPP
from .rpr import RPR
from .rrp import RRP
from .rrr import RRR

__all__ = ["Group", "Field", "ROLES", "ROLE_MEANINGS", "KinematicState", "FRAME",
           "OWNER", "LinkJoints", "Crank", "Cylinder", "RRR", "RRP", "RPP", "RPR", "LinkPoint",
           "Closure",
           "Drawing"]

"""Group types: the crank, the Assur groups and points fixed on links, one class each.

Every type derives from :class:`~linkage_fmu.groups.base.Group`, which states the
contract (kinematics at three orders, closed-form statics, equilibrium rows through its
joints, transmission angle, construction from a description file). A new type is one
class in one module here; importing it registers its ``kind`` for description files.

Examples
--------
>>> from linkage_fmu import groups
>>> sorted(groups.Group.registry)
['RPP', 'RPR', 'RRP', 'RRR', 'crank', 'point']
"""

from .base import FRAME, OWNER, Group, Joint, KinematicState
from .crank import Crank
from .point import LinkPoint
from .rpp import RPP
from .rpr import RPR
from .rrp import RRP
from .rrr import RRR

__all__ = ["Group", "Joint", "KinematicState", "FRAME", "OWNER", "Crank", "RRR", "RRP", "RPP",
           "RPR", "LinkPoint"]

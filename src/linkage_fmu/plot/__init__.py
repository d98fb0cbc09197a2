"""Plots of a linkage's kinetostatics: driving torque, pin-force polars, the linkage
with its joint forces and loads, transmission angles, the shaking force and moment, and
the crank's speed over a cycle with a flywheel, the power friction dissipates with
the efficiency, an optimisation's convergence, and the linkage in motion with its
forces (:func:`animate`, a GIF or an MP4).

Every public function returns a :class:`matplotlib.figure.Figure` and draws into the
``ax`` given, or into a new figure (made with :mod:`matplotlib.pyplot`, so ``plt.show()``
shows it). matplotlib is needed only here: ``pip install "linkage_fmu[plot]"``.

Angles: ``theta`` is the crank angle in radians (as in :meth:`Mechanism.solve
<linkage_fmu.Mechanism.solve>`), or give ``theta_deg`` in degrees instead; without
either, a revolution of :data:`N_ANGLES` angles 0, 0.5, ..., 360 degrees. The plots'
horizontal axes are in degrees: the given ``theta_deg`` itself, else ``degrees(theta)``.

Inputs: ``omega``, ``alpha`` and each load (by position after ``alpha``, as in
:meth:`~linkage_fmu.Mechanism.solve`, or by name) that are not given take the linkage's
start values (its ``[inputs]`` table and each load's ``start``), as ``mech.solve`` and
``linkage-fmu table`` do; a load over the cycle is computed at each angle unless given
by name.

What is drawn carries a ``gid`` (``artist.get_gid()``), so that scripts and tests can
find it: the curves by output name, ``"mean"``, ``"peak"``, ``"origin"``,
``"forces"`` (a quiver), ``"load:<name>"``, ``"toggle:<gamma>"`` and so on (see each
function).

Examples
--------
>>> import matplotlib
>>> matplotlib.use("Agg")
>>> import io
>>> from linkage_fmu import plot, presets
>>> mech = presets.get("four_bar")
>>> fig = plot.torque(mech, omega=10.0, load=5.0)
>>> fig.savefig(io.BytesIO(), format="png")
>>> [p.name for p in plot.force_pairs(mech)]
['F21', 'F32', 'F43', 'F14']
"""

from .animation import N_FRAMES, LinkageAnimation, animate
from .convergence import convergence
from .curves import ZERO_FRACTION, loss, polar, revolution_mean, rounded, shaking, torque
from .inputs import N_ANGLES
from .parts import ForcePair, force_pairs, hull, link_points
from .picture import ARROW_FRACTION, MOMENT_FRACTION, linkage
from .placement import place_boxes
from .speed import speed
from .transmission_angles import TOGGLE_TOL, toggles, transmission

__all__ = ["torque", "polar", "linkage", "transmission", "shaking", "speed", "loss",
           "convergence", "animate", "LinkageAnimation", "N_FRAMES",
           "ForcePair",
           "force_pairs", "link_points", "hull", "revolution_mean", "rounded", "toggles",
           "place_boxes", "N_ANGLES", "ARROW_FRACTION", "MOMENT_FRACTION", "TOGGLE_TOL",
           "ZERO_FRACTION"]

"""The artist that places the labels of the linkage's picture each time the figure is
drawn (:func:`~linkage_fmu.plot.placement.place_boxes` in display pixels). It needs
matplotlib, so the picture imports it only when it draws."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from .placement import line_boxes, place_boxes

try:  # an artist; without matplotlib this still imports, and figures.pyplot() says so
    from matplotlib.artist import Artist as _Artist
    from matplotlib.text import Text as _Text
except ImportError:  # pragma: no cover
    _Artist = _Text = object

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes


class LabelPlacer(_Artist):
    """Places the labels of :func:`linkage` where they do not overlap, at each draw,
    before the labels are drawn and once the layout has fixed the axes' transform (the
    size of a text is in points and the linkage in metres, so where they collide
    depends on the figure): with :func:`place_boxes` in display pixels, in the order
    they were added, kept off each other, the marks (joint circles), the frame points'
    symbols, the scale's key, the arrows (:attr:`quivers`, shaft and head as drawn),
    the moments' arcs and the guides (:attr:`curves`, :attr:`heads`) and the links'
    lines and plates' edges (:attr:`segments`, drawn at most :attr:`LINK_PT` wide);
    inside the axes unless no spot there is clear (a cost of :attr:`LEAVE_PT` more
    distance: in practice, never). A label farther than :attr:`LEADER_PT` from its
    anchor gets a thin line to it."""

    GAP_PT = 3.0  # spacing of the rings, and the least gap between labels
    MARK_PT = 5.0  # half the side of the square kept clear about a mark
    LEADER_PT = 16.0
    LEAVE_PT = 1e5
    LINK_PT = 3.0  # the widest line a link is drawn with

    def __init__(self, ax: "Axes"):
        super().__init__()
        self.set_zorder(-math.inf)  # drawn before the axes' other artists
        self.set_in_layout(False)
        self.labels: list = []  # (annotation, anchor [m], preferred direction [m])
        self.marks = np.empty((0, 2))  # [m]
        self.blocks = np.empty((0, 4))  # x0, y0, x1, y1 [m]: the frame points' symbols
        self.segments = np.empty((0, 4))  # x, y, u, v [m]: the links' lines
        self.quivers: list = []  # matplotlib Quivers: their arrows
        self.curves: list = []  # (points (n, 2) [m], line width [pt]): arcs, guides
        self.heads: list = []  # (x, y [m], size [pt]): an arc's head, its tip at x, y
        self.key = None
        ax.add_artist(self)

    def add(self, text: str, xy, toward, color: str, **kwargs):
        """A label ``text`` of the point ``xy`` [m], preferably in the direction of the
        vector ``toward`` [m] from it."""
        ann = self.axes.annotate(
            text, xy, xytext=(0.0, 0.0), textcoords="offset points", ha="center",
            va="center", color=color, arrowprops=dict(arrowstyle="-", color=color, lw=0.6,
                                                      shrinkA=1.0, shrinkB=2.0), **kwargs)
        ann.arrow_patch.set_visible(False)
        ann.set_in_layout(False)  # placed after the layout: it must not move the axes
        self.labels.append((ann, np.asarray(xy, float), np.asarray(toward, float)))
        return ann

    def _taken(self, renderer, px: float) -> np.ndarray:
        """The boxes [display px] labels keep off: the marks, the frame points'
        symbols, the scale's key, the arrows, the arcs and their heads, the guides,
        the links' lines."""
        to = self.axes.transData.transform
        m = self.MARK_PT * px
        marks = to(self.marks).reshape(-1, 2)
        blocks = to(self.blocks.reshape(-1, 2)).reshape(-1, 4)
        boxes = [np.c_[marks - m, marks + m], np.c_[np.minimum(blocks[:, :2], blocks[:, 2:]),
                                                    np.maximum(blocks[:, :2], blocks[:, 2:])]]
        if self.key is not None and self.key.get_visible():
            key = self.key
            x, y = self.axes.transAxes.transform((key.X, key.Y))
            length = abs(to((key.U, 0.0))[0] - to((0.0, 0.0))[0])  # the key's tip is at X
            text = key.text.get_window_extent(renderer)
            half = max(0.5 * text.height, 3.0 * px)
            sep = 7.2 * px  # QuiverKey's labelsep, 0.1 inch
            boxes.append([[x - length, y - half, x + sep + text.width, y + half]])
        for q in self.quivers:
            boxes.append(self._arrows(q, px))
        for xy, width in self.curves:
            boxes.append(line_boxes(to(np.reshape(xy, (-1, 2))), 0.5 * width * px, px))
        for x, y, size in self.heads:
            (hx, hy), h = to((x, y)), size * px
            boxes.append([[hx - h, hy - h, hx + h, hy + h]])
        boxes.append(self._lines(px))
        return np.concatenate([np.reshape(b, (-1, 4)) for b in boxes])

    def _arrows(self, q, px: float) -> np.ndarray:
        """Boxes [display px] covering the arrows of the quiver ``q`` (drawn with
        ``angles="xy", scale_units="xy", scale=1``: from its tail to its tip in data
        coordinates; its ``width`` a fraction of the axes' width): the shaft half its
        width either side, the head (``headlength`` widths long) ``headwidth / 2``."""
        if not q.get_visible():
            return np.empty((0, 4))
        to = self.axes.transData.transform
        w = q.width * self.axes.bbox.width
        xy = np.c_[q.X, q.Y].reshape(-1, 2)
        uv = np.c_[q.U, q.V].reshape(-1, 2)
        tail = {"tail": xy, "tip": xy - uv}.get(q.pivot, xy - 0.5 * uv)
        boxes = [np.empty((0, 4))]
        for a, b in zip(to(tail), to(tail + uv)):
            length = float(np.hypot(*(b - a)))
            d = (b - a) / length if length > 0.0 else np.zeros(2)
            boxes.append(line_boxes(np.array([a, b]), 0.5 * w, px))
            head = np.array([b - q.headlength * w * d, b])
            boxes.append(line_boxes(head, 0.5 * q.headwidth * w, px))
        return np.concatenate(boxes)

    def _lines(self, px: float) -> np.ndarray:
        """Boxes [display px] covering the segments drawn :attr:`LINK_PT` wide."""
        to = self.axes.transData.transform
        boxes = [np.empty((0, 4))]
        for x, y, u, v in self.segments:
            boxes.append(line_boxes(to([(x, y), (x + u, y + v)]), 0.5 * self.LINK_PT * px, px))
        return np.concatenate(boxes)

    def draw(self, renderer):
        labels = [(a, xy, d) for a, xy, d in self.labels if a.get_visible()]
        if not self.get_visible() or not labels:
            return
        px = renderer.points_to_pixels(1.0)
        to = self.axes.transData.transform
        anchors, sizes, toward, shifts = [], [], [], []
        for ann, xy, direction in labels:
            ann.update_positions(renderer)
            box = _Text.get_window_extent(ann, renderer)  # the text, not its leader
            at = to(xy)
            d = to(xy + direction) - at
            anchors.append(at)
            sizes.append((box.width, box.height))
            toward.append(math.atan2(d[1], d[0]) if np.hypot(*d) > 0 else math.pi / 4)
            # the box's centre from the text's position (its alignment, its descent)
            shifts.append(np.array(box.corners().mean(axis=0)) -
                          ann.get_transform().transform(ann.xyann))
        centres, distances = place_boxes(
            anchors, sizes, toward, self._taken(renderer, px), self.axes.bbox.extents,
            self.GAP_PT * px, leave=self.LEAVE_PT * px)
        for (ann, _, _), at, centre, shift, r in zip(labels, anchors, centres, shifts,
                                                      distances):
            offset = tuple((centre - shift - at) / px)
            if not np.allclose(offset, ann.xyann, rtol=0.0, atol=1e-3):
                ann.xyann = offset  # only if it moved: no redraw for nothing
            leader = bool(r > self.LEADER_PT * px)
            if ann.arrow_patch.get_visible() != leader:
                ann.arrow_patch.set_visible(leader)

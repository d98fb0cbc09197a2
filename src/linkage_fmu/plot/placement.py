"""Where labels go: :func:`place_boxes` puts boxes near their anchors, clear of each
other and of what they should not cover; plain numpy, in any unit of length."""

from __future__ import annotations

import math

import numpy as np

from ..errors import InputError


def _overlapping(boxes: np.ndarray, taken: np.ndarray, pad: float) -> np.ndarray:
    """For each of ``boxes`` (rows ``x0, y0, x1, y1``), whether it comes within ``pad``
    of any of ``taken``."""
    b, t = boxes[:, None, :], taken[None, :, :]
    return ((b[..., 0] < t[..., 2] + pad) & (t[..., 0] < b[..., 2] + pad) &
            (b[..., 1] < t[..., 3] + pad) & (t[..., 1] < b[..., 3] + pad)).any(axis=1)


#: the directions tried about a label's anchor: the preferred one, then the others in
#: pairs on either side of it, 22.5 degrees apart
_TURNS = np.radians(22.5) * np.array([0] + [s * k for k in range(1, 9) for s in (1, -1)][:15])


def place_boxes(anchors, sizes, toward, taken=(), frame=None, gap: float = 1.0,
                avoid=(), cover: float = 0.0, leave: float = math.inf
                ) -> tuple[np.ndarray, np.ndarray]:
    """Centres for boxes of the ``sizes`` ``(w, h)``, each near its anchor, such that no
    two come within ``gap`` of each other or of the boxes ``taken``.

    Each box in turn, from the first, is tried on rings about its anchor (distances
    ``gap * (1, 2, 4, 7, 11, ...)`` from the anchor to the box's edge) in 16 directions
    22.5 degrees apart, the direction ``toward`` [rad] first, then the others by how far
    they turn from it. Of the spots clear of the boxes placed before it and of
    ``taken``, it takes the one of least cost: its distance, plus ``cover`` if it comes
    within ``gap`` of one of the boxes ``avoid`` (lines it had better not hide), plus
    ``leave`` if it is not inside ``frame`` (``x0, y0, x1, y1``); of equal costs, the
    first tried. Where no ring has a clear spot inside ``frame``, the box goes to the
    clear spot inside it nearest its anchor on a grid ``gap`` apart, if there is one.
    Any unit of length will do (display pixels in :func:`linkage`); the result depends
    on nothing else.

    Returns
    -------
    centres : ndarray, shape (n, 2)
    distances : ndarray, shape (n,)
        From each anchor to its box's edge along the direction taken.

    Examples
    --------
    Two boxes 4 wide and 2 high anchored at the same point, both wanting to lie to its
    right: the first does, one gap away; the second, kept a gap off the first, takes
    the first clear direction on the same ring, turned 157.5 degrees to the upper left.

    >>> centres, distances = place_boxes([(0, 0), (0, 0)], [(4, 2), (4, 2)], [0.0, 0.0])
    >>> centres.round(3).tolist(), distances.tolist()
    ([[3.0, 0.0], [-2.924, 1.211]], [1.0, 1.0])

    In a frame that ends at x = -1 it goes to the fourth ring instead, 45 degrees up:

    >>> centres, distances = place_boxes([(0, 0), (0, 0)], [(4, 2), (4, 2)], [0.0, 0.0],
    ...                                  frame=(-1, -10, 10, 10))
    >>> centres.round(3).tolist(), distances.tolist()
    ([[3.0, 0.0], [3.828, 3.828]], [1.0, 4.0])
    """
    if not gap > 0.0:
        raise InputError(f"gap must be > 0, got {gap!r}")
    anchors = np.asarray(anchors, dtype=float).reshape(-1, 2)
    sizes = np.asarray(sizes, dtype=float).reshape(-1, 2)
    boxes = [np.asarray(taken, dtype=float).reshape(-1, 4)]
    avoid = np.asarray(avoid, dtype=float).reshape(-1, 4)
    x0, y0, x1, y1 = (-math.inf, -math.inf, math.inf, math.inf) if frame is None else frame
    centres, distances = np.empty_like(anchors), np.empty(len(anchors))
    for n, ((ax, ay), (w, h), a) in enumerate(zip(anchors, sizes, np.broadcast_to(
            np.asarray(toward, dtype=float), len(anchors)))):
        c, s = np.cos(a + _TURNS), np.sin(a + _TURNS)
        with np.errstate(divide="ignore"):  # along an axis, one side sets the edge
            edge = np.minimum(0.5 * w / np.abs(c), 0.5 * h / np.abs(s))
        now = np.concatenate(boxes)
        best, best_cost, k = None, math.inf, 0
        while True:
            r = gap * (1 + k * (k + 1) // 2)
            if r >= best_cost or (best is not None and r > 1e6 * max(gap, w, h)):
                break  # no farther spot can cost less (or only infinite costs are left)
            cx, cy = ax + (r + edge) * c, ay + (r + edge) * s
            spots = np.c_[cx - 0.5 * w, cy - 0.5 * h, cx + 0.5 * w, cy + 0.5 * h]
            cost = r + cover * _overlapping(spots, avoid, gap) + np.where(
                (spots[:, 0] >= x0) & (spots[:, 1] >= y0) & (spots[:, 2] <= x1) &
                (spots[:, 3] <= y1), 0.0, leave)
            clear = np.flatnonzero(~_overlapping(spots, now, gap))
            if clear.size:
                j = clear[np.argmin(cost[clear])]
                if best is None or cost[j] < best_cost:
                    best, best_cost = (spots[j], r), cost[j]
            k += 1
        if best_cost >= leave and frame is not None:  # no ring had a clear spot inside
            best = _inside(np.array([ax, ay]), w, h, frame, now, gap) or best
        box, distances[n] = best
        centres[n] = 0.5 * (box[:2] + box[2:])
        boxes.append(box[None, :])
    return centres, distances


def _inside(anchor: np.ndarray, w: float, h: float, frame, taken: np.ndarray, gap: float):
    """``(box, distance)``: of the boxes ``w`` by ``h`` centred on a grid ``gap`` apart
    over ``frame``, the nearest to ``anchor`` that lies inside it clear of ``taken``
    (None if there is none): where the rings about the anchor had no such spot."""
    x0, y0, x1, y1 = frame
    if not (x1 - x0 > w and y1 - y0 > h):
        return None
    xs = np.arange(x0 + 0.5 * w, x1 - 0.5 * w, gap)
    ys = np.arange(y0 + 0.5 * h, y1 - 0.5 * h, gap)
    if xs.size * ys.size > 250_000:
        return None  # a frame that large has clear spots on the rings
    cx, cy = (c.ravel() for c in np.meshgrid(xs, ys))
    spots = np.c_[cx - 0.5 * w, cy - 0.5 * h, cx + 0.5 * w, cy + 0.5 * h]
    dx = np.maximum.reduce([spots[:, 0] - anchor[0], anchor[0] - spots[:, 2], 0 * cx])
    dy = np.maximum.reduce([spots[:, 1] - anchor[1], anchor[1] - spots[:, 3], 0 * cy])
    order = np.argsort(np.hypot(dx, dy), kind="stable")
    for part in np.array_split(order, max(1, order.size // 2000)):
        clear = part[~_overlapping(spots[part], taken, gap)]
        if clear.size:
            j = clear[0]
            return spots[j], float(np.hypot(dx[j], dy[j]))
    return None


def line_boxes(points: np.ndarray, half: float, step: float) -> np.ndarray:
    """Boxes ``x0, y0, x1, y1`` that together cover the polyline through ``points``
    (shape ``(n, 2)``) drawn ``2 * half`` wide, for :func:`place_boxes` to keep boxes
    off: squares of side ``2 * half + step`` centred every ``step`` or less along it
    (a point within ``half`` of the line lies within ``half + step / 2`` of one of the
    centres along each axis).

    Examples
    --------
    >>> line_boxes(np.array([[0.0, 0.0], [4.0, 0.0]]), 1.0, 2.0).tolist()
    [[-2.0, -2.0, 2.0, 2.0], [0.0, -2.0, 4.0, 2.0], [2.0, -2.0, 6.0, 2.0]]
    """
    points = np.asarray(points, dtype=float).reshape(-1, 2)
    out, spacing = [points[:1]], step
    for a, b in zip(points, points[1:]):
        length = float(np.hypot(*(b - a)))
        n = int(min(math.ceil(length / step), 10_000))  # at most 10,000 a segment...
        spacing = max(spacing, length / max(n, 1))  # ...farther apart, larger
        out.append(a + np.linspace(0.0, 1.0, n + 1)[1:, None] * (b - a))
    centres = np.concatenate(out)
    h = half + 0.5 * spacing
    return np.c_[centres - h, centres + h]

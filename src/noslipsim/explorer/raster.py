"""The portrait as an image the server paints: its cost in the page does not grow with the points.

A portrait fills with tens of thousands of points a second at high speed; a
scatter glyph makes the page redraw every point on each update, and the
frame rate falls as the portrait fills.  :class:`PortraitRaster` paints each
new point into a fixed RGBA image (one pixel block per point, the orbit's
colour, the latest point on top) and the page draws that one image.
"""
from __future__ import annotations

import numpy as np

__all__ = ["PortraitRaster"]


def _pack(hex_colors):
    """``#rrggbb`` strings as opaque RGBA uint32 (little-endian byte order, as Bokeh's ``image_rgba`` reads)."""
    rgb = np.array([[int(h[i:i + 2], 16) for i in (1, 3, 5)] for h in hex_colors], dtype=np.uint32)
    return rgb[:, 0] | (rgb[:, 1] << 8) | (rgb[:, 2] << 16) | (np.uint32(255) << 24)


class PortraitRaster:
    """A ``size x size`` RGBA image of the box ``(x0, x1, y0, y1)``, painted point by point.

    Parameters
    ----------
    box : (x0, x1, y0, y1)
        Data range covered (row 0 at ``y0``, as ``image_rgba`` draws it).
    colors : list of str
        ``#rrggbb`` per colour index.
    size : int
        Pixels per side.
    dot : int
        Side of the pixel block painted per point.
    """

    def __init__(self, box, colors, size=460, dot=3):
        self.box = tuple(float(v) for v in box)
        self.size = int(size)
        self.dot = int(dot)
        self.colors = _pack(colors)
        self.image = np.zeros((self.size, self.size), dtype=np.uint32)
        self.points = 0

    def clear(self, box=None):
        """Erase the image (and move it to ``box``)."""
        if box is not None:
            self.box = tuple(float(v) for v in box)
        self.image[:] = 0
        self.points = 0

    def pixels(self, x, y):
        """Column and row of each point; points outside the box are dropped (``None`` rows)."""
        x0, x1, y0, y1 = self.box
        col = np.floor((np.asarray(x, float) - x0) / (x1 - x0) * self.size).astype(np.int64)
        row = np.floor((np.asarray(y, float) - y0) / (y1 - y0) * self.size).astype(np.int64)
        keep = (col >= 0) & (col < self.size) & (row >= 0) & (row < self.size)
        return col[keep], row[keep], keep

    def paint(self, x, y, ci):
        """Paint points ``(x, y)`` in colours ``ci`` (indices into ``colors``); later points on top."""
        col, row, keep = self.pixels(x, y)
        color = self.colors[np.asarray(ci, dtype=np.int64)[keep] % len(self.colors)]
        for dr in range(self.dot):
            for dc in range(self.dot):
                r, c = np.minimum(row + dr, self.size - 1), np.minimum(col + dc, self.size - 1)
                self.image[r, c] = color
        self.points += int(keep.sum())

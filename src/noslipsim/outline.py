"""Drawing primitives: what an element looks like, as plain coordinates (no drawing library).

Each element kind says how it is drawn through
:meth:`noslipsim.elements.BoundaryElement.outline`, as a tuple of these
primitives; the plot layer (:mod:`noslipsim.plot.table`) turns them into
matplotlib artists, and :func:`noslipsim.plot.table_shapes` into polylines for
other libraries.  A new element kind draws itself with the three primitives
below and touches no drawing code.
"""
from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

TWO_PI = 2.0 * math.pi


class Wall(NamedTuple):
    """A wall drawn as a polyline: ``points`` is a sequence of ``(x, y)``."""

    points: list


class Disc(NamedTuple):
    """A filled disc: a scatterer, the table outside it."""

    center: tuple
    radius: float


class Curve(NamedTuple):
    """An unfilled circle (``theta1`` is ``None``: a container) or the CCW arc ``theta0 -> theta1`` of one."""

    center: tuple
    radius: float
    theta0: float = 0.0
    theta1: float | None = None

    def span(self) -> float:
        """The angle the curve covers, in ``(0, 2 pi]``."""
        if self.theta1 is None:
            return TWO_PI
        return (self.theta1 - self.theta0) % TWO_PI or TWO_PI

    def polyline(self, points_per_turn: int) -> tuple[list[float], list[float]]:
        """``(xs, ys)``: the curve sampled at ``points_per_turn`` points per full turn (at least 8)."""
        span = self.span()
        a = self.theta0 + np.linspace(0.0, span, max(8, int(points_per_turn * span / TWO_PI)))
        return ((self.center[0] + self.radius * np.cos(a)).tolist(),
                (self.center[1] + self.radius * np.sin(a)).tolist())

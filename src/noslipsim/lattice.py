"""Periodic scenes: which element copies reach a cell, and cell bookkeeping.

A periodic scene repeats its elements at every ``n1 a1 + n2 a2``.  Cell
``(n1, n2)`` is the parallelogram centred at ``n1 a1 + n2 a2`` spanned by
``a1, a2``; positions are reported unfolded together with the integer cell
indices ``cell_a1, cell_a2`` of the cell that holds them.
"""
from __future__ import annotations

import math

import numpy as np

#: Relative margin on bounding boxes when deciding which copies reach a cell.
REACH_MARGIN = 1e-9


def lattice_matrix(lattice):
    """``A`` (lattice vectors as columns) and its inverse ``B``."""
    A = np.array([lattice["a1"], lattice["a2"]], dtype=float).T
    return A, np.linalg.inv(A)


def reaching_copies(elements, lattice):
    """Int array ``(K, 3)`` of copies ``(element, o1, o2)`` whose bounding box meets cell 0.

    A copy translated by ``o1 a1 + o2 a2`` meets the centred cell when its box's
    lattice coordinates overlap ``[-1/2, 1/2]`` in both directions (conservative:
    a copy listed here may still miss the cell; none that meets it is left out).
    """
    A, B = lattice_matrix(lattice)
    rows = []
    for i, e in enumerate(elements):
        x0, y0, x1, y1 = e.bbox()
        if not all(map(math.isfinite, (x0, y0, x1, y1))):
            raise ValueError(f"elements[{i}]: infinite lines cannot be repeated on a lattice")
        corners = np.array([[x0, y0], [x1, y0], [x0, y1], [x1, y1]]) @ B.T
        lo = corners.min(axis=0) - REACH_MARGIN
        hi = corners.max(axis=0) + REACH_MARGIN
        for o1 in range(math.ceil(-0.5 - hi[0]), math.floor(0.5 - lo[0]) + 1):
            for o2 in range(math.ceil(-0.5 - hi[1]), math.floor(0.5 - lo[1]) + 1):
                rows.append((i, o1, o2))
    return np.array(rows, dtype=np.int64).reshape(-1, 3)


def cell_of(points, lattice):
    """Integer cell indices ``(n1, n2)`` of points (nearest lattice site).

    Elementwise arithmetic (not a matrix product, whose rounding depends on the
    batch shape), so a point gets the same cell alone or in an ensemble.
    """
    _, B = lattice_matrix(lattice)
    p = np.asarray(points, float)
    x, y = p[..., 0], p[..., 1]
    return np.stack([np.rint(B[0, 0] * x + B[0, 1] * y), np.rint(B[1, 0] * x + B[1, 1] * y)],
                    axis=-1).astype(np.int64)


def cell_origin(cells, lattice):
    """Centres ``n1 a1 + n2 a2`` of cells (elementwise, like :func:`cell_of`)."""
    A, _ = lattice_matrix(lattice)
    c = np.asarray(cells, float)
    n1, n2 = c[..., 0], c[..., 1]
    return np.stack([n1 * A[0, 0] + n2 * A[0, 1], n1 * A[1, 0] + n2 * A[1, 1]], axis=-1)


def unit_cell_polygon(lattice):
    """Vertices of cell 0 (CCW), for drawing."""
    A, _ = lattice_matrix(lattice)
    corners = np.array([[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5], [-0.5, 0.5]]) @ A.T
    area = A[0, 0] * A[1, 1] - A[1, 0] * A[0, 1]
    return corners if area > 0 else corners[::-1]

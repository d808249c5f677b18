"""Periodic scenes: which element copies reach a cell, and cell bookkeeping.

A periodic scene repeats its elements at every ``n1 a1 + n2 a2``.  Cell
``(n1, n2)`` is the parallelogram centred at ``n1 a1 + n2 a2`` spanned by
``a1, a2``; positions are reported unfolded together with the integer cell
indices ``cell_a1, cell_a2`` of the cell that holds them.
"""
from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

#: Relative margin on bounding boxes when deciding which copies reach a cell.
REACH_MARGIN = 1e-9


def lattice_matrix(lattice):
    """``A`` (lattice vectors as columns) and its inverse ``B`` (read-only; built once per basis)."""
    return _matrices(tuple(map(float, lattice["a1"])), tuple(map(float, lattice["a2"])))


@lru_cache(maxsize=256)
def _matrices(a1, a2):
    A = np.array([a1, a2], dtype=float).T
    with np.errstate(all="ignore"):
        B = np.linalg.inv(A)
    A.flags.writeable = False
    B.flags.writeable = False
    return A, B


def reaching_copies(elements, lattice):
    """Int array ``(K, 3)`` of copies ``(element, o1, o2)`` that reach cell 0.

    A copy translated by ``o1 a1 + o2 a2`` reaches the centred cell when the
    element itself (not only its box) comes within ``REACH_MARGIN`` (in lattice
    coordinates) of the cell: a segment that crosses the cell, a circle whose
    curve passes through it (a disk whose box only grazes a corner of the cell
    is left out, and so is a circle enclosing the whole cell).  Arcs are tested
    as their full circle and their box.  The test is conservative by the
    margin: a copy listed here may miss the cell by that much; none that meets
    it is left out.  Candidates come from the box's lattice coordinates.
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
                if _reaches(e, A, B, o1, o2):
                    rows.append((i, o1, o2))
    return np.array(rows, dtype=np.int64).reshape(-1, 3)


def _reaches(e, A, B, o1, o2):
    """Whether the copy of ``e`` shifted by ``o1 a1 + o2 a2`` comes within ``REACH_MARGIN`` of cell 0."""
    from ..elements import StraightCarrier

    h = 0.5 + REACH_MARGIN
    shift = A @ np.array([o1, o2], float)
    if isinstance(e.carrier(), StraightCarrier):  # a segment: clip it to the inflated cell in lattice coordinates
        (p0, _, _), (p1, _, _) = e.end_frames()
        p = B @ (p0 + shift)
        d = B @ (p1 + shift) - p
        lo, hi = 0.0, 1.0
        for k in range(2):
            if d[k] == 0.0:
                if abs(p[k]) > h:
                    return False
                continue
            with np.errstate(over="ignore"):  # a tiny d[k]: the bounds are +-inf, which is right
                s0, s1 = sorted(((-h - p[k]) / d[k], (h - p[k]) / d[k]))
            lo, hi = max(lo, s0), min(hi, s1)
        return lo <= hi
    # circles and arcs: the curve passes through the cell iff the cell's nearest point lies
    # within r of the centre and its farthest vertex beyond r
    c, r = e.carrier()
    c = c + shift
    verts = np.array([[-h, -h], [h, -h], [h, h], [-h, h]]) @ A.T
    far = float(np.hypot(*(verts - c).T).max())
    inside = bool(np.all(np.abs(B @ c) <= h))
    near = 0.0 if inside else min(_point_segment(c, verts[k], verts[(k + 1) % 4]) for k in range(4))
    tol = REACH_MARGIN * r
    return near <= r + tol and far >= r - tol


def _point_segment(c, a, b):
    ab = b - a
    s = min(max(float((c - a) @ ab) / float(ab @ ab), 0.0), 1.0)
    return float(np.hypot(*(c - a - s * ab)))


def disks_apart(disks, lattice, gap):
    """Whether every two disks of the periodic scene, lattice copies included, are more than ``gap`` apart.

    ``disks``: ``(center, radius)`` pairs.  Disk ``i`` and the copy of disk
    ``j`` translated by ``n1 a1 + n2 a2`` (``n != 0`` when ``i == j``) are
    apart when their centres are more than ``r_i + r_j + gap`` apart.  Each
    centre is first moved by a lattice vector into cell 0 (a symmetry of the
    periodic scene), so the translations that could bring two disks closer lie
    within ``1 + |B| (r_i + r_j + gap)`` in lattice coordinates, and all of
    them are checked, for all pairs at once.
    """
    A, B = lattice_matrix(lattice)
    centres = np.array([c for c, _ in disks], float).reshape(-1, 2)
    radii = np.array([r for _, r in disks], float)
    centres = centres - np.rint(centres @ B.T) @ A.T
    reach = radii[:, None] + radii[None, :] + gap
    span = math.ceil(1.0 + float(np.linalg.norm(B, 2)) * float(reach.max()))
    diff = centres[:, None, :] - centres[None, :, :]
    for n1 in range(-span, span + 1):
        for n2 in range(-span, span + 1):
            d = diff - A @ np.array([n1, n2], float)
            close = np.hypot(d[..., 0], d[..., 1]) <= reach
            if n1 == 0 and n2 == 0:
                np.fill_diagonal(close, False)
            if close.any():
                return False
    return True


#: The largest cell index (per basis vector) a lattice position may have: cell indices and the
#: origins ``n1 a1 + n2 a2`` are exact up to here, and an int64 holds them.
MAX_CELL_INDEX = 2.0 ** 52


def cell_of(points, lattice, field="position"):
    """Integer cell indices ``(n1, n2)`` of points (nearest lattice site).

    Elementwise arithmetic (not a matrix product, whose rounding depends on the
    batch shape), so a point gets the same cell alone or in an ensemble.
    A point more than :data:`MAX_CELL_INDEX` cells from the origin (or not
    finite) raises ``ValueError`` naming ``field``.
    """
    _, B = lattice_matrix(lattice)
    p = np.asarray(points, float)
    x, y = p[..., 0], p[..., 1]
    cells = np.stack([np.rint(B[0, 0] * x + B[0, 1] * y), np.rint(B[1, 0] * x + B[1, 1] * y)], axis=-1)
    if not np.all(np.abs(cells) <= MAX_CELL_INDEX):  # NaN fails too
        worst = p.reshape(-1, 2)[np.argmax(np.nan_to_num(np.abs(cells), nan=np.inf).reshape(-1, 2).max(axis=1))]
        raise ValueError(f"{field}: {tuple(float(c) for c in worst)} lies more than 2**52 cells from the "
                         "origin; a lattice position must be finite and within 2**52 cells, where cell "
                         "indices and cell origins are exact")
    return cells.astype(np.int64)


def element_cells(element, points, lattice):
    """Integer indices ``(n1, n2)`` of the copy of ``element`` each point lies on (``points`` ``(N, 2)``).

    The copy translated by ``n1 a1 + n2 a2`` that is nearest to the point:
    what a point on an element needs (a boundary start, a twin orbit put back
    in the base cell), where :func:`cell_of`, the parallelogram cell that
    holds the point, is another cell as soon as the element reaches out of
    its own (a disk of radius above ``sqrt(3)/4`` on the unit triangular
    lattice).  Candidates are the translations that bring the point into the
    element's bounding box (the copies that can hold it, as in
    :func:`reaching_copies`); each point takes the one at the least distance
    (a full circle: distance to the circle).
    """
    A, B = lattice_matrix(lattice)
    p = np.asarray(points, float).reshape(-1, 2)
    x0, y0, x1, y1 = element.bbox()
    box = np.array([[x0, y0], [x1, y0], [x0, y1], [x1, y1]]) @ B.T
    lo, hi = box.min(axis=0) - REACH_MARGIN, box.max(axis=0) + REACH_MARGIN
    frac = p @ B.T
    first = np.ceil(frac - hi[None, :]).astype(np.int64)      # n with frac - n within [lo, hi]
    span = np.floor(hi - lo).astype(np.int64) + 2
    k1, k2 = np.meshgrid(np.arange(span[0]), np.arange(span[1]), indexing="ij")
    offsets = np.stack([k1.ravel(), k2.ravel()], axis=-1)
    cand = first[:, None, :] + offsets[None, :, :]            # (N, K, 2)
    rel = p[:, None, :] - cand.astype(float) @ A.T
    dist = element.distance(rel)
    return cand[np.arange(len(p)), np.argmin(dist, axis=1)]


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


def reduced_matrix(lattice):
    """Lattice vectors of the Lagrange–Gauss reduced basis as columns, ``b1 . b2 >= 0`` (the cell's acute corner)."""
    from .canonical import reduce_basis

    A, _ = lattice_matrix(lattice)
    return A @ reduce_basis(A).astype(float)


def covering_radius(lattice) -> float:
    """The lattice's covering radius: the largest distance from a point of the plane to its nearest lattice site.

    In a reduced basis ``b1, b2`` with ``b1 . b2 >= 0`` the triangle ``0, b1,
    b2`` has no obtuse angle, so it and its point reflection tile the plane as
    the lattice's Delaunay triangles; the farthest points from every site are
    their circumcentres, at the circumradius ``|b1| |b2| |b1 - b2| / (2 |b1 x b2|)``
    (``d / sqrt(3)`` on the triangular lattice of spacing ``d``, ``d / sqrt(2)``
    on the square one).
    """
    R = reduced_matrix(lattice)
    b1, b2 = R[:, 0], R[:, 1]
    cross = abs(float(b1[0] * b2[1] - b1[1] * b2[0]))
    return float(np.hypot(*b1) * np.hypot(*b2) * np.hypot(*(b1 - b2)) / (2.0 * cross))


#: :func:`disks_cover_plane` gives up (answers "not shown covered") past this many subdivision
#: levels, or this many pieces of the cell at one level: the disks then leave at most slivers
#: too thin for the engine, or nothing, and a start drawn there says so.
COVER_MAX_LEVELS = 24
COVER_MAX_PIECES = 50_000


def disks_cover_plane(disks, lattice) -> bool:
    """Whether the disks ``(center, radius)`` and their lattice copies certainly cover the whole plane.

    One disk: exactly, ``r >= covering_radius``.  Several: the reduced cell
    is cut into ``2^k x 2^k`` small parallelograms, each of centre ``c`` and
    half-diagonal ``h``; a piece lies inside one disk copy when ``|c - C| + h
    <= r``, and a centre outside every copy is a point of the table (the
    answer is ``False``); the other pieces are cut in four, up to
    :data:`COVER_MAX_LEVELS` levels.  ``True`` only when every piece of the
    cell was shown inside a disk, so a table with points is never refused;
    an undecided case (the disks leave at most slivers) answers ``False``.
    """
    radii = np.array([r for _, r in disks], float)
    if len(radii) == 1:
        return bool(radii[0] >= covering_radius(lattice))
    R = reduced_matrix(lattice)
    Rinv = np.linalg.inv(R)
    centres = np.array([c for c, _ in disks], float).reshape(-1, 2)
    centres = centres - np.rint(centres @ Rinv.T) @ R.T  # a lattice vector is a symmetry: into the reduced cell
    span = math.ceil(1.0 + float(np.linalg.norm(Rinv, 2)) * float(radii.max()))
    n = np.arange(-span, span + 1, dtype=float)
    shifts = (np.stack(np.meshgrid(n, n, indexing="ij"), axis=-1).reshape(-1, 2)) @ R.T
    C = (centres[:, None, :] + shifts[None, :, :]).reshape(-1, 2)
    r = np.repeat(radii, len(shifts))
    diag = 0.5 * max(float(np.hypot(*(R[:, 0] + R[:, 1]))), float(np.hypot(*(R[:, 0] - R[:, 1]))))
    pieces = np.array([[0.0, 0.0]])  # centres of the pieces in lattice coordinates (the cell is [-1/2, 1/2]^2)
    size = 1.0
    for _ in range(COVER_MAX_LEVELS):
        if len(pieces) > COVER_MAX_PIECES:
            return False
        pts = pieces @ R.T
        dist = np.hypot(pts[:, None, 0] - C[None, :, 0], pts[:, None, 1] - C[None, :, 1])
        if not (dist <= r).any(axis=1).all():
            return False  # a point in no disk: the table is not empty
        inside = (dist + diag * size <= r).any(axis=1)
        pieces = pieces[~inside]
        if len(pieces) == 0:
            return True
        size *= 0.5
        q = 0.5 * size
        pieces = (pieces[:, None, :] + np.array([[-q, -q], [q, -q], [-q, q], [q, q]])[None]).reshape(-1, 2)
    return False

"""Named constructors for the paper's tables.

Every function returns a :class:`~noslipsim.scenes.Scene`; ``law``, ``gamma``
and ``force`` are passed through (defaults: no-slip, uniform disk
``gamma = 1/sqrt(2)``, no force).  Polygons are counter-clockwise with the
table on the left of every edge.  ``Scene.to_yaml()`` writes any of them as a
scene file.
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np

from ._validate import positive
from .elements import MIN_GAP, Arc, Circle, Line, Segment, polygon_defect
from .scenes import Scene

UNIFORM_DISK = 1.0 / math.sqrt(2.0)


def _scene(elements, law, gamma, force):
    return Scene(tuple(elements), law=law, gamma=gamma, force=force)


def half_plane(*, law="no-slip", gamma=UNIFORM_DISK, gravity=1.0):
    """The upper half plane ``y > 0`` with force ``(0, -gravity)`` (the bouncing ball)."""
    return _scene([Line((0.0, 0.0), (0.0, 1.0))], law, gamma, (0.0, -gravity))


def wedge(phi, *, opening="up", law="no-slip", gamma=UNIFORM_DISK, force=(0.0, -1.0)):
    """Wedge of half-angle ``phi`` (wall to bisector), vertex at the origin, bisector vertical.

    Elements: ``0`` the left wall, ``1`` the right wall (infinite lines whose
    half planes intersect in the wedge).  ``opening='down'`` puts the vertex on top.
    """
    if not 0.0 < phi < math.pi / 2:
        raise ValueError(f"phi: wedge half-angle must lie in (0, pi/2), got {phi}")
    if opening not in ("up", "down"):
        raise ValueError(f"opening: must be 'up' or 'down', got {opening!r}")
    sy = 1.0 if opening == "up" else -1.0
    c, s = math.cos(phi), math.sin(phi)
    return _scene([Line((0.0, 0.0), (c, sy * s)), Line((0.0, 0.0), (-c, sy * s))], law, gamma, force)


def channel(width=1.0, *, law="no-slip", gamma=UNIFORM_DISK, force=(0.0, 0.0)):
    """Horizontal channel ``0 < y < width``: element 0 the floor, 1 the ceiling."""
    if not width > 0:
        raise ValueError(f"width: must be > 0, got {width}")
    return _scene([Line((0.0, 0.0), (0.0, 1.0)), Line((0.0, width), (0.0, -1.0))], law, gamma, force)


def _check_simple(v):
    """Refuse a polygon whose edges cross or touch away from their shared vertices, or fold back on themselves."""
    defect = polygon_defect(v, MIN_GAP * float(np.abs(v).max()))
    if defect is None:
        return
    kind, i, j = defect
    n = len(v)
    if kind == "fold":
        raise ValueError(f"vertices: the polygon folds back on itself at vertex {j} {v[j].tolist()}")
    if kind == "near":
        raise ValueError(f"vertices: edges {i} and {j} come within {MIN_GAP:g} times the polygon's size of each "
                         "other (inside the engine's tolerances, which orbits cross)")
    raise ValueError(f"vertices: the polygon is not simple: edge {i} ({v[i].tolist()} -> {v[(i + 1) % n].tolist()}) "
                     f"meets edge {j} ({v[j].tolist()} -> {v[(j + 1) % n].tolist()})")


def polygon(vertices, *, law="no-slip", gamma=UNIFORM_DISK, force=(0.0, 0.0), disks=()):
    """Polygon table from its vertices (either orientation; stored counter-clockwise).

    ``disks`` adds circular scatterers ``(cx, cy, r)`` inside it.  Element
    ``i`` is the edge from vertex ``i`` to vertex ``i+1`` (after orientation).
    """
    try:
        v = np.asarray(vertices, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"vertices: expected at least 3 points (x, y), got {vertices!r}") from None
    if v.ndim != 2 or v.shape[1] != 2 or len(v) < 3:
        raise ValueError("vertices: expected at least 3 points (x, y)")
    if not np.all(np.isfinite(v)):
        raise ValueError("vertices: must be finite")
    _check_simple(v)
    area = 0.5 * np.sum(v[:, 0] * np.roll(v[:, 1], -1) - np.roll(v[:, 0], -1) * v[:, 1])
    if area == 0 or not np.isfinite(area):
        raise ValueError("vertices: the polygon has zero or undefined area")
    if area < 0:
        v = v[::-1]
    edges = [Segment(tuple(v[i]), tuple(v[(i + 1) % len(v)]), "left") for i in range(len(v))]
    circles = [Circle((cx, cy), r, "outside") for cx, cy, r in disks]
    return _scene(edges + circles, law, gamma, force)


def regular_polygon(n, *, circumradius=1.0, law="no-slip", gamma=UNIFORM_DISK, force=(0.0, 0.0)):
    """Regular ``n``-gon centred at the origin with a horizontal bottom edge."""
    if int(n) != n or n < 3:
        raise ValueError(f"n: a polygon needs an integer number of sides >= 3, got {n}")
    ang = -math.pi / 2 - math.pi / n + 2 * math.pi * np.arange(n) / n
    return polygon(np.c_[circumradius * np.cos(ang), circumradius * np.sin(ang)],
                   law=law, gamma=gamma, force=force)


def rectangle(width=2.0, height=1.0, *, disks=(), law="no-slip", gamma=UNIFORM_DISK, force=(0.0, 0.0)):
    """Rectangle ``[0, width] x [0, height]`` (edges bottom, right, top, left) with disk scatterers ``(cx, cy, r)``."""
    width, height = positive(width, "width"), positive(height, "height")
    return polygon([(0, 0), (width, 0), (width, height), (0, height)], disks=disks,
                   law=law, gamma=gamma, force=force)


def two_disks(radius, *, distance=2.0, box=None, law="no-slip", gamma=UNIFORM_DISK, force=(0.0, 0.0)):
    """Two disk scatterers of ``radius`` centred at ``(-distance/2, 0)`` and ``(distance/2, 0)``.

    Without ``box`` the table is open (an orbit that misses both disks escapes);
    ``box=(width, height)`` encloses them in a centred rectangle (elements: 4
    edges, then the two disks).
    """
    if not 0 < 2 * radius < distance:
        raise ValueError(f"radius: disks must not touch (0 < 2 radius < distance), got {radius}")
    disks = [(-distance / 2, 0.0, radius), (distance / 2, 0.0, radius)]
    if box is None:
        return _scene([Circle((cx, cy), r) for cx, cy, r in disks], law, gamma, force)
    w, h = box
    return polygon([(-w / 2, -h / 2), (w / 2, -h / 2), (w / 2, h / 2), (-w / 2, h / 2)], disks=disks,
                   law=law, gamma=gamma, force=force)


def lemon(radius=1.0, distance=1.0, *, law="specular", gamma=0.0, force=(0.0, 0.0)):
    """Lemon: the intersection of two disks of ``radius`` whose centres are ``distance`` apart.

    Element 0 is the right-hand arc (of the disk centred at ``(-distance/2, 0)``),
    element 1 the left-hand arc.
    """
    if not 0 < distance < 2 * radius:
        raise ValueError(f"distance: must lie in (0, 2 radius) for a lemon, got {distance}")
    alpha = math.acos(distance / (2 * radius))
    a = Arc((-distance / 2, 0.0), radius, -alpha, alpha, "inside")
    b = Arc((distance / 2, 0.0), radius, math.pi - alpha, math.pi + alpha, "inside")
    return _scene([a, b], law, gamma, force)


def stadium(length=1.0, radius=1.0, *, law="no-slip", gamma=UNIFORM_DISK, force=(0.0, 0.0)):
    """Bunimovich stadium: a ``length`` x ``2 radius`` rectangle capped by half disks.

    Elements: bottom segment, right cap, top segment, left cap (CCW).
    """
    if not (length > 0 and radius > 0):
        raise ValueError("length, radius: must be > 0")
    a = length / 2
    return _scene([
        Segment((-a, -radius), (a, -radius)),
        Arc((a, 0.0), radius, -math.pi / 2, math.pi / 2, "inside"),
        Segment((a, radius), (-a, radius)),
        Arc((-a, 0.0), radius, math.pi / 2, 3 * math.pi / 2, "inside"),
    ], law, gamma, force)


def sinai_torus(radius=0.25, *, law="no-slip", gamma=UNIFORM_DISK, force=(0.0, 0.0)):
    """Sinai billiard on the unit square torus: a disk of ``radius`` at the origin, lattice ``Z^2``.

    Positions are unfolded (the Lorentz gas on a square lattice); cell indices
    say which copy of the torus holds the particle.
    """
    if not 0 < radius < 0.5:
        raise ValueError(f"radius: must lie in (0, 1/2) on the unit torus, got {radius}")
    return Scene((Circle((0.0, 0.0), radius, "outside"),), law=law, gamma=gamma, force=force,
                 lattice={"a1": [1.0, 0.0], "a2": [0.0, 1.0]})


def hex_lorentz_cell(radius=0.3, *, law="no-slip", gamma=UNIFORM_DISK, force=(0.0, 0.0)):
    """Disk of ``radius`` in the hexagonal Wigner–Seitz cell of the unit triangular lattice.

    Lattice ``a1 = (1, 0)``, ``a2 = (1/2, sqrt(3)/2)``: the periodic Lorentz gas
    (disks must not overlap: ``radius < 1/2``).
    """
    if not 0 < radius < 0.5:
        raise ValueError(f"radius: must lie in (0, 1/2) on the unit triangular lattice, got {radius}")
    return Scene((Circle((0.0, 0.0), radius, "outside"),), law=law, gamma=gamma, force=force,
                 lattice={"a1": [1.0, 0.0], "a2": [0.5, math.sqrt(3.0) / 2.0]})


def closed_hex_cell(radius=0.4, *, law="no-slip", gamma=UNIFORM_DISK, force=(0.0, 0.0), wall_law=None):
    """The hexagonal Wigner-Seitz cell of :func:`noslipsim.tables.hex_lorentz_cell`, closed by walls.

    Six segments (counter-clockwise, elements 0-5; vertices at ``(cos a, sin a)
    / sqrt(3)``, ``a = pi/6 + k pi/3``: vertical sides at ``x = +-1/2``, a vertex
    at the top and one at the bottom) and the disk of ``radius`` at the origin
    (element 6).  Unlike the periodic cell, a particle cannot leave it, so its
    energy ``(|v|^2 + w^2)/2 - a.q`` bounds the kinetic energy under a force.
    ``wall_law`` gives the six walls their own collision law (``None``: the
    scene's ``law``): ``law='no-slip', wall_law='specular'`` is a no-slip disk
    in a cell of specular walls (a mixed table, docs/scenes.md).
    """
    if not 0 < radius < 0.5:
        raise ValueError(f"radius: must lie in (0, 1/2) (the cell's inradius), got {radius}")
    a = math.pi / 6 + math.pi / 3 * np.arange(6)
    scene = polygon(np.c_[np.cos(a), np.sin(a)] / math.sqrt(3.0), disks=[(0.0, 0.0, radius)], law=law,
                    gamma=gamma, force=force)
    if wall_law is None:
        return scene
    walls = tuple(dataclasses.replace(e, law=wall_law) if e.disk() is None else e for e in scene.elements)
    return scene.replace(elements=walls)


def galton_board(spacing=2.0, radius=0.5, gravity=1.0, *, law="no-slip", gamma=UNIFORM_DISK, top_row=None):
    """Galton board: pegs of ``radius`` on a triangular lattice of ``spacing``, force ``(0, -gravity)``.

    Lattice ``a1 = (spacing, 0)``, ``a2 = (spacing/2, spacing sqrt(3)/2)``; a peg
    at the origin of every cell.  ``top_row=None`` (the default) continues the
    lattice upwards without end; an integer ``k`` bounds it: row ``k`` (pegs at
    height ``k spacing sqrt(3)/2``) is the top row, with nothing above it
    (``Scene.top`` half a row above it), as a Galton board is built.  The paper gives no geometry for its board:
    the defaults here are only a convenient example.  How much the results
    depend on the choice (the no-slip trapped share moves steeply with the
    radius) and the geometry of the paper's figures are in the README and
    ``config/config.yaml``.
    """
    if not 0 < 2 * radius < spacing:
        raise ValueError(f"radius: pegs must not touch (0 < 2 radius < spacing), got {radius}")
    if not gravity > 0:
        raise ValueError(f"gravity: must be > 0, got {gravity}")
    if top_row is not None and (isinstance(top_row, bool) or not isinstance(top_row, (int, np.integer))):
        raise TypeError(f"top_row: expected an integer row index or None, got {top_row!r}")
    row = spacing * math.sqrt(3.0) / 2.0
    return Scene((Circle((0.0, 0.0), radius, "outside"),), law=law, gamma=gamma, force=(0.0, -gravity),
                 lattice={"a1": [spacing, 0.0], "a2": [spacing / 2, row]},
                 top=None if top_row is None else (int(top_row) + 0.5) * row)


def walled_galton_board(spacing=2.0, radius=0.5, gravity=1.0, *, rows, width, top_row=0, law="no-slip",
                        gamma=UNIFORM_DISK, wall_law=None):
    """A finite Galton board: the pegs of :func:`galton_board` between two side walls at ``x = +-width``.

    The pegs of rows ``top_row`` down to ``top_row - rows`` (the row at the
    terminal depth of :func:`noslipsim.experiments.galton_distribution`
    included) whose whole disk lies between the walls, ``|x| + radius <
    width``; nothing above the top row, as on the bounded lattice.  The walls
    are two vertical lines (the last two elements), with the scene's ``law``
    unless ``wall_law`` gives them their own.  A plain scene: the cost of a
    collision grows with the number of pegs (about ``2 (rows + 1) width /
    spacing``).

    Parameters
    ----------
    spacing, radius, gravity, law, gamma
        As in :func:`galton_board`.
    rows : int
        Rows below the top row (``rows + 1`` rows of pegs), >= 1.
    width : float
        Half-width of the board (walls at ``x = -width`` and ``x = width``),
        larger than ``radius``.
    top_row : int
        The top row's index (its pegs at height ``top_row spacing sqrt(3)/2``).
    wall_law : {None, 'no-slip', 'specular'}
        The walls' own collision law (``None``: the scene's ``law``).
    """
    if not 0 < 2 * radius < spacing:
        raise ValueError(f"radius: pegs must not touch (0 < 2 radius < spacing), got {radius}")
    if not gravity > 0:
        raise ValueError(f"gravity: must be > 0, got {gravity}")
    if isinstance(rows, bool) or not isinstance(rows, (int, np.integer)) or rows < 1:
        raise ValueError(f"rows: expected an integer >= 1, got {rows!r}")
    if isinstance(top_row, bool) or not isinstance(top_row, (int, np.integer)):
        raise TypeError(f"top_row: expected an integer row index, got {top_row!r}")
    width = positive(width, "width")
    if not width > radius:
        raise ValueError(f"width: the walls must leave room for a peg (width > radius = {radius}), got {width}")
    row = spacing * math.sqrt(3.0) / 2.0
    reach = math.ceil(width / spacing) + 1
    pegs = []
    for j in range(int(top_row), int(top_row) - int(rows) - 1, -1):
        # the triangular lattice: each row down is shifted by half a spacing (a2 = (spacing/2, row))
        for x in spacing * np.arange(-reach, reach + 1) + (spacing / 2) * (j % 2):
            if abs(x) + radius < width:
                pegs.append(Circle((float(x), j * row), radius, "outside"))
    walls = (Line((-width, 0.0), (1.0, 0.0), law=wall_law), Line((width, 0.0), (-1.0, 0.0), law=wall_law))
    return Scene((*pegs, *walls), law=law, gamma=gamma, force=(0.0, -gravity))

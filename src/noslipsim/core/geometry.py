"""Per-kind geometry of boundary elements (the protocol every kind implements).

For each kind: the crossing polynomial along a flight (positive on the table
side), the signed distance, the extent test (ends inclusive within a
tolerance), the projection onto the element with the outward unit normal, and
the arclength coordinate.  Adding an element kind touches this module and the event code that
branches on the kind (docs/extending.md, "An element kind", lists every file).

Frame convention (docs/conventions.md, "The collision frame"): ``n`` is the *outward* unit normal (out of
the table, into the wall) and the tangent is ``t = J n = (-n_y, n_x)``.
"""
import math

import numpy as np

from .exact import cross_dd, shifted_dot, two_sum
from .jit import jit
from .layout import (
    ARC,
    CIRCLE,
    END_END,
    END_START,
    LINE,
    SEG_CROSS_SCALE,
    SEG_P1X,
    SEG_P1Y,
    SEGMENT,
)

TWO_PI = 2.0 * math.pi

#: A line's value ``(q - p) . n`` is taken as formed when its two terms sum to at most this many
#: times its size (relative error then at most about ``3 LINE_GATE eps`` = 1.7e-13); otherwise it
#: cancelled and is formed again exactly.  Large enough that ordinary tables almost never take the
#: exact path (measured: benchmarks/results/ablation.md).  docs/algorithm.md, *1. Next hit*.
LINE_GATE = 256.0


@jit
def line_value(kind, p, x, y):
    """Signed distance ``(q - p) . n_in`` of ``q = (x, y)`` from a line or segment (``p`` its row).

    The plain form carries ``eps |q - p|`` (off by 1e-10 at 10^6 along a wall); where it cancels
    (:data:`LINE_GATE`), :func:`line_value_exact`.  The hit search over all elements uses the plain
    form only; :func:`events.exact_line_hit` redoes the hit on the element hit.
    """
    a = (x - p[0]) * p[2]
    b = (y - p[1]) * p[3]
    d = a + b
    if abs(a) + abs(b) <= LINE_GATE * abs(d):
        return d
    return line_value_exact(kind, p, x, y)


@jit
def line_value_exact(kind, p, x, y):
    """:func:`line_value` to a few ulps of itself, always (a call, so the common path stays small).

    A segment: ``-side ((q - p0) x (p1 - p0)) / L`` (``side`` +1 for a table on the left), both
    differences and the cross product exact to ``eps^2`` (:mod:`exact`), from the segment's own float
    end points.  A line: its stored float unit normal, by :func:`exact.shifted_dot`.
    """
    if kind == SEGMENT:
        fx, fxl = two_sum(x, -p[0])
        fy, fyl = two_sum(y, -p[1])
        ex, exl = two_sum(p[SEG_P1X], -p[0])
        ey, eyl = two_sum(p[SEG_P1Y], -p[1])
        return (cross_dd(fx, fxl, fy, fyl, ex, ey) + (fx * eyl - fy * exl)) * p[SEG_CROSS_SCALE]
    return shifted_dot(x, y, p[0], p[1], p[2], p[3])


@jit
def lattice_shift(A, n1, n2):
    """The translation ``n1 a1 + n2 a2`` (lattice vectors are the columns of ``A``; zero for plain scenes)."""
    return n1 * A[0, 0] + n2 * A[0, 1], n1 * A[1, 0] + n2 * A[1, 1]


@jit(inline="always")
def lattice_coordinates(B, x, y):
    """``(alpha, beta) = B (x, y)``: a point (or velocity) in units of the lattice vectors (``B = A^-1``)."""
    return B[0, 0] * x + B[0, 1] * y, B[1, 0] * x + B[1, 1] * y


@jit(inline="always")
def nearest_cell(B, x, y):
    """Integer indices ``(n1, n2)`` of the cell holding ``(x, y)`` (centred cells: the nearest lattice site)."""
    alpha, beta = lattice_coordinates(B, x, y)
    return int(np.rint(alpha)), int(np.rint(beta))


@jit(inline="always")
def copy_shift(A, o1, o2, shifted):
    """:func:`lattice_shift` of an element copy, or exact zeros without work when nothing is ``shifted``.

    A plain scene's copies have zero offsets (``A = 0``): skipping the zeros gives the same values and
    spares each element of each collision two conversions and four products.
    """
    if shifted:
        return lattice_shift(A, o1, o2)
    return 0.0, 0.0


@jit
def crossing_slope(kind, p, x, y, vx, vy):
    """``c1`` of :func:`crossing_coefficients`, the rate at which the flight crosses at ``t = 0`` (no force needed)."""
    if kind == LINE or kind == SEGMENT:
        return vx * p[2] + vy * p[3]
    return p[3] * 2.0 * ((x - p[0]) * vx + (y - p[1]) * vy)


@jit
def crossing_coefficients(kind, p, x, y, vx, vy, ax, ay):
    """Coefficients ``(c0, ..., c4)`` of the crossing polynomial of element ``p`` along a flight.

    Lines and segments: signed distance ``(q(t) - p) . n_in`` (degree <= 2).
    Circles and arcs: ``sigma (|q(t) - c|^2 - r^2)`` (degree <= 4; <= 2 without force).
    """
    if kind == LINE or kind == SEGMENT:
        nx = p[2]
        ny = p[3]
        c0 = (x - p[0]) * nx + (y - p[1]) * ny
        return c0, crossing_slope(kind, p, x, y, vx, vy), 0.5 * (ax * nx + ay * ny), 0.0, 0.0
    sig = p[3]
    dx = x - p[0]
    dy = y - p[1]
    r = p[2]
    c0 = sig * ((dx * dx + dy * dy) - r * r)
    c1 = crossing_slope(kind, p, x, y, vx, vy)
    c2 = sig * ((vx * vx + vy * vy) + (dx * ax + dy * ay))
    c3 = sig * (vx * ax + vy * ay)
    c4 = sig * 0.25 * (ax * ax + ay * ay)
    return c0, c1, c2, c3, c4


@jit
def signed_distance(kind, p, x, y):
    """Distance to the element's supporting line or circle, positive on the table side."""
    if kind == LINE or kind == SEGMENT:
        return (x - p[0]) * p[2] + (y - p[1]) * p[3]
    return p[3] * (math.hypot(x - p[0], y - p[1]) - p[2])


@jit
def distance_rate(kind, p, x, y, vx, vy):
    """Time derivative of :func:`signed_distance` for a particle at ``(x, y)`` with velocity ``v``."""
    if kind == LINE or kind == SEGMENT:
        return vx * p[2] + vy * p[3]
    dx = x - p[0]
    dy = y - p[1]
    return p[3] * (dx * vx + dy * vy) / math.hypot(dx, dy)


@jit
def extent_coordinate(kind, p, x, y):
    """Position along a segment (from p0) or CCW angle past theta0 on an arc; 0 for lines and circles."""
    if kind == SEGMENT:
        return (x - p[0]) * p[4] + (y - p[1]) * p[5]
    if kind == ARC:
        ang = math.atan2(y - p[1], x - p[0]) - p[4]
        ang = ang % TWO_PI
        return ang
    return 0.0


@jit
def extent_position(kind, p, x, y, tol):
    """Where ``(x, y)`` lies in the element's extent: -1 outside, 0 interior, 1 at the start, 2 at the end.

    ``tol`` is an absolute length.  Within ``tol`` of an end is at that end; beyond an end, the extent
    reaches ``tol`` times the end's factor (columns ``END_START``, ``END_END``): the full band at a convex
    junction, a rounding-sized one at reflex junctions and free ends (docs/algorithm.md, *4. Corner
    rule and element ends*).
    """
    if kind == SEGMENT:
        u = (x - p[0]) * p[4] + (y - p[1]) * p[5]
        L = p[6]
        if u < -tol * p[END_START] or u > L + tol * p[END_END]:
            return -1
        if u <= tol:
            return 1
        if u >= L - tol:
            return 2
        return 0
    if kind == ARC:
        ang = extent_coordinate(kind, p, x, y)
        span = p[5]
        atol = tol / p[2]
        if ang <= atol or ang >= TWO_PI - atol * p[END_START]:
            return 1
        if span - atol <= ang <= span + atol * p[END_END]:
            return 2
        if ang < span:
            return 0
        return -1
    return 0


@jit
def element_box(kind, p):
    """Axis-aligned bounding box ``(x0, y0, x1, y1)`` of an element (infinite for lines)."""
    if kind == LINE:
        return -math.inf, -math.inf, math.inf, math.inf
    if kind == SEGMENT:
        x1 = p[0] + p[6] * p[4]
        y1 = p[1] + p[6] * p[5]
        return min(p[0], x1), min(p[1], y1), max(p[0], x1), max(p[1], y1)
    return p[0] - p[2], p[1] - p[2], p[0] + p[2], p[1] + p[2]


@jit
def place_on_element(kind, p, x, y):
    """Project ``(x, y)`` onto the element: returns ``(x', y', nx, ny)`` with ``n`` the outward unit normal.

    Lines are projected orthogonally, circles radially, so the particle sits
    on the boundary to rounding and never on the far side by more.
    """
    if kind == LINE or kind == SEGMENT:
        nx = p[2]
        ny = p[3]
        d = (x - p[0]) * nx + (y - p[1]) * ny
        return x - d * nx, y - d * ny, -nx, -ny
    dx = x - p[0]
    dy = y - p[1]
    rho = math.hypot(dx, dy)
    ux = dx / rho
    uy = dy / rho
    r = p[2]
    sig = p[3]
    return p[0] + r * ux, p[1] + r * uy, -sig * ux, -sig * uy


@jit
def arclength(kind, p, x, y):
    """Boundary coordinate ``s`` of a point on the element.

    Line: signed distance from its point along ``t = J n``; segment: distance
    from ``p0``; circle: ``r`` times the CCW angle in ``[0, 2 pi)``; arc: ``r``
    times the CCW angle past ``theta0``.
    """
    if kind == LINE:
        # t = J n_out = J(-n_in) = (n_in_y, -n_in_x)
        return (x - p[0]) * p[3] - (y - p[1]) * p[2]
    if kind == SEGMENT:
        return (x - p[0]) * p[4] + (y - p[1]) * p[5]
    if kind == CIRCLE:
        ang = math.atan2(y - p[1], x - p[0]) % TWO_PI
        return p[2] * ang
    return p[2] * extent_coordinate(kind, p, x, y)

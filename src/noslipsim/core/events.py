"""Event times: when and where a flight next leaves the table.

The flight ``q(t) = q + v t + a t^2/2`` hits element ``i`` at the smallest exit root of its crossing
polynomial in ``(0, hi]`` whose point lies in the element's extent.  For the element just hit the exact
root ``t = 0`` is divided out, so it can be hit again after any positive time (a ball bouncing on a peg).

Degrees: lines 2 with force, 1 without; circles 4 with force, 2 without;
each one less after deflation.  A scene without force never evaluates a cubic
or quartic.  docs/algorithm.md, *1. Next hit* to *5. Grazing guard*.
"""
import math

from .geometry import (
    LINE_GATE,
    TWO_PI,
    crossing_coefficients,
    crossing_slope,
    distance_rate,
    extent_coordinate,
    extent_position,
    line_value_exact,
    signed_distance,
)
from .jit import jit
from .layout import ARC, END_END, END_START, LINE, SEGMENT
from .roots import cubic_exits, linear_exit, quadratic_exit, quartic_exits, straight_circle_exit
from .tolerances import CONTACT_GAP, CONTACT_TOL, NONCONVEX_END_FACTOR

INF = math.inf


@jit
def flight_position(x, y, vx, vy, ax, ay, t):
    """Position after time ``t`` of free flight under constant acceleration."""
    return x + t * (vx + 0.5 * ax * t), y + t * (vy + 0.5 * ay * t)


@jit(inline="always")
def advance(x, y, vx, vy, ax, ay, t, has_force):
    """State ``(x, y, vx, vy)`` after time ``t >= 0`` of free flight.

    Without a force the acceleration terms are exact zeros, skipped: the same values, which the
    compiler cannot drop itself (docs/algorithm.md, *Paying only for what a scene needs*).
    """
    if has_force:
        hx, hy = flight_position(x, y, vx, vy, ax, ay, t)
        return hx, hy, vx + ax * t, vy + ay * t
    return x + t * vx, y + t * vy, vx, vy


@jit
def exit_roots(kind, c0, c1, c2, c3, c4, has_force, deflate, hi):
    """Up to two exit roots in ``(0, hi]`` of an element's crossing polynomial, at the degree it needs."""
    if deflate:  # p(t) = t h(t) with p(0) = 0 exactly: h has the same sign for t > 0
        c0, c1, c2, c3, c4 = c1, c2, c3, c4, 0.0
    straight = kind == LINE or kind == SEGMENT
    if straight:
        if has_force:
            if deflate:
                return linear_exit(c0, c1, hi), INF
            return quadratic_exit(c0, c1, c2, hi), INF
        if deflate:
            return INF, INF
        return linear_exit(c0, c1, hi), INF
    if has_force:
        if deflate:
            return cubic_exits(c0, c1, c2, c3, hi)
        return quartic_exits(c0, c1, c2, c3, c4, hi)
    if deflate:
        return linear_exit(c0, c1, hi), INF
    return quadratic_exit(c0, c1, c2, hi), INF


@jit(inline="always")  # inlined at the call sites: a call per element costs more than its work
def straight_hit_time(kind, p, x, y, vx, vy, deflate, hi, extent_tol):
    """:func:`element_hit_time` for a straight flight (no force): the lean path.

    The coefficients of :func:`geometry.crossing_coefficients` at ``a = 0`` with the same
    floating-point operations (the same hits, bit for bit), only those a straight flight needs: a wall
    the flight moves away from is dropped before its distance is formed (measured: benchmarks/RESULTS.md,
    *Single orbits*).
    """
    if kind == LINE or kind == SEGMENT:
        if deflate:  # a line is not met again after t = 0
            return INF
        c1 = vx * p[2] + vy * p[3]
        if not c1 < 0.0:
            return INF
        t = linear_exit((x - p[0]) * p[2] + (y - p[1]) * p[3], c1, hi)
    else:
        t = straight_circle_exit(x - p[0], y - p[1], vx, vy, p[3], p[2], deflate, hi)
    if t != INF and (kind == SEGMENT or kind == ARC):
        if extent_position(kind, p, x + t * vx, y + t * vy, extent_tol) < 0:
            return INF
    return t


@jit(inline="always")
def element_hit_time(kind, p, x, y, vx, vy, ax, ay, has_force, deflate, hi, extent_tol):
    """First time in ``(0, hi]`` at which the flight leaves the table through this element, or inf."""
    if not has_force:
        return straight_hit_time(kind, p, x, y, vx, vy, deflate, hi, extent_tol)
    c0, c1, c2, c3, c4 = crossing_coefficients(kind, p, x, y, vx, vy, ax, ay)
    e1, e2 = exit_roots(kind, c0, c1, c2, c3, c4, has_force, deflate, hi)
    if kind != SEGMENT and kind != ARC:
        return e1
    for k in range(2):
        e = e1 if k == 0 else e2
        if e == INF:
            break
        hx, hy = flight_position(x, y, vx, vy, ax, ay, e)
        if extent_position(kind, p, hx, hy, extent_tol) >= 0:
            return e
    return INF


@jit
def starts_at_open_end(kind, p, x, y, extent_tol):
    """True if a flight from ``(x, y)`` starts on this segment's or arc's line or circle at an open end.

    An *open* end is a reflex junction or a free end (end factor < 1); "at" and "on" are to within
    ``NONCONVEX_END_FACTOR * extent_tol`` along the element and across it.  There the crossing
    polynomial's exact root ``t = 0`` is no collision, and the caller deflates it
    (:func:`search.cell_search`; docs/algorithm.md, *4. Corner rule and element ends*).
    """
    band = extent_tol * NONCONVEX_END_FACTOR
    if not abs(signed_distance(kind, p, x, y)) <= band:
        return False
    if kind == SEGMENT:
        u = (x - p[0]) * p[4] + (y - p[1]) * p[5]
        return ((p[END_START] < 1.0 and abs(u) <= band)
                or (p[END_END] < 1.0 and abs(u - p[6]) <= band))
    if kind == ARC:
        ang = extent_coordinate(kind, p, x, y)
        atol = band / p[2]
        return ((p[END_START] < 1.0 and (ang <= atol or ang >= TWO_PI - atol))
                or (p[END_END] < 1.0 and abs(ang - p[5]) <= atol))
    return False


@jit(inline="always")
def window_box(bounded, xi, yi, vxi, vyi, ax, ay, span, extent_tol):
    """``(x0, y0, x1, y1)``: a box holding the flight from ``(xi, yi)`` over ``span`` (unbounded if not ``bounded``).

    The arc lies in the hull of its Bezier control points (start, the
    velocity's midpoint, end), so an element copy whose box misses this one
    cannot be hit in the window; the margin covers the rounding of the points.
    """
    if not bounded:
        return -INF, -INF, INF, INF
    x2, y2 = flight_position(xi, yi, vxi, vyi, ax, ay, span)
    x1 = xi + 0.5 * span * vxi
    y1 = yi + 0.5 * span * vyi
    margin = 1e-9 * (abs(xi) + abs(yi) + abs(x2) + abs(y2) + abs(x1) + abs(y1)) + extent_tol
    return min(xi, x1, x2) - margin, min(yi, y1, y2) - margin, max(xi, x1, x2) + margin, max(yi, y1, y2) + margin


@jit
def leaves_through_contact(kind, p, x, y, vx, vy, ax, ay, tol):
    """True if a particle at ``(x, y)`` touches this element and is moving out through it.

    Touching: signed distance in ``[-tol, tol * CONTACT_GAP / CONTACT_TOL]`` (on or, by rounding,
    past its line; a real gap is left to the root finder), ends inclusive, never at a reflex or free
    end (end factor < 1).  The corner rule's test (docs/algorithm.md, *4. Corner rule and element ends*).
    """
    d = signed_distance(kind, p, x, y)
    if d < -tol or d > tol * (CONTACT_GAP / CONTACT_TOL):
        return False
    where = extent_position(kind, p, x, y, tol)
    if where < 0:
        return False
    # at a reflex junction the table is locally the union of the two half planes:
    # having just entered the other one, the particle is inside
    if (where == 1 and p[END_START] < 1.0) or (where == 2 and p[END_END] < 1.0):
        return False
    rate = distance_rate(kind, p, x, y, vx, vy)
    if rate > 0.0:
        return False
    if rate == 0.0:
        c2 = crossing_coefficients(kind, p, x, y, vx, vy, ax, ay)[2]
        if c2 >= 0.0:
            return False
    return True


@jit
def slides_off(kind, p, x, y, vx, vy, ax, ay):
    """True if, just after a hit on this element, the flight leaves through it at once.

    Possible only when the incoming normal velocity was zero to rounding; the event model cannot go
    on (docs/algorithm.md, *5. Grazing guard*).
    """
    c1 = crossing_slope(kind, p, x, y, vx, vy)  # decides all but a contact along the wall
    if c1 > 0.0:
        return False
    if c1 < 0.0:
        return True
    c2, c3, c4 = crossing_coefficients(kind, p, x, y, vx, vy, ax, ay)[2:]
    if c2 != 0.0:
        return c2 < 0.0
    if c3 != 0.0:
        return c3 < 0.0
    return c4 < 0.0


@jit(inline="always")
def exact_line_hit(kind, p, x, y, vx, vy, ax, ay, has_force, deflated, t, hx, hy, px, py, vxi, vyi):
    """A hit on a line or segment redone where the plain distances cancelled (far along a long wall).

    Where the start's plain distance cancelled (its terms exceed ``LINE_GATE`` times its value) or the
    plain projection of ``(hx, hy)`` to ``(px, py)`` carries more than ``LINE_GATE`` times the hit
    point's own rounding, :func:`_redo_line_hit`; once per collision, so the search over all elements
    stays plain (docs/algorithm.md, *1. Next hit*).  Returns ``(t, px, py, vx, vy)`` at the hit (``v``
    changes with ``t`` under a force).
    """
    a = (x - p[0]) * p[2]
    b = (y - p[1]) * p[3]
    ha = (hx - p[0]) * p[2]
    hb = (hy - p[1]) * p[3]
    # the start's distance: relative to itself (the flight time is proportional to it); the hit
    # point's (about 0): against the point's own rounding, eps max(|hx|, |hy|)
    if ((deflated or abs(a) + abs(b) <= LINE_GATE * abs(a + b))
            and abs(ha) + abs(hb) <= LINE_GATE * max(abs(hx), abs(hy))):
        return t, px, py, vxi, vyi
    return _redo_line_hit(kind, p, x, y, vx, vy, ax, ay, has_force, deflated, t, hx, hy, vxi, vyi)


@jit
def _redo_line_hit(kind, p, x, y, vx, vy, ax, ay, has_force, deflated, t, hx, hy, vxi, vyi):
    """:func:`exact_line_hit`'s rare path: the exit root from the start's exact distance (unless the
    element was just hit: its root ``t = 0`` is deflated and its distance not used), then the
    projection with the exact distance (:func:`geometry.line_value_exact`)."""
    nx = p[2]
    ny = p[3]
    a = (x - p[0]) * nx
    b = (y - p[1]) * ny
    if not deflated and abs(a) + abs(b) > LINE_GATE * abs(a + b):
        c0 = line_value_exact(kind, p, x, y)
        c1 = vx * nx + vy * ny
        t2 = quadratic_exit(c0, c1, 0.5 * (ax * nx + ay * ny), INF) if has_force else linear_exit(c0, c1, INF)
        if t2 < INF:
            t = t2
            hx, hy, vxi, vyi = advance(x, y, vx, vy, ax, ay, t, has_force)
    d = line_value_exact(kind, p, hx, hy)
    return t, hx - d * nx, hy - d * ny, vxi, vyi

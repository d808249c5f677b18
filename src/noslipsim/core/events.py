"""Event times: when and where a flight next leaves the table.

The flight ``q(t) = q + v t + a t^2/2`` hits element ``i`` at the smallest
exit root of its crossing polynomial in ``(0, hi]`` whose point lies in the
element's extent.  For the element just hit the exact root ``t = 0`` is
removed analytically (the polynomial is divided by ``t``), so the same element
can be hit again after any positive time (a ball bouncing on a peg).

Degrees: lines 2 with force, 1 without; circles 4 with force, 2 without;
each one less after deflation.  A scene without force never evaluates a cubic
or quartic.
"""
import math

from .geometry import (
    crossing_coefficients,
    distance_rate,
    extent_position,
    signed_distance,
)
from .jit import jit
from .layout import ARC, LINE, SEGMENT
from .roots import cubic_exits, linear_exit, quadratic_exit, quartic_exits

INF = math.inf


@jit
def flight_position(x, y, vx, vy, ax, ay, t):
    """Position after time ``t`` of free flight under constant acceleration."""
    return x + t * (vx + 0.5 * ax * t), y + t * (vy + 0.5 * ay * t)


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


@jit
def element_hit_time(kind, p, x, y, vx, vy, ax, ay, has_force, deflate, hi, extent_tol):
    """First time in ``(0, hi]`` at which the flight leaves the table through this element, or inf."""
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
def next_hit(kinds, params, x, y, vx, vy, ax, ay, has_force, current, hi, extent_tol):
    """Earliest hit ``(t, element)`` over all elements (ties go to the lower index), or ``(inf, -1)``."""
    best_t = hi
    best_i = -1
    for i in range(kinds.shape[0]):
        t = element_hit_time(kinds[i], params[i], x, y, vx, vy, ax, ay, has_force,
                             i == current, best_t, extent_tol)
        if t < best_t or (best_i < 0 and t == best_t and t < INF):
            best_t = t
            best_i = i
    if best_i < 0:
        return INF, -1
    return best_t, best_i


@jit
def leaves_through_contact(kind, p, x, y, vx, vy, ax, ay, tol):
    """True if a particle at ``(x, y)`` touches this element (within ``tol``) and is moving out through it.

    Used for the corner rule: after a hit, any other element touched at the
    same point (ends inclusive) whose supporting line or circle the new
    velocity leaves through is hit at once.  At a convex vertex leaving that
    half plane is leaving the table, whatever the direction along the element;
    at a reflex vertex the extra reflection keeps the particle inside too.
    """
    d = signed_distance(kind, p, x, y)
    if abs(d) > tol:
        return False
    where = extent_position(kind, p, x, y, tol)
    if where < 0:
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

    In exact arithmetic the post-collision normal velocity points into the
    table; it can only fail to when the incoming normal velocity was zero to
    rounding (a grazing contact under a force that presses the particle on the
    wall, or a contact exactly along the wall): the event model cannot go on.
    """
    c0, c1, c2, c3, c4 = crossing_coefficients(kind, p, x, y, vx, vy, ax, ay)
    if c1 > 0.0:
        return False
    if c1 < 0.0:
        return True
    if c2 != 0.0:
        return c2 < 0.0
    if c3 != 0.0:
        return c3 < 0.0
    return c4 < 0.0

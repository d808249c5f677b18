"""The magnetic field as a flight of the event search (:mod:`search`): ``F = (x, y, vx, vy, W)``.

The path is the cyclotron arc of :mod:`magnetic` (speed and spin kept, the velocity turning at the
rate ``W``), which meets each line or circle at most once per period, at its exit root, or never.
So every answer here is one closed-form root: an element's exit from the state where the window
opens, a lattice face's or a level's exit from the functional ``f0 + n . (q(t) - q(0))``, whose
quadratic in the tangent half-angle is the one a line's distance has
(:func:`magnetic.functional_coefficients`).  No search, no step: nothing here can give up.
"""
import math

from .geometry import copy_shift, extent_position
from .jit import jit
from .layout import ARC, LINE, SEGMENT
from .magnetic import (
    advance,
    centre,
    circle_coefficients_at,
    exit_after,
    exit_root,
    exit_time,
    functional_coefficients,
    line_coefficients,
    root_position,
    zeta_time,
)
from .search import leading_point, reach_box

INF = math.inf
#: The search is inlined where it is called, with each element's exit in it: called out of line, the
#: arrays it is passed cost about a fifth of a magnetic collision (benchmarks/RESULTS.md).
INLINE = True
#: Every exit is one closed-form root: nothing gives up.
GIVES_UP = False


start = leading_point


@jit(inline="always")
def state_at(F, t):
    """``(x, y, vx, vy)`` at time ``t``."""
    return advance(F[0], F[1], F[2], F[3], F[4], t)


@jit(inline="always")
def speed_bound(vx, vy):
    """``|v|`` to rounding (the reach tests' margin of 1e-9 covers it) from ``sqrt``, not ``math.hypot`` (a libm call
    per search; measured: benchmarks/RESULTS.md); ``inf`` (no test) where the squares could under- or overflow."""
    s2 = vx * vx + vy * vy
    if not 1e-280 < s2 < 1e280:
        return INF
    return math.sqrt(s2)


@jit(inline="always")
def path_box(F):
    """The cyclotron circle's box (:func:`search.box_search`), widened by ``1e-9`` of its size and place, far
    more than the path's rounding; a straight flight (``W = 0``) has none (infinite)."""
    x, y, vx, vy, W = F
    if W == 0.0:
        return -INF, -INF, INF, INF
    mx, my, rho = centre(x, y, vx, vy, W)
    rho += 1e-9 * (rho + abs(mx) + abs(my))
    return mx - rho, my - rho, mx + rho, my + rho


@jit(inline="always")
def at_start(F):
    """``(x, y, vx, vy, W, c)``: the flight from ``t = 0`` and a bound ``c`` on its speed (:func:`speed_bound`)."""
    x, y, vx, vy, W = F
    return x, y, vx, vy, W, speed_bound(vx, vy)


@jit(inline="always")
def window(F, lo):
    """The state where a window opens at ``lo`` (the path from there is the same circle, re-based), as
    :func:`at_start` gives it."""
    if lo == 0.0:
        return at_start(F)
    x, y, vx, vy = advance(F[0], F[1], F[2], F[3], F[4], lo)
    return x, y, vx, vy, F[4], speed_bound(vx, vy)


@jit(inline="always")
def window_box(F, G, lo, hi, extent_tol):
    """A bounded window: the box the path, at its constant speed, cannot leave from where the window opens
    (the speed bound there, ``G[5]``: within rounding of the speed, which the box's margin covers)."""
    bounded = hi < INF
    bx0 = by0 = bx1 = by1 = 0.0
    if bounded:
        bx0, by0, bx1, by1 = reach_box(G[0], G[1], G[5], hi - lo, extent_tol)
    return bounded, bx0, by0, bx1, by1


shift = copy_shift


@jit(inline="always")
def element_exit(kind, p, G, S, deflate, lo, hi, extent_tol):
    """The exit root in ``(lo, hi]`` through the element copy shifted by ``S[:2]``, within its extent, or inf.

    ``G`` is the state at ``lo`` (:func:`window`; ``deflate`` only with ``lo = 0``): the next exit after ``lo``,
    as a closed path meets an element at one root per period.  The cell search passes the earliest hit so far
    as ``hi``: a copy the path cannot reach by then, a segment's exit off the segment (its point is rational,
    :func:`root_position`) and an exit certainly later (:func:`magnetic.exit_after`) are dropped before the
    exit's ``atan2`` (docs/algorithm.md, "Magnetic flights", *What a copy costs*).
    """
    x, y, vx, vy, W, c = G
    x -= S[0]
    y -= S[1]
    # |q(t) - q(lo)| <= c (t - lo): no hit before the distance ``gap`` is flown
    reach = c * (hi - lo) * (1.0 + 1e-9) + extent_tol if not deflate and hi < INF else INF
    if kind == LINE or kind == SEGMENT:  # layout normals point into the table; magnetic's out of it
        if (x - p[0]) * p[2] + (y - p[1]) * p[3] > reach:
            return INF
        c0, c1, c2, m0, m1, m2 = line_coefficients(x, y, vx, vy, W, p[0], p[1], -p[2], -p[3], deflate)
    else:
        rho = math.hypot(x - p[0], y - p[1])  # the gap's and the quadratic's: one hypot for both
        if p[3] * (rho - p[2]) > reach:
            return INF
        c0, c1, c2, m0, m1, m2 = circle_coefficients_at(x, y, vx, vy, W, p[0], p[1], p[2], p[3], deflate, rho,
                                                        math.hypot(vx, vy))
    found, num, den = exit_root(c0, c1, c2, m0, m1, m2, deflate)
    if not found:
        return INF
    if kind == SEGMENT and not _in_extent(kind, p, x, y, vx, vy, W, num, den, extent_tol):
        return INF
    if hi < INF and W != 0.0 and exit_after(num, den, W, lo, hi):  # certainly late: no atan2 for its time
        return INF
    t = zeta_time(num, den, W)
    if t == INF or lo + t > hi:
        return INF
    # an arc's extent test takes an atan2 of its own: after the time, which rejects late exits first
    if kind == ARC and not _in_extent(kind, p, x, y, vx, vy, W, num, den, extent_tol):
        return INF
    return lo + t


@jit(inline="always")
def _in_extent(kind, p, x, y, vx, vy, W, num, den, extent_tol):
    """The root ``zeta = num / den`` lies in the segment's or arc's extent (its point from the root itself: no
    sine or cosine)."""
    hx, hy = root_position(x, y, vx, vy, W, num, den)
    return extent_position(kind, p, hx, hy, extent_tol) >= 0


@jit(inline="always")
def _functional_exit(f, m0, nx, ny, vx, vy, W):
    """Time of the first exit of ``f + n . (q(t) - q(0))`` from the state ``(vx, vy)`` where it is ``f``
    (``m0``: the size of the terms ``f`` was formed from; :func:`magnetic.functional_coefficients`)."""
    c0, c1, c2, m0, m1, m2 = functional_coefficients(f, m0, nx, ny, vx, vy, W)
    return exit_time(c0, c1, c2, m0, m1, m2, W, False)


@jit(inline="always")  # a strip's two faces advance to the same t_in: inlined, LLVM may form it once (no gain measured)
def face_exit(F, f0, nx, ny, t_in):
    """First time ``>= t_in`` at which ``f0 + n . (q(t) - q(0))`` (positive inside) leaves; ``t_in`` when on or
    past the face then and moving out (or along it and turning out)."""
    x0, y0, vx, vy, W = F
    f = f0
    m0 = abs(f0)
    if t_in != 0.0:
        qx, qy, vx, vy = advance(x0, y0, vx, vy, W, t_in)
        f = f0 + (nx * (qx - x0) + ny * (qy - y0))
        m0 += abs(nx) * (abs(qx) + abs(x0)) + abs(ny) * (abs(qy) + abs(y0))
    rate = nx * vx + ny * vy
    if f <= 0.0 and (rate < 0.0 or (rate == 0.0 and W * (ny * vx - nx * vy) < 0.0)):
        return t_in
    return t_in + _functional_exit(f, m0, nx, ny, vx, vy, W)


@jit
def line_exit(F, f0, nx, ny):
    """The first exit root in ``(0, inf)`` of ``f0 + n . (q(t) - q(0))`` (a level, a long wall's exact distance)."""
    return _functional_exit(f0, abs(f0), nx, ny, F[2], F[3], F[4])

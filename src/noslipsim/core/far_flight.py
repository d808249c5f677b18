"""Free flight seen from a cell far from its start (``cells.FAR_CELLS`` or more): the cell search's flight there.

``F`` is :mod:`free_flight`'s, and :data:`straight`, :data:`falling` are two flights as there.  Formed
plainly, the start relative to a far copy, a difference of two lengths as long as the flight, carries
``eps`` times it.  Here the flight's point where the window opens is formed to twice the working
precision (:func:`flight_point_dd`) and the copy's translation exactly (:func:`exact.lattice_shift_dd`),
so *which* copy is hit, and when, is decided to the cell's precision; the velocity there is ``v + a lo``
(a few ulps of the speed).  The copy just hit is solved from the collision, plainly, as in
:mod:`free_flight`.  docs/algorithm.md, *Lattices*.

The window ``G = (xh, xl, yh, yl, vx, vy, ax, ay, x, y, vx0, vy0)``: the point as two floats each, the
velocity and acceleration there, and the collision's state (for the copy just hit).
"""
import functools
import math

from .events import element_hit_time
from .events import window_box as _arc_box
from .exact import lattice_shift_dd, two_prod, two_sum
from .geometry import copy_shift
from .jit import jit
from .search import FlightProtocol

INF = math.inf


@jit(inline="always")
def flight_point_dd(x, vx, ax, t, has_force):
    """One coordinate of the flight's point ``x + vx t + ax t^2/2`` as ``(h, l)``, exact but for ``eps^2`` of its terms.

    The products are formed exactly (:func:`exact.two_prod`; ``t^2`` too) and
    summed with :func:`exact.two_sum`, so subtracting a far translation from
    ``h + l`` leaves a few ulps of the difference, however long the flight.
    """
    p, pe = two_prod(vx, t)
    lo = pe
    if has_force:
        tt, te = two_prod(t, t)
        h = 0.5 * ax
        g, ge = two_prod(h, tt)
        p, e = two_sum(p, g)
        lo = ((e + pe) + ge) + h * te
    s, e = two_sum(p, x)
    return s, e + lo


@jit(inline="always")
def minus_shift_dd(h, lo, sh, sl):
    """``(h + lo) - (sh + sl)`` rounded once: a far point seen from a far translation, to a few ulps of itself."""
    s, e = two_sum(h, -sh)
    return s + ((e + lo) - sl)


@jit(inline="always")
def start(F):
    """``(x, y)`` at the collision."""
    return F[0], F[1]


@jit(inline="always")
def at_start(F):
    """The collision's state in the window's form (only its plain part is read, for the copy just hit)."""
    x, y, vx, vy, ax, ay = F
    return x, 0.0, y, 0.0, vx, vy, ax, ay, x, y, vx, vy


@jit(inline="always")
def shift(A, o1, o2, shifted):
    """The copy's translation plainly (filters, the copy just hit) and exactly, ``(sx, sy, sxh, sxl, syh, syl)``."""
    sx, sy = copy_shift(A, o1, o2, True)
    sxh, sxl, syh, syl = lattice_shift_dd(A, o1, o2)
    return sx, sy, sxh, sxl, syh, syl


@functools.cache
def far_flight(FALLING):
    """The far cells' flight (:mod:`search`'s protocol) without (``FALLING=False``) or under the force (``True``)."""
    @jit(inline="always")
    def window(F, lo):
        """The point at ``lo`` to twice the working precision, the velocity there (module docstring)."""
        x, y, vx, vy, ax, ay = F
        xh, xl = flight_point_dd(x, vx, ax, lo, FALLING)
        yh, yl = flight_point_dd(y, vy, ay, lo, FALLING)
        vxi = vx
        vyi = vy
        if FALLING:
            vxi = vx + ax * lo
            vyi = vy + ay * lo
        return xh, xl, yh, yl, vxi, vyi, ax, ay, x, y, vx, vy

    @jit(inline="always")
    def window_box(F, G, lo, hi, extent_tol):
        """Under a force and a bounded window, the box of the window's arc (:func:`events.window_box`)."""
        if not FALLING:
            return False, 0.0, 0.0, 0.0, 0.0
        bounded = hi < INF
        bx0, by0, bx1, by1 = _arc_box(bounded, G[0] + G[1], G[2] + G[3], G[4], G[5], G[6], G[7], hi - lo,
                                      extent_tol)
        return bounded, bx0, by0, bx1, by1

    @jit(inline="always")
    def element_exit(kind, p, G, S, deflate, lo, hi, extent_tol):
        """:func:`events.element_hit_time` from the window's exact point seen from the copy's exact translation."""
        xh, xl, yh, yl, vx, vy, ax, ay, x0, y0, vx0, vy0 = G
        if deflate:  # the copy just hit, from the collision (lo = 0)
            return element_hit_time(kind, p, x0 - S[0], y0 - S[1], vx0, vy0, ax, ay, FALLING, True, hi, extent_tol)
        return lo + element_hit_time(kind, p, minus_shift_dd(xh, xl, S[2], S[3]), minus_shift_dd(yh, yl, S[4], S[5]),
                                     vx, vy, ax, ay, FALLING, False, hi - lo, extent_tol)

    return FlightProtocol(
        __name__=f"{__name__}.{'falling' if FALLING else 'straight'}",
        # reached only by long flights: the search is compiled once, out of line; no exit searches
        INLINE=False, GIVES_UP=False, start=start, at_start=at_start, window=window, window_box=window_box,
        shift=shift, element_exit=element_exit)


#: A straight flight's far cells.
straight = far_flight(False)
#: Far cells under the force.
falling = far_flight(True)

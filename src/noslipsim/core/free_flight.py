"""Free flight (straight, or a parabola under the constant force) as a flight of the cell search (:mod:`search`).

``F = (x, y, vx, vy, ax, ay)``: the state at the collision and the acceleration.  Each copy is solved on
the flight re-centred where the window opens (its crossing polynomial formed at the scale of the cell,
:func:`events.element_hit_time`); the copy just hit from the collision, its root ``t = 0`` divided out.
Under a force a copy whose box misses the box of the window's arc is skipped (:func:`events.window_box`);
a straight flight skips the filter, whose test costs about as much as its exit.  Nothing here searches,
so nothing gives up.

Two flights, :data:`straight` (no force) and :data:`falling` (under the force): the force is a constant
of each, not a member of ``F``, as numba prunes a branch on a closure's constant before typing, never one
on a tuple's member (docs/algorithm.md, *One event search for every flight*; the compile time it saves:
benchmarks/RESULTS.md, "Where the compile time went").
"""
import functools
import math

from .events import advance, element_hit_time
from .events import window_box as _arc_box
from .geometry import copy_shift
from .jit import jit
from .search import FlightProtocol, leading_point, same_flight

INF = math.inf


@functools.cache
def free_flight(FALLING):
    """The free flight's protocol (:mod:`search`) without (``FALLING=False``) or under the force (``True``)."""
    @jit(inline="always")
    def window(F, lo):
        """The flight re-centred at ``lo``: its state there, the same acceleration."""
        x, y, vx, vy, ax, ay = F
        xi, yi, vxi, vyi = advance(x, y, vx, vy, ax, ay, lo, FALLING)
        return xi, yi, vxi, vyi, ax, ay

    @jit(inline="always")
    def window_box(F, G, lo, hi, extent_tol):
        """Under a force and a bounded window, the box of the window's arc; no filter otherwise."""
        if not FALLING:
            return False, 0.0, 0.0, 0.0, 0.0
        bounded = hi < INF
        bx0, by0, bx1, by1 = _arc_box(bounded, G[0], G[1], G[2], G[3], G[4], G[5], hi - lo, extent_tol)
        return bounded, bx0, by0, bx1, by1

    @jit(inline="always")
    def element_exit(kind, p, G, S, deflate, lo, hi, extent_tol):
        """:func:`events.element_hit_time` on the flight ``G`` seen from the copy shifted by ``S``, offset by ``lo``."""
        x, y, vx, vy, ax, ay = G
        if deflate:  # from the collision (lo = 0): the time as it comes
            return element_hit_time(kind, p, x - S[0], y - S[1], vx, vy, ax, ay, FALLING, True, hi, extent_tol)
        return lo + element_hit_time(kind, p, x - S[0], y - S[1], vx, vy, ax, ay, FALLING, False, hi - lo,
                                     extent_tol)

    @jit(inline="always")
    def state_at(F, t):
        """``(x, y, vx, vy)`` at time ``t``."""
        x, y, vx, vy, ax, ay = F
        return advance(x, y, vx, vy, ax, ay, t, FALLING)

    return FlightProtocol(
        __name__=f"{__name__}.{'falling' if FALLING else 'straight'}",
        # the search is inlined where it is called: a call per cell costs more than its work
        INLINE=True, GIVES_UP=False, start=leading_point, at_start=same_flight, window=window,
        window_box=window_box, shift=copy_shift, element_exit=element_exit, state_at=state_at)


#: A straight flight (no force).
straight = free_flight(False)
#: A flight under the constant force.
falling = free_flight(True)

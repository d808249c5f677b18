"""Free flight (straight, or a parabola under the constant force) as a flight of the cell search (:mod:`search`).

``F = (x, y, vx, vy, ax, ay, has_force)``: the state at the collision and the acceleration.  Each
copy is solved on the flight re-centred where the window opens (its crossing polynomial formed at
the scale of the cell, :func:`events.element_hit_time`); the copy just hit from the collision, its
root ``t = 0`` divided out.  Under a force a copy whose box misses the box of the window's arc is
skipped (:func:`events.window_box`); a straight flight skips the filter, whose test costs about as
much as its exit.  Nothing here searches, so nothing gives up.

``has_force`` is a compile-time constant of every specialised event loop: the straight path is the
one compiled (a scene without force never forms a cubic or quartic).
"""
import math

from .events import advance, element_hit_time
from .events import window_box as _arc_box
from .geometry import copy_shift
from .jit import jit
from .search import leading_point, same_flight

INF = math.inf
#: The search is inlined where it is called: a call per cell costs more than its work (events.hit_in_cell).
INLINE = True
#: No element exit searches: none gives up.
GIVES_UP = False


start = leading_point


at_start = same_flight


@jit(inline="always")
def window(F, lo):
    """The flight re-centred at ``lo``: its state there, the same acceleration."""
    x, y, vx, vy, ax, ay, has_force = F
    xi, yi, vxi, vyi = advance(x, y, vx, vy, ax, ay, lo, has_force)
    return xi, yi, vxi, vyi, ax, ay, has_force


@jit(inline="always")
def window_box(F, G, lo, hi, extent_tol):
    """Under a force and a bounded window, the box of the window's arc; no filter otherwise."""
    bounded = hi < INF and F[6]
    bx0, by0, bx1, by1 = _arc_box(bounded, G[0], G[1], G[2], G[3], G[4], G[5], hi - lo, extent_tol)
    return bounded, bx0, by0, bx1, by1


shift = copy_shift


@jit(inline="always")
def element_exit(kind, p, G, S, deflate, lo, hi, extent_tol):
    """:func:`events.element_hit_time` on the flight ``G`` seen from the copy shifted by ``S``, offset by ``lo``."""
    x, y, vx, vy, ax, ay, has_force = G
    if deflate:  # from the collision (lo = 0): the time as it comes
        return element_hit_time(kind, p, x - S[0], y - S[1], vx, vy, ax, ay, has_force, True, hi, extent_tol)
    return lo + element_hit_time(kind, p, x - S[0], y - S[1], vx, vy, ax, ay, has_force, False, hi - lo,
                                 extent_tol)


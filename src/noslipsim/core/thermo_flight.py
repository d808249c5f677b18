"""The isokinetic thermostat as a flight of the event search (:mod:`search`): ``F = (fl, E)``.

``fl`` is the closed-form path from the collision (:func:`thermostat.flight`), ``E`` the
field's strength; every answer is one of :mod:`thermo_events`, which certifies it.
"""
import math

from .geometry import copy_shift
from .jit import jit
from .search import reach_box
from .thermo_events import element_hit
from .thermo_events import face_exit as _face_exit
from .thermo_events import line_exit as _line_exit
from .thermostat import state

INF = math.inf
#: The search is compiled once, called per cell (its circle search is long).
INLINE = False
#: A circle's search may run out of steps (:data:`search.GAVE_UP`).
GIVES_UP = True


@jit(inline="always")
def start(F):
    """``(x, y)`` at the collision."""
    return F[0][0], F[0][1]


@jit(inline="always")
def state_at(F, t):
    """``(x, y, vx, vy)`` at time ``t``."""
    return state(F[0], t)


@jit(inline="always")
def window(F, lo):
    """The path itself: its exits are solved from the collision over ``(lo, hi]``."""
    return F


@jit(inline="always")
def at_start(F):
    """The path itself."""
    return F


@jit(inline="always")
def window_box(F, G, lo, hi, extent_tol):
    """A bounded window: the box the path, at its constant speed, cannot leave from where the window opens."""
    bounded = hi < INF
    bx0 = by0 = bx1 = by1 = 0.0
    if bounded:
        xi, yi = state(F[0], lo)[:2]
        bx0, by0, bx1, by1 = reach_box(xi, yi, F[0][4], hi - lo, extent_tol)
    return bounded, bx0, by0, bx1, by1


shift = copy_shift


@jit(inline="always")
def element_exit(kind, p, F, S, deflate, lo, hi, extent_tol):
    """:func:`thermo_events.element_hit` (``GAVE_UP`` when a circle search ran out of steps)."""
    return element_hit(kind, p, F[0], S[0], S[1], deflate, lo, hi, extent_tol, F[1])


@jit(inline="always")
def face_exit(F, f0, nx, ny, t_in):
    """:func:`thermo_events.face_exit`."""
    return _face_exit(F[0], f0, nx, ny, t_in)


@jit(inline="always")
def line_exit(F, f0, nx, ny):
    """:func:`thermo_events.line_exit` over ``(0, inf)``."""
    return _line_exit(F[0], f0, nx, ny, 0.0, INF, False)

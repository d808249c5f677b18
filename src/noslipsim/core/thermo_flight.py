"""The isokinetic thermostat as a flight of the event search (:mod:`search`): ``F = (fl, E)``.

``fl`` is the closed-form path from the collision (:func:`thermostat.flight`), ``E`` the
field's strength; every answer is one of :mod:`thermo_events`, which certifies it.
"""
import math

from .jit import jit
from .thermo_events import element_hit
from .thermo_events import face_exit as _face_exit
from .thermo_events import line_exit as _line_exit
from .thermostat import state

INF = math.inf


@jit(inline="always")
def start(F):
    """``(x, y)`` at the collision."""
    return F[0][0], F[0][1]


@jit(inline="always")
def state_at(F, t):
    """``(x, y, vx, vy)`` at time ``t``."""
    return state(F[0], t)


@jit(inline="always")
def speed_bound(F):
    """The speed, kept in flight."""
    return F[0][4]


@jit(inline="always")
def window(F, lo):
    """The path itself: its exits are solved from the collision over ``(lo, hi]``."""
    return F


@jit(inline="always")
def element_exit(kind, p, F, sx, sy, deflate, lo, hi, extent_tol):
    """:func:`thermo_events.element_hit` (``GAVE_UP`` when a circle search ran out of steps)."""
    return element_hit(kind, p, F[0], sx, sy, deflate, lo, hi, extent_tol, F[1])


@jit(inline="always")
def face_exit(F, f0, nx, ny, t_in):
    """:func:`thermo_events.face_exit`."""
    return _face_exit(F[0], f0, nx, ny, t_in)


@jit(inline="always")
def line_exit(F, f0, nx, ny):
    """:func:`thermo_events.line_exit` over ``(0, inf)``."""
    return _line_exit(F[0], f0, nx, ny, 0.0, INF, False)

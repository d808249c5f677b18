"""The event loop: one orbit, collision after collision.

One bounce is three named steps (as in DynamicalBilliards.jl):

1. next hit: the earliest exit root over all elements (:func:`events.next_hit`);
2. relocate: evaluate the flight at that root and project onto the element
   (:func:`geometry.place_on_element`), so rounding never leaves the particle
   outside;
3. resolve: apply the collision law (:func:`laws.collide`).

Corner rule: after a hit, every other element that touches the hit point
(within ``CONTACT_TOL``) and that the new velocity would leave through is hit
at once, in index order, each counted as a collision with ``corner = 1``;
at a right-angle corner this reverses the velocity as the limit of nearby
orbits does.  More than ``MAX_CORNER_BOUNCES`` in a row stop the orbit.

Positions and times are always relative to the last collision; only the
total time is a running sum.
"""
import math

from .events import flight_position, leaves_through_contact, next_hit, slides_off
from .geometry import arclength, place_on_element
from .jit import jit
from .laws import collide
from .layout import (
    LOG_CORNER, LOG_ELEMENT, LOG_S, LOG_T, LOG_VX, LOG_VX_IN, LOG_VY, LOG_VY_IN, LOG_W,
    LOG_W_IN, LOG_X, LOG_Y, STOP_CORNER, STOP_ESCAPE, STOP_GRAZING, STOP_LEVEL,
    STOP_MAX_COLLISIONS, STOP_MAX_TIME,
)
from .roots import quadratic_exit
from .tolerances import CONTACT_TOL, EXTENT_TOL, MAX_CORNER_BOUNCES

INF = math.inf


@jit
def _record(log, n, t, x, y, vx, vy, w, vx_in, vy_in, w_in, kind, p, element, corner):
    if n < log.shape[0]:
        row = log[n]
        row[LOG_T] = t
        row[LOG_X] = x
        row[LOG_Y] = y
        row[LOG_VX] = vx
        row[LOG_VY] = vy
        row[LOG_W] = w
        row[LOG_VX_IN] = vx_in
        row[LOG_VY_IN] = vy_in
        row[LOG_W_IN] = w_in
        row[LOG_ELEMENT] = element
        row[LOG_S] = arclength(kind, p, x, y)
        row[LOG_CORNER] = corner


@jit
def _contact_element(kinds, params, x, y, vx, vy, ax, ay, current, tol):
    for j in range(kinds.shape[0]):
        if j != current and leaves_through_contact(kinds[j], params[j], x, y, vx, vy, ax, ay, tol):
            return j
    return -1


@jit
def run_orbit(kinds, params, law, c, s, ax, ay, x, y, vx, vy, w,
              max_collisions, max_time, stop_below, scale, log):
    """Run one orbit from a state strictly inside the table.

    Parameters
    ----------
    kinds, params : arrays
        Scene elements (see :mod:`noslipsim.core.layout`).
    law : int
        ``SPECULAR`` or ``NOSLIP``; ``c, s`` are the no-slip coefficients.
    ax, ay : float
        Constant acceleration (force per unit mass).
    x, y, vx, vy, w : float
        Initial position, velocity and scaled spin ``w = gamma R omega``.
    max_collisions : int
        Stop after this many collisions (corner collisions included).
    max_time : float
        Stop at this time (the state is advanced to it); ``inf`` for none.
    stop_below : float
        Stop when the particle crosses this height downwards; ``-inf`` for none.
    scale : float
        Length scale of the scene, for the relative tolerances.
    log : float64 array (n_log, N_LOG)
        Collision records for the first ``n_log`` collisions (may have 0 rows).

    Returns
    -------
    n, stop, n_corner, t, x, y, vx, vy, w
        Collision count, stop code, corner collisions, and the final state.
    """
    has_force = ax != 0.0 or ay != 0.0
    t = 0.0
    current = -1
    n = 0
    n_corner = 0
    stop = STOP_MAX_COLLISIONS
    while n < max_collisions:
        length = max(scale, abs(x), abs(y))
        extent_tol = EXTENT_TOL * length
        remaining = max_time - t
        t_hit, i_hit = next_hit(kinds, params, x, y, vx, vy, ax, ay, has_force, current,
                                INF, extent_tol)
        t_level = INF
        if stop_below > -INF:
            t_level = quadratic_exit(y - stop_below, vy, 0.5 * ay, INF)
        if t_level < INF and t_level <= t_hit and t_level <= remaining:
            x, y = flight_position(x, y, vx, vy, ax, ay, t_level)
            y = stop_below
            vx += ax * t_level
            vy += ay * t_level
            t += t_level
            stop = STOP_LEVEL
            break
        if i_hit < 0:  # no element ahead: the orbit leaves for good (state of the last collision)
            stop = STOP_ESCAPE
            break
        if t_hit > remaining:
            x, y = flight_position(x, y, vx, vy, ax, ay, remaining)
            vx += ax * remaining
            vy += ay * remaining
            t = max_time
            stop = STOP_MAX_TIME
            break
        # relocate onto the element, then resolve the collision
        hx, hy = flight_position(x, y, vx, vy, ax, ay, t_hit)
        vx_in = vx + ax * t_hit
        vy_in = vy + ay * t_hit
        kind = kinds[i_hit]
        p = params[i_hit]
        x, y, nx, ny = place_on_element(kind, p, hx, hy)
        vx, vy, w_out = collide(law, c, s, vx_in, vy_in, w, nx, ny)
        t += t_hit
        _record(log, n, t, x, y, vx, vy, w_out, vx_in, vy_in, w, kind, p, i_hit, 0.0)
        w = w_out
        n += 1
        current = i_hit
        # corner rule: other elements touched here that the particle would leave through
        bounces = 0
        while n < max_collisions:
            j = _contact_element(kinds, params, x, y, vx, vy, ax, ay, current,
                                 CONTACT_TOL * length)
            if j < 0:
                break
            bounces += 1
            if bounces > MAX_CORNER_BOUNCES:
                stop = STOP_CORNER
                break
            kind = kinds[j]
            p = params[j]
            nx, ny = place_on_element(kind, p, x, y)[2:]
            vx_in = vx
            vy_in = vy
            vx, vy, w_out = collide(law, c, s, vx_in, vy_in, w, nx, ny)
            _record(log, n, t, x, y, vx, vy, w_out, vx_in, vy_in, w, kind, p, j, 1.0)
            w = w_out
            n += 1
            n_corner += 1
            current = j
        if stop == STOP_CORNER:
            break
        if slides_off(kinds[current], params[current], x, y, vx, vy, ax, ay):
            stop = STOP_GRAZING
            break
    return n, stop, n_corner, t, x, y, vx, vy, w

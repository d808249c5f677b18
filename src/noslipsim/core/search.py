"""The event search of a closed-form flight, written once: the earliest hit in a cell, the cell walk, a long wall.

A *flight* is a module that answers seven questions about the path from one
collision to the next, each a small kernel taking the flight's state ``F``
(a tuple the module builds; it is never inspected here):

=================================================  ==========================================================
``start(F)``                                        ``(x, y)`` at ``t = 0``
``state_at(F, t)``                                  ``(x, y, vx, vy)`` at time ``t``
``speed_bound(F)``                                  a bound on the speed over the flight (the reach filter)
``window(F, lo)``                                   the flight as ``element_exit`` takes it for a window
                                                    opening at ``lo`` (formed once per cell)
``element_exit(kind, p, G, sx, sy, deflate,         the first exit root in ``(lo, hi]`` through the element
lo, hi, extent_tol)``                               copy shifted by ``(sx, sy)``, within its extent, of the
                                                    flight ``G = window(F, lo)``; ``inf`` for none, a negative
                                                    time when the search gave up
``face_exit(F, f0, nx, ny, t_in)``                  the first time ``>= t_in`` at which ``f0 + n . (q(t) - q(0))``
                                                    (positive inside) leaves; ``t_in`` when on or past it and
                                                    moving out
``line_exit(F, f0, nx, ny)``                        the first exit root in ``(0, inf)`` of that function
=================================================  ==========================================================

:func:`event_search` builds, for one flight, the cell search (:func:`hit_in_cell`'s rules: the copy
just hit deflated, a segment or arc whose open end the flight starts at deflated too, copies out of
reach skipped, ties to the earlier copy), the lattice walk (each strip's exit a ``face_exit``) and the
exact hit on a long wall.  The thermostat (:mod:`thermo_events`) and the magnetic field
(:mod:`magnetic_flight`) are such flights; the polynomial flights (straight and free fall) keep their
own tuned search (:mod:`events`, :mod:`cells`), whose windows are re-centred at each cell's entry time
(docs/extending.md, "A flight").
"""
import functools
import math

from .events import starts_at_open_end
from .geometry import LINE_GATE, copy_shift, element_box, lattice_coordinates, line_value_exact
from .jit import jit
from .layout import ARC, END_END, END_START, SEGMENT

INF = math.inf
#: The element :func:`event_search`'s cell search returns when a search in it gave up (a negative time).
SEARCH_FAILED = -2
#: The time returned with :data:`SEARCH_FAILED`.
GAVE_UP = -1.0


@functools.cache
def event_search(flight, compile=jit):
    """``(hit_in_cell, walk_hit, exact_line_hit)`` for the flight module ``flight`` (built once per flight).

    ``compile``: how each is compiled (:func:`jit.jit`; the identity gives their Python source, calling
    the flight's functions as they are, for tests that patch a flight's constants).

    ``hit_in_cell(kinds, params, copies, A, d1, d2, F, cur_e, cur_o1, cur_o2, hi, extent_tol, t_in, shifted)``:
    the earliest hit in ``(t_in, hi]`` over the copies that reach cell ``(d1, d2)``; ``(t, element, o1, o2)``,
    ``(inf, -1, 0, 0)`` or ``(GAVE_UP, SEARCH_FAILED, 0, 0)``.

    ``walk_hit(kinds, params, copies, A, B, F, cur_e, cur_o1, cur_o2, t_limit, extent_tol, max_cells)``: the
    earliest hit in a periodic scene; ``(t, element, o1, o2, status)``, status 0 hit, 1 past ``t_limit``,
    2 past ``max_cells`` cells, 3 a search gave up.

    ``exact_line_hit(kind, p, F, sx, sy, deflated, t, hx, hy, px, py, vx, vy)``: a hit far along a long wall
    redone from the exact distances (:func:`events.exact_line_hit`); ``(t, px, py, vx, vy)``.
    """
    start = flight.start
    state_at = flight.state_at
    speed_bound = flight.speed_bound
    window = flight.window
    element_exit = flight.element_exit
    face_exit = flight.face_exit
    line_exit = flight.line_exit

    @compile
    def hit_in_cell(kinds, params, copies, A, d1, d2, F, cur_e, cur_o1, cur_o2, hi, extent_tol, t_in, shifted):
        bounded = hi < INF
        xi = 0.0
        yi = 0.0
        reach = INF
        if bounded:  # the path cannot get farther than speed x window from where it enters
            xi, yi = state_at(F, t_in)[:2]
            reach = speed_bound(F) * (hi - t_in) * (1.0 + 1e-9) + extent_tol
        x0, y0 = start(F)
        G0 = window(F, 0.0)
        G = window(F, t_in)  # the flight where the window opens: once per cell, not per copy
        best_t = hi
        best_e = -1
        best_o1 = 0
        best_o2 = 0
        for k in range(copies.shape[0]):
            e = copies[k, 0]
            o1 = copies[k, 1] + d1
            o2 = copies[k, 2] + d2
            sx, sy = copy_shift(A, o1, o2, shifted)
            if e == cur_e and o1 == cur_o1 and o2 == cur_o2:
                t = element_exit(kinds[e], params[e], G0, sx, sy, True, 0.0, best_t, extent_tol)
            else:
                if bounded:
                    ex0, ey0, ex1, ey1 = element_box(kinds[e], params[e])
                    if (ex0 + sx > xi + reach or ex1 + sx < xi - reach
                            or ey0 + sy > yi + reach or ey1 + sy < yi - reach):
                        continue
                t = element_exit(kinds[e], params[e], G, sx, sy, False, t_in, best_t, extent_tol)
                if (0.0 <= t <= best_t and t < INF and (kinds[e] == SEGMENT or kinds[e] == ARC)
                        and (params[e, END_START] < 1.0 or params[e, END_END] < 1.0)
                        and starts_at_open_end(kinds[e], params[e], x0 - sx, y0 - sy, extent_tol)):
                    # the root t = 0 at an open end is exact: no collision (events.hit_in_cell)
                    t = element_exit(kinds[e], params[e], G0, sx, sy, True, 0.0, best_t, extent_tol)
            if t < 0.0:  # a search gave up: the earliest hit is unknown
                return GAVE_UP, SEARCH_FAILED, 0, 0
            if t < best_t or (best_e < 0 and t == best_t and t < INF):
                best_t = t
                best_e = e
                best_o1 = o1
                best_o2 = o2
        if best_e < 0:
            return INF, -1, 0, 0
        return best_t, best_e, best_o1, best_o2

    @compile
    def strip_exit(F, alpha0, bx, by, d, t_in):
        """First time ``>= t_in`` the lattice coordinate ``alpha0 + b . (q(t) - q(0))`` leaves ``[d - 1/2, d + 1/2]``:
        ``(t, +1)`` through the upper face, ``(t, -1)`` through the lower, ``(inf, 0)`` if never."""
        t_up = face_exit(F, d + 0.5 - alpha0, -bx, -by, t_in)
        t_dn = face_exit(F, alpha0 - (d - 0.5), bx, by, t_in)
        if t_up <= t_dn and t_up < INF:
            return t_up, 1
        if t_dn < INF:
            return t_dn, -1
        return INF, 0

    @compile
    def walk_hit(kinds, params, copies, A, B, F, cur_e, cur_o1, cur_o2, t_limit, extent_tol, max_cells):
        x0, y0 = start(F)
        a0, b0 = lattice_coordinates(B, x0, y0)
        d1 = 0
        d2 = 0
        t_in = 0.0
        ta, sa = strip_exit(F, a0, B[0, 0], B[0, 1], 0, 0.0)
        tb, sb = strip_exit(F, b0, B[1, 0], B[1, 1], 0, 0.0)
        for _ in range(max_cells):
            t_out = min(ta, tb)
            t, e, o1, o2 = hit_in_cell(kinds, params, copies, A, d1, d2, F, cur_e, cur_o1, cur_o2, t_out,
                                       extent_tol, t_in, True)
            if e >= 0:
                return t, e, o1, o2, 0
            if e == SEARCH_FAILED:
                return GAVE_UP, SEARCH_FAILED, 0, 0, 3
            if t_out >= t_limit:
                return INF, -1, 0, 0, 1
            if ta == t_out:
                d1 += sa
                ta, sa = strip_exit(F, a0, B[0, 0], B[0, 1], d1, t_out)
            if tb == t_out:
                d2 += sb
                tb, sb = strip_exit(F, b0, B[1, 0], B[1, 1], d2, t_out)
            t_in = t_out
        return INF, -1, 0, 0, 2

    @compile
    def exact_line_hit(kind, p, F, sx, sy, deflated, t, hx, hy, px, py, vxi, vyi):
        # hx, hy: the hit point relative to the copy; px, py: its plain projection (events.exact_line_hit)
        nx = p[2]
        ny = p[3]
        x0, y0 = start(F)
        x = x0 - sx
        y = y0 - sy
        a = (x - p[0]) * nx
        b = (y - p[1]) * ny
        ha = (hx - p[0]) * nx
        hb = (hy - p[1]) * ny
        cancelled = not deflated and abs(a) + abs(b) > LINE_GATE * abs(a + b)
        if not cancelled and abs(ha) + abs(hb) <= LINE_GATE * max(abs(hx), abs(hy)):
            return t, px, py, vxi, vyi
        if cancelled:
            t2 = line_exit(F, line_value_exact(kind, p, x, y), nx, ny)
            if t2 < INF:
                t = t2
                qx, qy, vxi, vyi = state_at(F, t)
                hx = qx - sx
                hy = qy - sy
        d = line_value_exact(kind, p, hx, hy)
        return t, hx - d * nx, hy - d * ny, vxi, vyi

    return hit_in_cell, walk_hit, exact_line_hit

"""The event search of a flight, written once: the earliest hit in a cell, the cell walk, a long wall.

A *flight* is a module (or a :class:`FlightProtocol`, closures over the flight's constants) that
answers a few questions about the path from one collision to the next, each a small kernel taking the
flight's state ``F`` (a tuple the flight builds; it is never inspected here).  The cell search
(:func:`cell_search`) asks:

=================================================  ==========================================================
``start(F)``                                        ``(x, y)`` at ``t = 0``
``at_start(F)``                                     the flight as ``element_exit`` takes it from ``t = 0``
``window(F, lo)``                                   the flight as ``element_exit`` takes it for a window
                                                    opening at ``lo`` (formed once per cell), of
                                                    ``at_start``'s type
``window_box(F, G, lo, hi, extent_tol)``            ``(bounded, x0, y0, x1, y1)``: a box the path cannot
                                                    leave over ``(lo, hi]`` (copies outside it are skipped),
                                                    or ``bounded`` false for no filter
``shift(A, o1, o2, shifted)``                       the copy's translation ``S``, ``S[:2]`` its plain value
``element_exit(kind, p, G, S, deflate, lo, hi,      the first exit root in ``(lo, hi]`` through the element
extent_tol)``                                       copy shifted by ``S``, within its extent; ``inf`` for
                                                    none, a negative time when the search gave up
``INLINE``, ``GIVES_UP``                            constants: inline the search at its call sites; may
                                                    ``element_exit`` give up
=================================================  ==========================================================

The closed-form flights' walk and long-wall hit (:func:`event_search`) ask three more:

=================================================  ==========================================================
``state_at(F, t)``                                  ``(x, y, vx, vy)`` at time ``t``
``face_exit(F, f0, nx, ny, t_in)``                  the first time ``>= t_in`` at which ``f0 + n . (q(t) - q(0))``
                                                    (positive inside) leaves; ``t_in`` when on or past it and
                                                    moving out
``line_exit(F, f0, nx, ny)``                        the first exit root in ``(0, inf)`` of that function
=================================================  ==========================================================

A closed path (the magnetic field's) gives ``path_box(F)``, ``(x0, y0, x1, y1)``, a box it stays in, for the
search over the cells it covers (:func:`box_search`).

Free flight (:mod:`free_flight`, and :mod:`far_flight` for cells far from the start), the
thermostat (:mod:`thermo_flight`) and the magnetic field (:mod:`magnetic_flight`) are such flights.
Free flight keeps its own tuned cell walks (:mod:`cells`: an incremental grid walk without force,
faces from one quadratic each with it) and long-wall hit (:func:`events.exact_line_hit`); each
cell's copies it searches with :func:`cell_search` (docs/extending.md, "A flight").
"""
import functools
import math
import types

import numpy as np

from .events import starts_at_open_end
from .geometry import LINE_GATE, element_box, lattice_coordinates, line_value_exact
from .jit import inlined, jit
from .layout import ARC, END_END, END_START, SEGMENT

INF = math.inf
#: The element :func:`event_search`'s cell search returns when a search in it gave up (a negative time).
SEARCH_FAILED = -2
#: The time returned with :data:`SEARCH_FAILED`.
GAVE_UP = -1.0


class FlightProtocol(types.SimpleNamespace):
    """A flight's protocol as an object rather than a module: closures over the flight's compile-time constants.

    Equal only to itself (and hashed so), as a module is: :func:`cell_search` builds once per flight.
    """

    __eq__ = object.__eq__
    __hash__ = object.__hash__


@jit(inline="always")
def leading_point(F):
    """``start`` for a flight whose state opens with ``(x, y)``."""
    return F[0], F[1]


@jit(inline="always")
def same_flight(F):
    """``at_start`` for a flight that ``element_exit`` takes from ``t = 0`` as it is."""
    return F


@jit(inline="always")
def reach_box(xi, yi, speed, span, extent_tol):
    """The box a path from ``(xi, yi)`` at most ``speed`` fast cannot leave in ``span`` (a flight's ``window_box``)."""
    reach = speed * span * (1.0 + 1e-9) + extent_tol
    return xi - reach, yi - reach, xi + reach, yi + reach


@jit(inline="always")
def box_missed(kind, p, S, bx0, by0, bx1, by1):
    """True if the element copy shifted by ``S`` lies outside the box (it cannot be hit in the window)."""
    ex0, ey0, ex1, ey1 = element_box(kind, p)
    return ex0 + S[0] > bx1 or ex1 + S[0] < bx0 or ey0 + S[1] > by1 or ey1 + S[1] < by0


@jit(inline="always")
def open_end_start(kind, p, t, best_t, x, y, extent_tol):
    """True if a hit at ``t`` (the earliest so far) is the exact root ``t = 0`` at an open end the flight starts at.

    Such a segment or arc is deflated (:func:`hit_in_cell`'s rule).  Tested only for a copy that would be
    the earliest hit, with an open end, so closed convex tables pay two comparisons and change no bit.
    """
    return (0.0 <= t <= best_t and t < INF and (kind == SEGMENT or kind == ARC)
            and (p[END_START] < 1.0 or p[END_END] < 1.0)
            and starts_at_open_end(kind, p, x, y, extent_tol))


@functools.cache
def cell_search(flight, compile=jit, open_ends=True):
    """The earliest hit over a cell's element copies for the flight module ``flight`` (built once per flight).

    ``hit_in_cell(kinds, params, copies, A, d1, d2, F, cur_e, cur_o1, cur_o2, hi, extent_tol, t_in, shifted,
    ceiling=inf)``: the earliest hit in ``(t_in, hi]`` (the copy just hit, ``(cur_e, cur_o1, cur_o2)`` in
    absolute offsets, from ``t = 0`` with its root there deflated) over the copies ``copies[k] = (element,
    o1, o2)`` (element translated by ``o1 a1 + o2 a2``, the columns of ``A``, relative to cell ``(d1, d2)``;
    a plain scene lists each element once and passes ``shifted=False``).  A bounded lattice (a Galton
    board's top row) passes ``ceiling``, the top relative to the start's cell: a copy (every element a
    circle) whose centre lies above it does not exist.  A segment or arc whose open end (reflex junction
    or free end) the flight starts at is deflated too (:func:`open_end_start`): its root ``t = 0`` is
    exact and no collision; kept, it would be a hit a rounding-sized time later and reverse the
    particle (docs/algorithm.md, step 4).  Ties go to the earlier copy.  Returns ``(t, element, o1,
    o2)``, ``(inf, -1, 0, 0)``, or ``(GAVE_UP, SEARCH_FAILED, 0, 0)`` when a flight's search gave up.

    ``compile``: how it is compiled (:func:`jit.jit`, inlined where the flight says ``INLINE``; the
    identity gives its Python source).  ``open_ends=False`` compiles the open-end rule out: a table whose
    segments and arcs all meet at convex junctions (``KernelTable.open_ends``) never needs it.
    """
    if compile is jit:
        compile = inlined(flight.INLINE)
    return _hit_in_cell(flight.start, flight.at_start, flight.window, flight.window_box, flight.shift,
                        flight.element_exit, flight.GIVES_UP, bool(open_ends), compile)


def _hit_in_cell(start, at_start, window, window_box, shift, element_exit, gives_up, OPEN_ENDS, compile):
    """:func:`cell_search`'s kernel over one flight's functions."""
    @compile
    def hit_in_cell(kinds, params, copies, A, d1, d2, F, cur_e, cur_o1, cur_o2, hi, extent_tol, t_in, shifted,
                    ceiling=INF):
        x0, y0 = start(F)
        G0 = at_start(F)
        G = window(F, t_in)  # the flight where the window opens: once per cell, not per copy
        bounded, bx0, by0, bx1, by1 = window_box(F, G, t_in, hi, extent_tol)
        best_t = hi
        best_e = -1
        best_o1 = 0
        best_o2 = 0
        for k in range(copies.shape[0]):
            e = copies[k, 0]
            o1 = copies[k, 1] + d1
            o2 = copies[k, 2] + d2
            S = shift(A, o1, o2, shifted)
            if params[e, 1] + S[1] > ceiling:  # above a bounded lattice's top: no such copy (circles: cy)
                continue
            if e == cur_e and o1 == cur_o1 and o2 == cur_o2:
                t = element_exit(kinds[e], params[e], G0, S, True, 0.0, best_t, extent_tol)
            else:
                if bounded and box_missed(kinds[e], params[e], S, bx0, by0, bx1, by1):
                    continue
                t = element_exit(kinds[e], params[e], G, S, False, t_in, best_t, extent_tol)
                if OPEN_ENDS and open_end_start(kinds[e], params[e], t, best_t, x0 - S[0], y0 - S[1], extent_tol):
                    t = element_exit(kinds[e], params[e], G0, S, True, 0.0, best_t, extent_tol)
            if gives_up and t < 0.0:  # a search gave up: the earliest hit is unknown
                return GAVE_UP, SEARCH_FAILED, 0, 0
            if t < best_t or (best_e < 0 and t == best_t and t < INF):
                best_t = t
                best_e = e
                best_o1 = o1
                best_o2 = o2
        if best_e < 0:
            return INF, -1, 0, 0
        return best_t, best_e, best_o1, best_o2

    return hit_in_cell


@functools.cache
def event_search(flight, compile=jit, open_ends=True):
    """``(hit_in_cell, walk_hit, exact_line_hit)`` for the closed-form flight module ``flight`` (built once).

    ``hit_in_cell``: :func:`cell_search`'s (``open_ends`` as there).

    ``walk_hit(kinds, params, copies, A, B, F, cur_e, cur_o1, cur_o2, t_limit, extent_tol, max_cells,
    ceiling=inf)``: the earliest hit in a periodic scene (``ceiling``: a bounded lattice's top, as for
    ``hit_in_cell``); ``(t, element, o1, o2, status)``, status 0 hit, 1 past ``t_limit``, 2 past ``max_cells``
    cells, 3 a search gave up.

    ``exact_line_hit(kind, p, F, sx, sy, deflated, t, hx, hy, px, py, vx, vy)``: a hit far along a long wall
    redone from the exact distances (:func:`events.exact_line_hit`); ``(t, px, py, vx, vy)``.

    ``compile``: how each is compiled (:func:`jit.jit`; the identity gives their Python source, calling
    the flight's functions as they are, for tests that patch a flight's constants).
    """
    hit_in_cell = cell_search(flight, compile, open_ends)
    strip_exit = _strip_exit(flight.face_exit, compile)
    return hit_in_cell, _walk_hit(flight.start, hit_in_cell, strip_exit, compile), long_wall_hit(flight, compile)


def _strip_exit(face_exit, compile):
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

    return strip_exit


def _walk_hit(start, hit_in_cell, strip_exit, compile):
    # inlined into the event loop: out of line, its array arguments are copied each collision (cells.lattice_walk)
    @(inlined(True) if compile is jit else compile)
    def walk_hit(kinds, params, copies, A, B, F, cur_e, cur_o1, cur_o2, t_limit, extent_tol, max_cells,
                 ceiling=INF):
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
                                       extent_tol, t_in, True, ceiling)
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

    return walk_hit


#: Most element copies (cells the box covers times copies per cell) :func:`box_search` searches rather than
#: walk: below where the two cost the same, about 20, on Sinai tori of one and five copies a cell
#: (benchmarks/RESULTS.md).
BOX_COPIES = 16


@functools.cache
def box_search(flight, compile=jit, open_ends=True):
    """``box_hit(kinds, params, copies, A, B, F, cur_e, cur_o1, cur_o2, t_limit, extent_tol, ceiling=inf)`` for a
    flight whose path is closed: the earliest hit over every cell its box covers, without a walk (``ceiling`` as
    for ``hit_in_cell``).

    ``flight.path_box(F)``: ``(x0, y0, x1, y1)``, a box the whole path stays in (infinite: none).  A closed path
    meets each copy at one exit root per period, so the earliest over the copies of the cells it covers, each
    solved from ``t = 0`` with no window to re-base, is the walk's hit; it spares the walk's face exits, which
    cost a closed form of their own per cell.  ``(t, element, o1, o2, status)``: status 0 hit, 1 none by
    ``t_limit``, 2 a box over more than :data:`BOX_COPIES` copies (nothing searched: walk), 3 a search gave up.
    """
    return _box_hit(flight.path_box, cell_search(flight, compile, open_ends), compile)


@jit(inline="always")
def _cell_range(b1, b2, x0, y0, x1, y1, margin):
    """``(lo, n)``: the first of the ``n`` cells along the lattice coordinate ``b . q`` that the box reaches."""
    lo = b1 * (x0 if b1 > 0.0 else x1) + b2 * (y0 if b2 > 0.0 else y1) - margin
    hi = b1 * (x1 if b1 > 0.0 else x0) + b2 * (y1 if b2 > 0.0 else y0) + margin
    first = np.floor(lo + 0.5)  # a float: an infinite or NaN box is no integer
    return first, np.floor(hi + 0.5) - first + 1.0


def _box_hit(path_box, hit_in_cell, compile):
    @(inlined(True) if compile is jit else compile)
    def box_hit(kinds, params, copies, A, B, F, cur_e, cur_o1, cur_o2, t_limit, extent_tol, ceiling=INF):
        x0, y0, x1, y1 = path_box(F)
        lo1, n1 = _cell_range(B[0, 0], B[0, 1], x0, y0, x1, y1, extent_tol * (abs(B[0, 0]) + abs(B[0, 1])))
        lo2, n2 = _cell_range(B[1, 0], B[1, 1], x0, y0, x1, y1, extent_tol * (abs(B[1, 0]) + abs(B[1, 1])))
        if not n1 * n2 * copies.shape[0] <= BOX_COPIES:  # a large or unbounded box (NaN too): walk
            return INF, -1, 0, 0, 2
        best_t = t_limit
        best_e = -1
        best_o1 = 0
        best_o2 = 0
        for i in range(int(n1)):
            for j in range(int(n2)):
                t, e, o1, o2 = hit_in_cell(kinds, params, copies, A, int(lo1) + i, int(lo2) + j, F, cur_e, cur_o1,
                                           cur_o2, best_t, extent_tol, 0.0, True, ceiling)
                if e == SEARCH_FAILED:
                    return GAVE_UP, SEARCH_FAILED, 0, 0, 3
                if e >= 0 and (best_e < 0 or t < best_t):
                    best_t = t
                    best_e = e
                    best_o1 = o1
                    best_o2 = o2
        if best_e < 0:
            return INF, -1, 0, 0, 1
        return best_t, best_e, best_o1, best_o2, 0

    return box_hit


@functools.cache
def long_wall_hit(flight, compile=jit):
    """:func:`event_search`'s ``exact_line_hit`` for ``flight``: the cell search's ``open_ends`` does not touch it,
    so one serves every variant."""
    return _exact_line_hit(flight.start, flight.state_at, flight.line_exit, compile)


def _exact_line_hit(start, state_at, line_exit, compile):
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

    return exact_line_hit

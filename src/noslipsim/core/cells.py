"""Periodic lattices: walk the cells a flight crosses until a hit comes before the exit.

Cell ``(d1, d2)`` is the parallelogram ``{alpha a1 + beta a2 : |alpha - d1|, |beta - d2| <= 1/2}``
(centred cells: an obstacle at the origin lies inside cell 0).  Positions are
kept relative to the particle's current cell, so their precision is that of the
cell size however far an orbit diffuses.  For each cell the walk tests only the
element copies that reach it (precomputed, ``copies``) with the time window
capped at the cell's exit time; a hit found there is the earliest, because any
earlier hit lies in an earlier cell, where the same copy was tested.  Infinite
horizon corridors cost one cell per step and miss nothing.

Without a force the lattice coordinates are linear in time, and the walk is
an incremental grid traversal (Amanatides & Woo 1987): each face time comes
from the flight's start in one division, with no square root and no error
that grows with the cells walked.  The search windows of successive cells
share their end points, so no time is left out whatever the rounding of the
face times.
"""
import functools
import math

from . import far_flight, free_flight
from .exact import lattice_shift_dd, two_prod, two_sum
from .far_flight import flight_point_dd, minus_shift_dd
from .geometry import crossing_coefficients, lattice_coordinates, line_value, nearest_cell
from .jit import jit
from .layout import LINE, SEGMENT
from .roots import quadratic_exit, quadratic_roots
from .search import cell_search

INF = math.inf

#: The walk tests the copies of a cell this many cells (or more) from the flight's start on the
#: flight re-centred exactly (:func:`far_hit_in_cell`), and a straight flight's hit found there is
#: relocated by :func:`far_hit_point`; nearer cells and hits keep the plain evaluation, bit for bit.
#: Under a force the walk reports a hit found after it got this far with the escape's status (2)
#: and a finite time; the event loop leaves its collision loop as for an escape and, in its block
#: loop, moves the flight's start exactly to within :data:`NEAR_CELLS` of the hit (:func:`far_move`),
#: from where the walk finds the hit near.  Nothing of it is in the collision loop: a call there,
#: even never taken, cost the Galton board 30 %, a branch of its own 15-20 % (benchmarks/RESULTS.md).
FAR_CELLS = 16
#: :func:`far_move` puts a flight's start this many lattice units before its far hit (in each lattice
#: coordinate, at most): the walk then finds the hit in the start's cell or the next, from a start
#: formed at the scale of the hit point's coordinates in that cell, and the hit is as precise as a
#: near one (tests/test_far_force.py: velocity within 0.019 of its conditioning tolerance at 0.05,
#: 0.07 at 0.2, 0.64 at 1: the start's rounding grows with its coordinates, the plain flight with
#: its length).
NEAR_CELLS = 0.05


@jit
def _boundary_exit(g, rate, curv):
    """Time until ``g(tau) = g + rate tau + curv tau^2`` (positive inside) leaves, from ``tau = 0``.

    On or past the boundary and moving out: 0 (leave at once).
    """
    if g <= 0.0 and (rate < 0.0 or (rate == 0.0 and curv < 0.0)):
        return 0.0
    return quadratic_exit(g, rate, curv, INF)


@jit
def _strip_exit(alpha0, alpha1, alpha2, lo, hi, t_in):
    """First time ``>= t_in`` at which ``alpha(t) = alpha0 + alpha1 t + alpha2 t^2`` leaves ``[lo, hi]``.

    The polynomial is re-centred at ``t_in``.  Returns ``(t, step)`` with
    ``step = +1`` through ``hi``, ``-1`` through ``lo``, or ``(inf, 0)``.
    The side ``alpha`` moves towards (or, at rest, curves towards) is solved
    first: a finite exit there comes before any exit through the other side,
    which needs the motion to turn back, so one square root usually suffices.
    """
    al = alpha0 + t_in * (alpha1 + alpha2 * t_in)
    rate = alpha1 + 2.0 * alpha2 * t_in
    up = rate > 0.0 or (rate == 0.0 and alpha2 > 0.0)
    if up:
        t_up = _boundary_exit(hi - al, -rate, -alpha2)
        if t_up < INF:
            return t_in + t_up, 1
    t_dn = _boundary_exit(al - lo, rate, alpha2)
    if t_dn < INF:
        return t_in + t_dn, -1
    if not up:
        t_up = _boundary_exit(hi - al, -rate, -alpha2)
        if t_up < INF:
            return t_in + t_up, 1
    return INF, 0


@jit(inline="always")
def _face_time(alpha0, alpha1, face, t_in):
    """Time at which ``alpha0 + alpha1 t`` reaches ``face`` (``alpha1 != 0``), not before ``t_in``."""
    return max((face - alpha0) / alpha1, t_in)


@jit(inline="always")
def _straight_start(alpha0, alpha1, d, t_in):
    """``(t, step)``: when and which way a straight flight from ``t_in`` leaves the strip of cell index ``d``."""
    step = 1 if alpha1 > 0.0 else -1
    return (_face_time(alpha0, alpha1, d + 0.5 * step, t_in) if alpha1 != 0.0 else INF), step


@jit(inline="always")
def _straight_next(alpha0, alpha1, d, step, t_out):
    """A straight flight's next face time, in the strip ``d`` it entered at ``t_out``."""
    return _face_time(alpha0, alpha1, d + 0.5 * step, t_out)


@jit(inline="always")
def _straight_exits(a0, a1, a2, b0, b1, b2, d1, d2, t_in, ta, sa, tb, sb):
    """A straight flight's cell exits: the face times already stepped (:func:`_straight_next`)."""
    return ta, sa, tb, sb


@jit(inline="always")
def _straight_flight(x, y, vx, vy, ax, ay):
    """The cell search's flight without force (the zero acceleration compiled in)."""
    return x, y, vx, vy, 0.0, 0.0


@jit(inline="always")
def _force_start(alpha0, alpha1, d, t_in):
    """Under a force each cell solves its exits (:func:`_force_exits`): nothing before."""
    return INF, 0


@jit(inline="always")
def _force_next(alpha0, alpha1, d, step, t_out):
    """Under a force the next cell's exits are solved there (:func:`_force_exits`)."""
    return t_out


@jit(inline="always")
def _force_exits(a0, a1, a2, b0, b1, b2, d1, d2, t_in, ta, sa, tb, sb):
    """``(ta, sa, tb, sb)``: when and which way the flight under a force leaves cell ``(d1, d2)``."""
    ta, sa = _strip_exit(a0, a1, a2, d1 - 0.5, d1 + 0.5, t_in)
    tb, sb = _strip_exit(b0, b1, b2, d2 - 0.5, d2 + 0.5, t_in)
    return ta, sa, tb, sb


@jit(inline="always")
def _force_flight(x, y, vx, vy, ax, ay):
    """The cell search's flight under a force."""
    return x, y, vx, vy, ax, ay


def _by_distance(hit_in_cell, far_hit_in_cell):
    """A cell search by :func:`far_hit_in_cell` from ``FAR_CELLS`` cells on, by ``hit_in_cell`` nearer."""
    @jit(inline="always")
    def search(kinds, params, copies, A, d1, d2, F, cur_e, cur_o1, cur_o2, hi, extent_tol, t_in, shifted, ceiling):
        """``hit_in_cell``'s call, by the search that fits the cell's distance from the start."""
        if max(abs(d1), abs(d2)) < FAR_CELLS:
            return hit_in_cell(kinds, params, copies, A, d1, d2, F, cur_e, cur_o1, cur_o2, hi, extent_tol, t_in,
                               shifted, ceiling)
        return far_hit_in_cell(kinds, params, copies, A, d1, d2, F, cur_e, cur_o1, cur_o2, hi, extent_tol, t_in,
                               shifted, ceiling)

    return search


def _cell_walk(force, search, hand_on=None, inline=False):
    """A walk over the cells a flight crosses, from cell ``(d1, d2)`` at ``t_in``, each cell by ``search``.

    ``force``: the flight's exits solved per cell (:func:`_strip_exit`), else stepped face by face
    (:func:`_face_time`).  With ``hand_on`` (a near walk) the walk stops at ``FAR_CELLS`` cells from the
    start and hands on to ``hand_on`` with the same arguments; without, it walks on to ``max_cells``.
    A far walk under a force reports a hit with status 2 (:func:`lattice_walk`).  ``inline``: inlined
    into its caller.
    """
    start = _force_start if force else _straight_start
    exits = _force_exits if force else _straight_exits
    next_face = _force_next if force else _straight_next
    flight = _force_flight if force else _straight_flight
    NEAR = hand_on is not None
    HIT = 2 if force and not NEAR else 0
    compile = functools.partial(jit, inline="always") if inline else jit

    @compile
    def walk(kinds, params, copies, A, a0, a1, a2, b0, b1, b2, x, y, vx, vy, ax, ay, cur_e, cur_o1, cur_o2,
             t_limit, extent_tol, max_cells, ceiling, d1, d2, t_in):
        """``walk_hit``'s walk from cell ``(d1, d2)`` at ``t_in``; ``alpha(t) = a0 + a1 t + a2 t^2`` (and
        ``beta``) the flight's lattice coordinates.  A tie of the exits steps both indices (a lattice point)."""
        ta, sa = start(a0, a1, d1, t_in)
        tb, sb = start(b0, b1, d2, t_in)
        F = flight(x, y, vx, vy, ax, ay)
        k = 0
        while k < max_cells:
            # a long flight goes on out of line: a call in this loop cost the walk a third (Galton board)
            if NEAR and max(abs(d1), abs(d2)) >= FAR_CELLS:
                break
            k += 1
            ta, sa, tb, sb = exits(a0, a1, a2, b0, b1, b2, d1, d2, t_in, ta, sa, tb, sb)
            t_out = min(ta, tb)
            t, e, o1, o2 = search(kinds, params, copies, A, d1, d2, F, cur_e, cur_o1, cur_o2, t_out, extent_tol,
                                  t_in, True, ceiling)
            if e >= 0:
                return t, e, o1, o2, HIT
            if t_out >= t_limit:
                return INF, -1, 0, 0, 1
            if ta == t_out:
                d1 += sa
                ta = next_face(a0, a1, d1, sa, t_out)
            if tb == t_out:
                d2 += sb
                tb = next_face(b0, b1, d2, sb, t_out)
            t_in = t_out
        if NEAR and k < max_cells:
            return hand_on(kinds, params, copies, A, a0, a1, a2, b0, b1, b2, x, y, vx, vy, ax, ay, cur_e, cur_o1,
                           cur_o2, t_limit, extent_tol, max_cells - k, ceiling, d1, d2, t_in)
        return INF, -1, 0, 0, 2

    return walk


def _walk(straight, force):
    """:func:`lattice_walk`'s ``walk_hit`` over its walks without and with force."""
    @jit
    def walk_hit(kinds, params, copies, A, B, x, y, vx, vy, ax, ay, has_force,
                 cur_e, cur_o1, cur_o2, t_limit, extent_tol, max_cells, ceiling=INF):
        """:func:`lattice_walk`'s walk (its docstring)."""
        # lattice coordinates along the flight: alpha(t) = B[0].q(t), beta(t) = B[1].q(t)
        a0, b0 = lattice_coordinates(B, x, y)
        a1, b1 = lattice_coordinates(B, vx, vy)
        if not has_force:
            return straight(kinds, params, copies, A, a0, a1, 0.0, b0, b1, 0.0, x, y, vx, vy, 0.0, 0.0,
                            cur_e, cur_o1, cur_o2, t_limit, extent_tol, max_cells, ceiling, 0, 0, 0.0)
        a2, b2 = lattice_coordinates(B, ax, ay)
        return force(kinds, params, copies, A, a0, a1, 0.5 * a2, b0, b1, 0.5 * b2, x, y, vx, vy, ax, ay,
                     cur_e, cur_o1, cur_o2, t_limit, extent_tol, max_cells, ceiling, 0, 0, 0.0)

    return walk_hit


@functools.cache
def lattice_walk(open_ends=True):
    """``walk_hit(kinds, params, copies, A, B, x, y, vx, vy, ax, ay, has_force, cur_e, cur_o1, cur_o2, t_limit,
    extent_tol, max_cells, ceiling=inf)``: free flight's earliest hit in a periodic scene.

    Returns ``(t, element, o1, o2, status)``: ``status`` 0 for a hit, 1 when the
    walk passed ``t_limit`` without a hit, 2 when it crossed ``max_cells`` cells
    without a hit (an endless free flight, reported as an escape).  Cells ``FAR_CELLS``
    or more from the start are searched on the flight re-centred exactly there
    (:mod:`far_flight`, out of line); the event loop forms such a hit's point
    exactly for a straight flight (:func:`far_hit_point`).  Under a force
    (``has_force``) a hit found after the walk got that far is returned with
    status 2, as an escape but with its finite time ``t``: the event loop
    moves the flight's start near it (:func:`far_move`) and walks again.
    ``ceiling``: the top of a bounded lattice relative to cell 0 (copies whose
    centre lies above it are skipped, :func:`search.cell_search`); ``inf`` for none.
    ``open_ends``: the open-end rule compiled in (:func:`search.cell_search`).
    """
    near_falling = cell_search(free_flight.falling, open_ends=open_ends)
    far_falling = cell_search(far_flight.falling, open_ends=open_ends)
    # a straight flight's indices never turn back: its far walk searches every cell far
    straight = _cell_walk(False, cell_search(free_flight.straight, open_ends=open_ends),
                          hand_on=_cell_walk(False, cell_search(far_flight.straight, open_ends=open_ends)))
    force = _cell_walk(True, near_falling, hand_on=_cell_walk(True, _by_distance(near_falling, far_falling)),
                       inline=True)
    return _walk(straight, force)


#: Free flight's lattice walk, the open-end rule compiled in.
walk_hit = lattice_walk()



@jit
def far_hit_point(kind, p, A, o1, o2, x, y, vx, vy, t):
    """Hit point of a long straight flight relative to the copy ``(o1, o2)`` it hit, to a few ulps of the element.

    ``q + v t - (o1 a1 + o2 a2)`` formed plainly carries ``eps`` times the
    flight's length.  Here it is formed to twice the working precision
    (:mod:`exact`) for the float ``t``; ``t`` itself carries ``eps t``, a
    step along the flight, which is removed by moving the point along ``v``
    to the element's exit root nearest to it (a root of a polynomial formed
    at the element's scale).  The result lies on the element's line or
    circle to rounding, wherever the flight started.
    """
    sxh, sxl, syh, syl = lattice_shift_dd(A, o1, o2)
    px, pe = two_prod(vx, t)
    s1, e1 = two_sum(px, -sxh)
    s2, e2 = two_sum(s1, x)
    rx = s2 + (((e2 + e1) + pe) - sxl)
    py, qe = two_prod(vy, t)
    s1, e1 = two_sum(py, -syh)
    s2, e2 = two_sum(s1, y)
    ry = s2 + (((e2 + e1) + qe) - syl)
    if kind == LINE or kind == SEGMENT:
        rate = vx * p[2] + vy * p[3]
        step = -line_value(kind, p, rx, ry) / rate if rate != 0.0 else 0.0
    else:
        c0, c1, c2 = crossing_coefficients(kind, p, rx, ry, vx, vy, 0.0, 0.0)[:3]
        n, r1, r2 = quadratic_roots(c0, c1, c2)
        step = 0.0
        if n == 2:
            step = r1 if c2 > 0.0 else r2  # the exit root, as in roots.quadratic_exit
    return rx + vx * step, ry + vy * step


@jit(inline="always")  # out of line, called around the collision loop, it cost the Galton board (specular) 10-15 %
def far_move(A, B, x, y, vx, vy, ax, ay, t_hit, t_max):
    """Move a flight under a force exactly to shortly before its far hit, re-based onto the cell reached.

    The flight ``q(t) = (x, y) + v t + a t^2/2`` (relative to its start cell) hits an
    element copy far away at ``t_hit``.  Its start moves to ``t_move = t_hit - delta``,
    ``delta`` the positive root of ``|a| delta^2 / 2 + |u| delta = L``, where ``u = v + a t_hit``
    is the velocity at the hit and ``L = NEAR_CELLS / max(|b1|, |b2|)`` (``b1, b2`` the rows
    of ``B = A^-1``).  Since ``q(t_hit - s) - q(t_hit) = -u s + a s^2/2``, the flight after
    ``t_move`` lies within ``L`` of the hit point, hence within ``NEAR_CELLS`` of it in each
    lattice coordinate.  Before ``t_hit`` the flight is in free space (``t_hit`` is its
    first hit), so the moved start is a start of the same flight, which meets the same
    copy ``delta`` later.  ``t_move`` is at most ``t_max`` (the time left before
    ``max_time``: the orbit then stops there).

    The point is formed to twice the working precision (:func:`flight_point_dd`) and seen
    from the cell ``(k1, k2)`` that holds it through the translation formed exactly
    (:func:`exact.lattice_shift_dd`): it carries a few ulps of the cell's size, not ``eps``
    times the flight's length.  The velocity is ``v + a t_move``, to a few ulps of itself.

    Returns ``(t_move, k1, k2, x, y, vx, vy)``, the new position relative to cell ``(k1, k2)``
    of the old frame.
    """
    ux = vx + ax * t_hit
    uy = vy + ay * t_hit
    u = math.sqrt(ux * ux + uy * uy)
    acc = math.sqrt(ax * ax + ay * ay)
    reach = NEAR_CELLS / max(math.sqrt(B[0, 0] * B[0, 0] + B[0, 1] * B[0, 1]),
                             math.sqrt(B[1, 0] * B[1, 0] + B[1, 1] * B[1, 1]))
    delta = 2.0 * reach / (u + math.sqrt(u * u + 2.0 * acc * reach))
    # delta < t_hit, as the walk got FAR_CELLS from the start; a half step keeps any rounding from stalling
    t_move = min(t_hit - delta if delta < t_hit else 0.5 * t_hit, t_max)
    xh, xl = flight_point_dd(x, vx, ax, t_move, True)
    yh, yl = flight_point_dd(y, vy, ay, t_move, True)
    k1, k2 = nearest_cell(B, xh, yh)
    sxh, sxl, syh, syl = lattice_shift_dd(A, k1, k2)
    px = minus_shift_dd(xh, xl, sxh, sxl)
    py = minus_shift_dd(yh, yl, syh, syl)
    j1, j2 = nearest_cell(B, px, py)
    if j1 != 0 or j2 != 0:  # the rounded point lay within rounding of a face: the exact one's cell
        k1 += j1
        k2 += j2
        sxh, sxl, syh, syl = lattice_shift_dd(A, k1, k2)
        px = minus_shift_dd(xh, xl, sxh, sxl)
        py = minus_shift_dd(yh, yl, syh, syl)
    return t_move, k1, k2, px, py, vx + ax * t_move, vy + ay * t_move

"""Periodic lattices: walk the cells a flight crosses until a hit comes before the exit.

Cell ``(d1, d2)`` is the parallelogram ``{alpha a1 + beta a2 : |alpha - d1|, |beta - d2| <= 1/2}``
(centred cells: an obstacle at the origin lies inside cell 0).  Positions are kept relative to
the particle's current cell, so their precision is that of the cell size however far an orbit
diffuses.  Each cell tests only the element copies that reach it (``copies``), its window capped
at the cell's exit: a hit found there is the earliest, as any earlier hit lies in an earlier cell,
where the same copy was tested; infinite-horizon corridors cost one cell per step.  Without a
force the walk is an incremental grid traversal (Amanatides & Woo 1987): each face time from the
flight's start, in one division.  Successive windows share their end points, so no time is left
out.  Cells ``FAR_CELLS`` or more from the start are searched on the flight re-centred exactly
there (docs/algorithm.md, *Lattices*).
"""
import functools
import math

from . import far_flight, free_flight
from .exact import lattice_shift_dd, two_prod, two_sum
from .far_flight import flight_point_dd, minus_shift_dd
from .geometry import crossing_coefficients, lattice_coordinates, line_value, nearest_cell
from .jit import inlined, jit
from .layout import LINE, SEGMENT
from .roots import quadratic_exit, quadratic_roots
from .search import cell_search

INF = math.inf

#: The walk tests the copies of a cell this many cells (or more) from the flight's start on the
#: flight re-centred exactly (:mod:`far_flight`), and a straight flight's hit found there is
#: relocated by :func:`far_hit_point`; nearer cells and hits keep the plain evaluation, bit for bit.
#: Under a force such a hit is reported with the escape's status (2) and its finite time, and the
#: event loop moves the flight's start to within :data:`NEAR_CELLS` of it (:func:`far_move`), out of
#: the collision loop (measured: benchmarks/RESULTS.md).
FAR_CELLS = 16
#: :func:`far_move` puts a flight's start this many lattice units (at most, in each coordinate) before
#: its far hit: the walk then finds the hit in the start's cell or the next, as precise as a near hit
#: (the precision against this choice: docs/algorithm.md, *Lattices*; tests/test_far_force.py).
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

    Returns ``(t, step)``: ``step = +1`` through ``hi``, ``-1`` through ``lo``, or ``(inf, 0)``.
    The side ``alpha`` moves (or, at rest, curves) towards is solved first: its finite exit
    comes first, so one square root usually suffices.
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


def _by_distance(hit_in_cell, far_hit_in_cell):
    """A cell search by ``far_hit_in_cell`` from ``FAR_CELLS`` cells on, by ``hit_in_cell`` nearer (a flight under
    a force may turn back)."""
    @jit(inline="always")
    def search(kinds, params, copies, A, d1, d2, F, cur_e, cur_o1, cur_o2, hi, extent_tol, t_in, shifted, ceiling):
        """``hit_in_cell``'s call, by the search that fits the cell's distance from the start."""
        if max(abs(d1), abs(d2)) < FAR_CELLS:
            return hit_in_cell(kinds, params, copies, A, d1, d2, F, cur_e, cur_o1, cur_o2, hi, extent_tol, t_in,
                               shifted, ceiling)
        return far_hit_in_cell(kinds, params, copies, A, d1, d2, F, cur_e, cur_o1, cur_o2, hi, extent_tol, t_in,
                               shifted, ceiling)

    return search


def _force_walk(search, hand_on=None):
    """The walk of :func:`lattice_walk` under a force from cell ``(d1, d2)`` at ``t_in``, each cell by ``search``.

    With ``hand_on`` (the near walk, inlined into ``walk_hit``) it stops ``FAR_CELLS`` cells from
    the start and hands on to ``hand_on`` with the same arguments; without (the far walk, out of line)
    it walks on to ``max_cells`` and reports a hit with status 2 (:func:`lattice_walk`).
    """
    NEAR = hand_on is not None

    @inlined(NEAR)
    def walk(kinds, params, copies, A, a0, a1, a2, b0, b1, b2, x, y, vx, vy, ax, ay, cur_e, cur_o1, cur_o2,
             t_limit, extent_tol, max_cells, ceiling, d1, d2, t_in):
        """The walk; ``alpha(t) = a0 + a1 t + a2 t^2`` and ``beta(t)`` are the flight's lattice coordinates."""
        k = 0
        while k < max_cells:
            # a long flight goes on out of line: a call in this loop cost the walk a third (Galton board)
            if NEAR and max(abs(d1), abs(d2)) >= FAR_CELLS:
                break
            k += 1
            ta, sa = _strip_exit(a0, a1, a2, d1 - 0.5, d1 + 0.5, t_in)
            tb, sb = _strip_exit(b0, b1, b2, d2 - 0.5, d2 + 0.5, t_in)
            t_out = min(ta, tb)
            t, e, o1, o2 = search(kinds, params, copies, A, d1, d2, (x, y, vx, vy, ax, ay), cur_e, cur_o1, cur_o2,
                                  t_out, extent_tol, t_in, True, ceiling)
            if e >= 0:
                return t, e, o1, o2, 0 if NEAR else 2  # a far hit: status 2 (lattice_walk)
            if t_out >= t_limit:
                return INF, -1, 0, 0, 1
            if ta == t_out:
                d1 += sa
            if tb == t_out:
                d2 += sb
            t_in = t_out
        if NEAR and k < max_cells:
            return hand_on(kinds, params, copies, A, a0, a1, a2, b0, b1, b2, x, y, vx, vy, ax, ay, cur_e, cur_o1,
                           cur_o2, t_limit, extent_tol, max_cells - k, ceiling, d1, d2, t_in)
        return INF, -1, 0, 0, 2

    return walk


def _straight_walk(search, hand_on=None):
    """The walk of :func:`lattice_walk` without force from cell ``(d1, d2)`` at ``t_in``, each cell by ``search``.

    The incremental grid walk: ``alpha(t) = a0 + a1 t`` and ``beta(t) = b0 + b1 t`` are the
    flight's lattice coordinates; cell ``(d1, d2)`` is left through the face ``d1 + s1/2`` (``s1``
    the sign of ``a1``) or ``d2 + s2/2``, whichever comes first; on a tie both indices step (a
    flight through a lattice point).  ``hand_on`` as for :func:`_force_walk`.
    """
    NEAR = hand_on is not None

    @inlined(NEAR)
    def walk(kinds, params, copies, A, a0, a1, b0, b1, x, y, vx, vy, cur_e, cur_o1, cur_o2, t_limit, extent_tol,
             max_cells, ceiling, d1, d2, t_in):
        """The walk (the factory's docstring)."""
        s1 = 1 if a1 > 0.0 else -1
        s2 = 1 if b1 > 0.0 else -1
        ta = _face_time(a0, a1, d1 + 0.5 * s1, t_in) if a1 != 0.0 else INF
        tb = _face_time(b0, b1, d2 + 0.5 * s2, t_in) if b1 != 0.0 else INF
        k = 0
        while k < max_cells:
            if NEAR and max(abs(d1), abs(d2)) >= FAR_CELLS:  # a long flight goes on out of line (as _force_walk)
                break
            k += 1
            t_out = min(ta, tb)
            t, e, o1, o2 = search(kinds, params, copies, A, d1, d2, (x, y, vx, vy, 0.0, 0.0),
                                  cur_e, cur_o1, cur_o2, t_out, extent_tol, t_in, True, ceiling)
            if e >= 0:
                return t, e, o1, o2, 0
            if t_out >= t_limit:
                return INF, -1, 0, 0, 1
            if ta == t_out:
                d1 += s1
                ta = _face_time(a0, a1, d1 + 0.5 * s1, t_out)
            if tb == t_out:
                d2 += s2
                tb = _face_time(b0, b1, d2 + 0.5 * s2, t_out)
            t_in = t_out
        if NEAR and k < max_cells:  # the face times again from (d1, d2, t_in): the same values (t_in <= both)
            return hand_on(kinds, params, copies, A, a0, a1, b0, b1, x, y, vx, vy, cur_e, cur_o1, cur_o2, t_limit,
                           extent_tol, max_cells - k, ceiling, d1, d2, t_in)
        return INF, -1, 0, 0, 2

    return walk


def _walk(walk, FALLING):
    """:func:`lattice_walk`'s ``walk_hit`` over ``walk``, the walk without force or (``FALLING``) under one."""
    # inlined: out of line, each collision's call copied ~50 words of array arguments between stack slots,
    # and in some frame layouts most loads of that copy met an aliasing store (the Galton board at 0.6 of its
    # rate; docs/algorithm.md, "Paying only for what a scene needs")
    @jit(inline="always")
    def walk_hit(kinds, params, copies, A, B, x, y, vx, vy, ax, ay, cur_e, cur_o1, cur_o2, t_limit, extent_tol,
                 max_cells, ceiling=INF):
        """:func:`lattice_walk`'s walk (its docstring)."""
        # lattice coordinates along the flight: alpha(t) = B[0].q(t), beta(t) = B[1].q(t)
        a0, b0 = lattice_coordinates(B, x, y)
        a1, b1 = lattice_coordinates(B, vx, vy)
        if not FALLING:
            return walk(kinds, params, copies, A, a0, a1, b0, b1, x, y, vx, vy,
                        cur_e, cur_o1, cur_o2, t_limit, extent_tol, max_cells, ceiling, 0, 0, 0.0)
        a2, b2 = lattice_coordinates(B, ax, ay)
        return walk(kinds, params, copies, A, a0, a1, 0.5 * a2, b0, b1, 0.5 * b2, x, y, vx, vy, ax, ay,
                    cur_e, cur_o1, cur_o2, t_limit, extent_tol, max_cells, ceiling, 0, 0, 0.0)

    return walk_hit


@functools.cache
def lattice_walk(open_ends=True, falling=False):
    """``walk_hit(kinds, params, copies, A, B, x, y, vx, vy, ax, ay, cur_e, cur_o1, cur_o2, t_limit, extent_tol,
    max_cells, ceiling=inf)``: free flight's earliest hit in a periodic scene, straight or (``falling``) under
    the force ``(ax, ay)``; each compiles only its own walk.

    Returns ``(t, element, o1, o2, status)``: ``status`` 0 for a hit, 1 when the walk passed
    ``t_limit`` without a hit, 2 when it crossed ``max_cells`` cells without one (an endless
    flight, reported as an escape).  The event loop forms the point of a straight flight's hit
    ``FAR_CELLS`` or more from the start exactly (:func:`far_hit_point`); under a force such a
    hit comes with status 2 and its finite time ``t``, and the event loop moves the flight's
    start near it (:func:`far_move`) and walks again.  ``ceiling``: the top of a bounded lattice
    relative to cell 0 (:func:`search.cell_search`); ``inf`` for none.  ``open_ends``: the
    open-end rule compiled in (:func:`search.cell_search`).
    """
    if not falling:
        return _walk(_straight_walk(cell_search(free_flight.straight, open_ends=open_ends),
                                    hand_on=_straight_walk(cell_search(far_flight.straight, open_ends=open_ends))),
                     False)
    near = cell_search(free_flight.falling, open_ends=open_ends)
    far = cell_search(far_flight.falling, open_ends=open_ends)
    return _walk(_force_walk(near, hand_on=_force_walk(_by_distance(near, far))), True)


@jit
def far_hit_point(kind, p, A, o1, o2, x, y, vx, vy, t):
    """Hit point of a long straight flight relative to the copy ``(o1, o2)`` it hit, to a few ulps of the element.

    ``q + v t - (o1 a1 + o2 a2)`` is formed to twice the working precision (:mod:`exact`), then
    moved along ``v`` to the element's exit root nearest to it, which removes the rounding of
    ``t`` (plainly the point carries ``eps`` times the flight's length; docs/algorithm.md, *Lattices*).
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


@jit(inline="always")  # out of line it cost the Galton board 10-15 % (benchmarks/RESULTS.md)
def far_move(A, B, x, y, vx, vy, ax, ay, t_hit, t_max):
    """Move a flight under a force exactly to shortly before its far hit, re-based onto the cell reached.

    The flight ``q(t) = (x, y) + v t + a t^2/2`` (relative to its start cell) first hits a far
    copy at ``t_hit``; its start moves to ``t_move = min(t_hit - delta, t_max)``, ``delta`` the
    positive root of ``|a| delta^2 / 2 + |u| delta = L`` (``u = v + a t_hit``,
    ``L = NEAR_CELLS / max(|b1|, |b2|)``, ``b1, b2`` the rows of ``B = A^-1``), so the flight after
    ``t_move`` lies within ``NEAR_CELLS`` of the hit in each lattice coordinate and, in free space
    before it, meets the same copy ``delta`` later.  ``t_max``: the time left before ``max_time``.
    The point is formed to twice the working precision (:func:`flight_point_dd`) and seen from the
    cell ``(k1, k2)`` that holds it through the exact shift (:func:`exact.lattice_shift_dd`): a few
    ulps of the cell's size (docs/algorithm.md, *Lattices*).

    Returns ``(t_move, k1, k2, x, y, vx, vy)``, the new position relative to cell ``(k1, k2)`` of the
    old frame, and the velocity ``v + a t_move`` (to a few ulps of itself).
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

"""The event loop of disk scatterers on a lattice without force (Sinai torus, Lorentz gases).

Flights are straight and the disks convex and apart, so this loop drops what the general one
(:mod:`loop`) needs for other scenes: deflation, the corner rule, the grazing stop, extents.
With ``d = q - c`` and ``b = d . v`` a flight meets the disk iff ``b < 0`` and
``disc = |v|^2 r^2 - (d x v)^2 > 0`` (Lagrange's identity, ``disc = b^2 - |v|^2 (|d|^2 - r^2)``: the
cross product keeps a long flight's grazing test precise; tangent, ``disc = 0``, is no hit), at
``t = (-b - sqrt(disc)) / |v|^2`` (no cancellation), on ``h = d + v t`` from the centre.  ``h`` lies
on the circle to rounding, so ``1/|h|^2`` and ``h/|h|`` are one Newton step from ``1/r^2`` and
``h/r`` (:data:`NEWTON_DELTA`, :func:`_disk_normal`): after the hit point no division or square root
lengthens the chain of dependent operations that limits the speed.  Specular:
``v' = v - 2 (v . h) h / |h|^2``; no-slip: :func:`laws.collide` with ``n = -h/|h|``.  The results
agree with the general loop's to rounding, not bit for bit.  :func:`disk_walk` walks one disk inside
its cell, :func:`disks_walk` any disks (docs/algorithm.md, *One disk per cell: the lean loop*).
"""
import functools
import math

from .energy import SETTLE_EVERY, settle_whole, state_energy
from .exact import cross_dd, fma, lattice_shift_dd, offset_dd
from .geometry import lattice_coordinates, lattice_shift, nearest_cell
from .jit import SOURCE_STAMP, inlined, jit
from .laws import collide
from .layout import (
    CIRCLE,
    NOSLIP,
    RECORD_LOG,
    RECORD_NONE,
    RECORD_PORTRAIT,
    SPECULAR,
    STOP_ESCAPE,
    STOP_LEVEL,
    STOP_MAX_COLLISIONS,
    STOP_MAX_TIME,
)
from .records import record
from .roots import linear_exit
from .tolerances import MAX_CELLS_PER_FLIGHT
from .variant import Variant, variant_code

INF = math.inf

#: A cell index no walk reaches: no disk is skipped.
NO_CELL = MAX_CELLS_PER_FLIGHT + 1

#: Largest ``| |h|^2/r^2 - 1 |`` for which one Newton step from ``1/r`` gives
#: ``1/|h|`` to rounding (its error is ``3/8 delta^2``); a larger one (a hit
#: point far off the circle, as at the end of a very long flight) divides.
NEWTON_DELTA = 1e-8


#: Cells a flight walks with the disk offset updated by one lattice vector per step; later cells
#: test their disks with :func:`_line_disk_far`, whose hit point keeps its digits however far.
INCREMENTAL_CELLS = 16


@jit(inline="always")
def _line_disk(dx, dy, vx, vy, ivv, rr):
    """``(t, hx, hy)`` of the flight ``d + v t`` (``d`` from the centre) entering the disk, or ``(inf, 0, 0)``."""
    b = dx * vx + dy * vy
    cross = dx * vy - dy * vx
    disc = rr - cross * cross
    if b < 0.0 and disc > 0.0:  # approaching and not beside nor tangent
        t = (-b - math.sqrt(disc)) * ivv
        return t, dx + vx * t, dy + vy * t
    return INF, 0.0, 0.0


@jit(inline="always")
def _line_disk_far(A, d1, d2, ex, ey, vx, vy, ivv, rr):
    """:func:`_line_disk` for the disk of a far cell ``(d1, d2)``; ``e`` is the start seen from the disk of cell 0.

    ``d = e - (d1 a1 + d2 a2)`` is as long as the flight (``h = d + v t`` would carry ``eps |d|``):
    it is formed exactly (:func:`exact.lattice_shift_dd`), ``d x v`` to a few ulps of itself
    (:func:`exact.cross_dd`), and ``h = ((d x v) (vy, -vx) - sqrt(disc) v) / |v|^2``, the foot of the
    perpendicular stepped back, without ``t``: a few ulps of ``r`` however far the flight went.
    """
    sxh, sxl, syh, syl = lattice_shift_dd(A, d1, d2)
    dxh, dxl = offset_dd(ex, sxh, sxl)
    dyh, dyl = offset_dd(ey, syh, syl)
    b = dxh * vx + dyh * vy
    cross = cross_dd(dxh, dxl, dyh, dyl, vx, vy)
    disc = rr - cross * cross
    if b < 0.0 and disc > 0.0:
        sq = math.sqrt(disc)
        t = (-b - sq) * ivv
        return t, (cross * vy - vx * sq) * ivv, -(cross * vx + vy * sq) * ivv
    return INF, 0.0, 0.0


@jit(inline="always")
def _walk_start(A, B, x, y, vx, vy):
    """``(vv, ivv, faces, steps, ta, tb)``: the cell walk of the straight flight from ``(x, y)`` at its start.

    ``faces = (a0, b0, ia, ib, s1, s2)``: the flight's lattice coordinates at ``t = 0``, their reciprocal
    rates and the directions of the steps; ``steps``: the change of an offset from a disk's centre per
    step in each direction; ``ta, tb``: the first face times.
    """
    a0, b0 = lattice_coordinates(B, x, y)
    a1, b1 = lattice_coordinates(B, vx, vy)
    vv = vx * vx + vy * vy
    s1 = 1 if a1 > 0.0 else -1
    s2 = 1 if b1 > 0.0 else -1
    ia = 1.0 / a1
    ib = 1.0 / b1
    ta = max((0.5 * s1 - a0) * ia, 0.0) if a1 != 0.0 else INF
    tb = max((0.5 * s2 - b0) * ib, 0.0) if b1 != 0.0 else INF
    steps = (s1 * A[0, 0], s1 * A[1, 0], s2 * A[0, 1], s2 * A[1, 1])
    return vv, 1.0 / vv, (a0, b0, ia, ib, s1, s2), steps, ta, tb


@jit(inline="always")
def _cross(t_out, d1, d2, dx, dy, ta, tb, faces, steps):
    """``(d1, d2, dx, dy, ta, tb)`` past the faces crossed at ``t_out``: the offset ``d`` one lattice vector on."""
    a0, b0, ia, ib, s1, s2 = faces
    ux, uy, wx, wy = steps
    if ta == t_out:
        d1 += s1
        dx -= ux
        dy -= uy
        ta = max((d1 + 0.5 * s1 - a0) * ia, t_out)
    if tb == t_out:
        d2 += s2
        dx -= wx
        dy -= wy
        tb = max((d2 + 0.5 * s2 - b0) * ib, t_out)
    return d1, d2, dx, dy, ta, tb


def _disk_walk(hand_on=None):
    """:func:`disk_walk`'s walk from its cell ``(d1, d2)`` on: with ``hand_on`` (near) along ``INCREMENTAL_CELLS``
    cells by :func:`_line_disk`, then on in ``hand_on``; without (far) by :func:`_line_disk_far`."""
    NEAR = hand_on is not None

    @inlined(NEAR)  # the far walk out of line: inlined too, its code cost the near walk 3 % (benchmarks/RESULTS.md)
    def walk(A, ex, ey, dx, dy, vx, vy, ivv, rr, d1, d2, faces, steps, ta, tb, cur_o1, cur_o2, t_limit, max_cells):
        """The walk; ``e``: the start seen from the disk of cell 0, ``d``: the offset in cell ``(d1, d2)``."""
        for _ in range(min(max_cells, INCREMENTAL_CELLS) if NEAR else max_cells):
            if not (d1 == cur_o1 and d2 == cur_o2):
                if NEAR:
                    t, hx, hy = _line_disk(dx, dy, vx, vy, ivv, rr)
                else:
                    t, hx, hy = _line_disk_far(A, d1, d2, ex, ey, vx, vy, ivv, rr)
                if t < INF:
                    return t, d1, d2, hx, hy, 0
            t_out = min(ta, tb)
            if t_out >= t_limit:
                return INF, 0, 0, 0.0, 0.0, 1
            d1, d2, dx, dy, ta, tb = _cross(t_out, d1, d2, dx, dy, ta, tb, faces, steps)
        if NEAR:  # a long flight goes on out of line: the near walk, the common case, stays as short
            return hand_on(A, ex, ey, dx, dy, vx, vy, ivv, rr, d1, d2, faces, steps, ta, tb, cur_o1, cur_o2,
                           t_limit, max_cells - INCREMENTAL_CELLS)
        return INF, 0, 0, 0.0, 0.0, 2

    return walk


_disk_walk_near = _disk_walk(hand_on=_disk_walk())


@jit(inline="always")
def disk_walk(p, A, B, x, y, vx, vy, cur_o1, cur_o2, t_limit, max_cells):
    """First disk hit of the straight flight from ``(x, y)`` (relative to cell 0); one disk ``p`` per cell.

    Walks the cells as :func:`cells.lattice_walk`'s walk does and tests the disk of each cell but the one
    just hit (in cell ``(cur_o1, cur_o2)``); the disk lies inside its cell, so the first hit found
    is the earliest.  The offset ``d`` from the disk's centre steps by one lattice vector per cell
    along ``INCREMENTAL_CELLS`` cells (each step rounds once), later cells use :func:`_line_disk_far`.

    Returns ``(t, o1, o2, hx, hy, status)``: the hit cell, the hit point relative to the centre,
    and ``status`` as in :func:`cells.lattice_walk` (0 hit, 1 past ``t_limit``, 2 past ``max_cells``).
    """
    vv, ivv, faces, steps, ta, tb = _walk_start(A, B, x, y, vx, vy)
    r = p[2]
    ex = x - p[0]
    ey = y - p[1]
    return _disk_walk_near(A, ex, ey, ex, ey, vx, vy, ivv, vv * (r * r), 0, 0, faces, steps, ta, tb, cur_o1, cur_o2,
                           t_limit, max_cells)


@jit(inline="always")
def _copy_near(A, p, o1, o2, d1, d2, x, y, dx, dy, vx, vy, ivv, rr):
    """:func:`_line_disk` for the copy of disk ``p`` ``(o1, o2)`` cells from walk cell ``(d1, d2)``, from ``d``."""
    ex = dx - p[0]
    ey = dy - p[1]
    if o1 != 0 or o2 != 0:
        sx, sy = lattice_shift(A, o1, o2)
        ex -= sx
        ey -= sy
    return _line_disk(ex, ey, vx, vy, ivv, rr)


@jit(inline="always")
def _copy_far(A, p, o1, o2, d1, d2, x, y, dx, dy, vx, vy, ivv, rr):
    """:func:`_line_disk_far` for the copy of disk ``p`` ``(o1, o2)`` cells from walk cell ``(d1, d2)``."""
    return _line_disk_far(A, d1 + o1, d2 + o2, x - p[0], y - p[1], vx, vy, ivv, rr)


def _disks_walk(hand_on=None):
    """:func:`disks_walk`'s walk from its cell ``(d1, d2)`` on: with ``hand_on`` (near) along ``INCREMENTAL_CELLS``
    cells by :func:`_copy_near`, then on in ``hand_on``; without (far) by :func:`_copy_far`."""
    NEAR = hand_on is not None
    test = _copy_near if NEAR else _copy_far

    @inlined(NEAR)
    def walk(params, copies, inside, A, x, y, dx, dy, vx, vy, vv, ivv, cur_e, cur_o1, cur_o2, d1, d2, faces, steps,
             ta, tb, found, t_limit, max_cells):
        """The walk; ``found = (t, j, o1, o2, hx, hy)``: the earliest hit so far (``t = inf``: none)."""
        best, bj, b1_, b2_, bx, by = found
        for _ in range(min(max_cells, INCREMENTAL_CELLS) if NEAR else max_cells):
            for j in range(copies.shape[0]):
                e = copies[j, 0]
                o1 = copies[j, 1]
                o2 = copies[j, 2]
                if e == cur_e and d1 + o1 == cur_o1 and d2 + o2 == cur_o2:
                    continue
                p = params[e]
                t, hx, hy = test(A, p, o1, o2, d1, d2, x, y, dx, dy, vx, vy, ivv, vv * (p[2] * p[2]))
                if t < best:
                    best, bj, b1_, b2_, bx, by = t, j, d1, d2, hx, hy
            t_out = min(ta, tb)
            if best <= t_out or (inside and best < INF):
                return best, b1_, b2_, bj, bx, by, 0
            if t_out >= t_limit:
                return INF, 0, 0, -1, 0.0, 0.0, 1
            d1, d2, dx, dy, ta, tb = _cross(t_out, d1, d2, dx, dy, ta, tb, faces, steps)
        if NEAR:  # a long flight goes on out of line, as in disk_walk
            return hand_on(params, copies, inside, A, x, y, dx, dy, vx, vy, vv, ivv, cur_e, cur_o1, cur_o2, d1, d2,
                           faces, steps, ta, tb, (best, bj, b1_, b2_, bx, by), t_limit, max_cells - INCREMENTAL_CELLS)
        return INF, 0, 0, -1, 0.0, 0.0, 2

    return walk


_disks_walk_near = _disks_walk(hand_on=_disks_walk())


@jit(inline="always")
def disks_walk(params, copies, inside, A, B, x, y, vx, vy, cur_e, cur_o1, cur_o2, t_limit, max_cells):
    """First disk hit of the straight flight from ``(x, y)`` (relative to cell 0).

    Tests in each cell the disk copies that reach it (``copies``: element ``e`` of ``params``
    translated by ``o1 a1 + o2 a2``) but the one just hit (element ``cur_e`` of cell
    ``(cur_o1, cur_o2)``: a straight flight leaving a convex disk does not meet it again), and takes
    the earliest hit so far once it comes before the cell's exit (any earlier hit lies in a cell
    already walked), or at once when every disk lies inside its cell (``inside``).  The offset ``d``
    from the cell's centre as in :func:`disk_walk`.

    Returns ``(t, o1, o2, j, hx, hy, status)``: the walk cell where the hit was found, the copy ``j``
    hit, the hit point relative to the copy's centre, and ``status`` as in :func:`cells.lattice_walk`.
    """
    vv, ivv, faces, steps, ta, tb = _walk_start(A, B, x, y, vx, vy)
    return _disks_walk_near(params, copies, inside, A, x, y, x, y, vx, vy, vv, ivv, cur_e, cur_o1, cur_o2, 0, 0,
                            faces, steps, ta, tb, (INF, -1, 0, 0, 0.0, 0.0), t_limit, max_cells)


@jit(inline="always")  # inlined, as every step of the loop below: they sit on its chain of dependent arithmetic
def _flight_limit(A, m1, m2, y, vy, stop_below, remaining):
    """``(t_level, oy, limit)``: the time to the stop level (inf: none), the cell's offset in y, the flight's bound."""
    t_level = INF
    oy = 0.0
    if stop_below > -INF:
        oy = lattice_shift(A, m1, m2)[1]
        t_level = linear_exit(y + oy - stop_below, vy, INF)
    return t_level, oy, min(remaining, t_level)


@jit(inline="always")
def _flight_stop(x, y, vx, vy, t, t_hit, status, t_level, oy, stop_below, remaining, limit, max_time):
    """``(stop, x, y, t)``: the orbit's stop before the hit (``STOP_MAX_COLLISIONS``: none, the state unchanged)."""
    if t_level < INF and t_level <= t_hit and t_level <= remaining:
        return STOP_LEVEL, x + t_level * vx, stop_below - oy, t + t_level
    if status == 2 or (status == 1 and limit == INF):
        return STOP_ESCAPE, x, y, t
    if status != 0 or t_hit > remaining:
        return STOP_MAX_TIME, x + remaining * vx, y + remaining * vy, max_time
    return STOP_MAX_COLLISIONS, x, y, t


@jit(inline="always")
def _rebase(A, B, x, y, o1, o2, cur_o1, cur_o2):
    """``(x, y, o1, o2, cur_o1, cur_o2)`` with the hit point of a disk reaching into other cells re-based onto the
    cell that holds it."""
    if cur_o1 != 0 or cur_o2 != 0:
        sx, sy = lattice_shift(A, cur_o1, cur_o2)
        x += sx
        y += sy
    k1, k2 = nearest_cell(B, x, y)
    if k1 != 0 or k2 != 0:
        sx, sy = lattice_shift(A, k1, k2)
        x -= sx
        y -= sy
        o1 += k1
        o2 += k2
        cur_o1 -= k1
        cur_o2 -= k2
    return x, y, o1, o2, cur_o1, cur_o2


@jit(inline="always")
def _disk_normal(hx, hy, ir):
    """``n = -h/|h|`` with no division or square root waiting on ``h``.

    With ``a = h/r`` and ``g = |a|^2 - 1`` (a few ulps; by fma, so nothing is
    rounded at 1), ``h/|h| = a (1 - g/2)`` to ``g^2``, and the correction
    enters each component before its one rounding (docs/algorithm.md
    section 0).
    """
    ax_ = hx * ir
    ay_ = hy * ir
    g = fma(ax_, ax_, fma(ay_, ay_, -1.0))
    if abs(g) < NEWTON_DELTA:
        hg = 0.5 * g
        return -fma(hx, ir, -hg * ax_), -fma(hy, ir, -hg * ay_)
    # a hit point far off the circle (the end of a very long flight)
    irho = 1.0 / math.sqrt(hx * hx + hy * hy)
    return -hx * irho, -hy * irho


@jit(inline="always")
def _disk_reflect(vx, vy, hx, hy, ir2):
    """``v`` reflected in the line through ``h``; ``1/|h|^2`` one Newton step from ``1/r^2``."""
    hh = hx * hx + hy * hy
    delta = hh * ir2 - 1.0
    ihh = ir2 * (1.0 - delta) if abs(delta) < NEWTON_DELTA else 1.0 / hh
    k = 2.0 * (vx * hx + vy * hy) * ihh
    return vx - k * hx, vy - k * hy


@jit(inline="always")
def _record_disk_hit(mode, rec, n_rec, mask, A, m1, m2, cur_o1, cur_o2, t, x, y, vx, vy, w, vx_in, vy_in, w_in, p,
                     e, nx, ny):
    """:func:`records.record` of a collision with disk ``e`` of cell ``(cur_o1, cur_o2)`` (from cell ``(m1, m2)``)."""
    ox, oy = lattice_shift(A, m1, m2)
    sx = 0.0
    sy = 0.0
    if cur_o1 != 0 or cur_o2 != 0:
        sx, sy = lattice_shift(A, cur_o1, cur_o2)
    return record(mode, rec, n_rec, mask, t, x, y, ox, oy, m1, m2, vx, vy, w, vx_in, vy_in, w_in, CIRCLE, p, sx, sy,
                  e, 0.0, nx, ny)


@functools.cache
def disk_lattice_kernel(spin=None, mode=None):
    """The event loop for disk scatterers on a lattice without force, with :func:`loop.run_orbit`'s signature.

    ``spin`` and ``mode`` are compile-time flags as in :func:`loop.orbit_kernel` (``None``: read from
    the arguments).  Only for scenes with :attr:`KernelTable.disk_lattice` (disjoint disks); the
    force, ``kinds``, ``lattice`` and junction arguments are ignored.  One copy with no shift (one
    disk inside its cell) runs a loop compiled around :func:`disk_walk`, any other scene one around
    :func:`disks_walk`, chosen once per orbit (so the one-disk loop carries no test for the other).
    """
    one_disk = _disk_loop(spin, mode, True)
    several = _disk_loop(spin, mode, False)

    @jit
    def run_disk_orbit(kinds, params, copies, A, B, lattice, jstart, jpts, law, c, s, ax, ay, thermostat, x, y, vx, vy,
                       w, max_collisions, max_time, stop_below, scale, mode, rec, mask, start_element=-1,
                       ceiling=math.inf, W=0.0):
        """:func:`loop.run_orbit` for disks on a lattice without force or field (same arguments and outputs).

        ``ceiling`` must be ``inf``: a bounded lattice (``Scene.top``) never runs this loop
        (:attr:`noslipsim._engine.table.KernelTable.disk_lattice` is false for it).
        """
        # every disk inside its cell (no copy shifted): a hit point lies in the cell where it is found
        inside = True
        for j in range(copies.shape[0]):
            inside = inside and copies[j, 1] == 0 and copies[j, 2] == 0
        # one disk inside its cell (the Sinai torus, the Lorentz gas): the loop without the copy loop
        if copies.shape[0] == 1 and inside:
            return one_disk(params, copies, A, B, law, c, s, x, y, vx, vy, w, max_collisions, max_time,
                            stop_below, mode, rec, mask, start_element, True)
        return several(params, copies, A, B, law, c, s, x, y, vx, vy, w, max_collisions, max_time, stop_below,
                       mode, rec, mask, start_element, inside)

    return run_disk_orbit


@functools.cache
def _disk_loop(spin, mode, one):
    """The loop of :func:`disk_lattice_kernel` for one disk inside its cell (``one``: :func:`disk_walk`,
    compiled without the copy loop) or for any disks (:func:`disks_walk`)."""
    SPIN_RT = spin is None
    SPIN = bool(spin)
    MODE_RT = mode is None
    MODE = RECORD_LOG if mode is None else int(mode)
    ONE = bool(one)
    VARIANT = variant_code(Variant(spin=spin, mode=mode, disks=True))  # reported with every result

    @jit
    def disk_loop(params, copies, A, B, law, c, s, x, y, vx, vy, w, max_collisions, max_time, stop_below, mode,
                  rec, mask, start_element, inside):
        """The event loop proper (``inside``: no copy shifted)."""
        law = law if SPIN_RT else (NOSLIP if SPIN else SPECULAR)
        mode = mode if MODE_RT else MODE
        # 1/r of the first disk once (the only one of a Sinai torus); of another disk at its hit
        e0 = copies[0, 0]
        ir0 = 1.0 / params[e0, 2]
        # the energy kept (energy.settle_whole); no force: |v|^2 (+ w^2 where the law exchanges it with the spin)
        mixes = law == NOSLIP and s != 0.0
        energy0 = state_energy(vx, vy, w, mixes, 0.0, 0.0, 0.0, 0.0, False)[0]
        t = 0.0
        # the disk the flight leaves: element cur_e of cell (cur_o1, cur_o2) (none at a start inside the table)
        cur_e = start_element
        cur_o1 = 0 if start_element >= 0 else NO_CELL
        cur_o2 = 0
        m1 = 0
        m2 = 0
        n = 0
        n_rec = 0
        stop = STOP_MAX_COLLISIONS
        # blocks of SETTLE_EVERY collisions, the energy measured and given back between two
        # (energy.settle): the call stays out of the collision loop (as in loop.py)
        block_end = min(max_collisions, SETTLE_EVERY)
        while True:
            while n < block_end:
                remaining = max_time - t
                t_level, oy, limit = _flight_limit(A, m1, m2, y, vy, stop_below, remaining)
                if ONE:
                    t_hit, o1, o2, hx, hy, status = disk_walk(params[e0], A, B, x, y, vx, vy, cur_o1, cur_o2, limit,
                                                              MAX_CELLS_PER_FLIGHT)
                    j = 0
                else:
                    t_hit, o1, o2, j, hx, hy, status = disks_walk(params, copies, inside, A, B, x, y, vx, vy, cur_e,
                                                                  cur_o1, cur_o2, limit, MAX_CELLS_PER_FLIGHT)
                stop, x, y, t = _flight_stop(x, y, vx, vy, t, t_hit, status, t_level, oy, stop_below, remaining, limit,
                                             max_time)
                if stop != STOP_MAX_COLLISIONS:
                    break
                # the particle is now at c + h, relative to walk cell (o1, o2), on the disk of element e
                # in cell (o1 + cur_o1, o2 + cur_o2)
                e = e0
                ir = ir0
                cur_o1 = 0
                cur_o2 = 0
                if not ONE:
                    e = copies[j, 0]
                    ir = 1.0 / params[e, 2]
                    cur_o1 = copies[j, 1]
                    cur_o2 = copies[j, 2]
                p = params[e]
                ir2 = ir * ir
                x = p[0] + hx
                y = p[1] + hy
                # a disk reaching into other cells: re-base onto the cell that holds the hit point
                if not ONE and not inside:
                    x, y, o1, o2, cur_o1, cur_o2 = _rebase(A, B, x, y, o1, o2, cur_o1, cur_o2)
                cur_e = e
                m1 += o1
                m2 += o2
                vx_in = vx
                vy_in = vy
                w_in = w
                nx = 0.0
                ny = 0.0
                if law == NOSLIP or mode == RECORD_PORTRAIT:
                    nx, ny = _disk_normal(hx, hy, ir)
                if law == NOSLIP:
                    vx, vy, w = collide(law, c, s, vx, vy, w, nx, ny)
                else:
                    vx, vy = _disk_reflect(vx, vy, hx, hy, ir2)
                t += t_hit
                n += 1
                if mode != RECORD_NONE:
                    n_rec = _record_disk_hit(mode, rec, n_rec, mask, A, m1, m2, cur_o1, cur_o2, t, x, y, vx, vy, w,
                                             vx_in, vy_in, w_in, p, e, nx, ny)
            if stop != STOP_MAX_COLLISIONS or n >= max_collisions:  # stopped inside the block, or done
                break
            # disks only, no force: nothing a targeted part keeps, so the whole state
            # (docs/algorithm.md, "Which form, per table")
            vx, vy, w = settle_whole(vx, vy, w, mixes, 0.0, 0.0, 0.0, 0.0, False, energy0)
            block_end = min(max_collisions, n + SETTLE_EVERY)
        ox, oy = lattice_shift(A, m1, m2)
        # the final state may lie in another cell (a stop in mid-flight)
        k1, k2 = nearest_cell(B, x, y)
        m1 += k1
        m2 += k2
        return n, stop, 0, n_rec, t, x + ox, y + oy, vx, vy, w, m1, m2, (VARIANT << 32) | SOURCE_STAMP

    return disk_loop

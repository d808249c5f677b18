"""The event loop of one disk per lattice cell without force (Sinai torus, Lorentz gas).

Such a scene needs far less than the general loop (:mod:`loop`): flights are
straight and the obstacle is a convex disk inside its cell, so the disk just
hit is not met on the next flight (no deflation), disks never touch (no
corner rule), a collision never slides off (no grazing stop), there are no
extents to test, and the first disk met along the cell walk is the hit.  The
test and the collision take no ``hypot``, projection or division after the
hit point is known (the chain of dependent operations from one collision to
the next is what limits the speed):

* hit: with ``d = q - c`` and ``b = d . v``, the flight meets the disk iff
  ``b < 0`` and ``disc = |v|^2 r^2 - (d x v)^2 > 0`` (Lagrange's identity:
  ``disc = b^2 - |v|^2 (|d|^2 - r^2)``; the cross product keeps a long
  flight's grazing test at full precision); the time is
  ``(-b - sqrt(disc)) / |v|^2`` (no cancellation: both terms are positive) and
  the hit point relative to the centre is ``h = d + v t``;
* ``h`` lies on the circle to rounding (as a projected point does), so
  ``|h|^2 = r^2 (1 + delta)`` with ``delta`` of a few ulps, and ``1/|h|^2`` and
  ``h/|h|`` are one Newton step from ``1/r^2`` and ``h/r``, accurate to
  ``delta^2`` (a division when ``delta`` is not small, see ``NEWTON_DELTA``);
  the normal's step is taken with fused multiply-adds (:func:`exact.fma`), so
  its correction is not rounded away at 1 (that biased the energy by
  -1e-16 per no-slip collision at r = 0.3; docs/algorithm.md section 0);
* specular: ``v' = v - 2 (v . h) h / |h|^2``, the reflection in the line
  through ``h``; no-slip: :func:`laws.collide` with ``n = -h/|h|``.

A tangent flight (``disc = 0``) is no hit, as in the general loop.  The
results differ from the general loop's in the last bits (the other variants
of :func:`loop.orbit_kernel` are identical to it bit for bit): every flight
agrees to rounding, stops and records included (``tests/test_disk_lattice.py``).
Measured on the Sinai torus: about twice the general loop's speed
(``benchmarks/RESULTS.md``).
"""
import functools
import math

from .energy import SETTLE_EVERY, settle, state_energy
from .exact import fma
from .geometry import lattice_coordinates, lattice_shift, nearest_cell
from .jit import jit
from .laws import collide
from .layout import (
    CIRCLE, NOSLIP, RECORD_LOG, RECORD_NONE, RECORD_PORTRAIT, SPECULAR, STOP_ESCAPE, STOP_LEVEL,
    STOP_MAX_COLLISIONS, STOP_MAX_TIME,
)
from .records import record
from .roots import linear_exit
from .tolerances import MAX_CELLS_PER_FLIGHT

INF = math.inf

#: A cell index no walk reaches: no disk is skipped.
NO_CELL = MAX_CELLS_PER_FLIGHT + 1

#: Largest ``| |h|^2/r^2 - 1 |`` for which one Newton step from ``1/r`` gives
#: ``1/|h|`` to rounding (its error is ``3/8 delta^2``); a larger one (a hit
#: point far off the circle, as at the end of a very long flight) divides.
NEWTON_DELTA = 1e-8


#: Cells a flight walks with the disk offset updated by one lattice vector per
#: step; later cells form it from the cell indices, so its rounding stays
#: within this many rounding errors of the direct form's.
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
def disk_walk(p, A, B, x, y, vx, vy, cur_o1, cur_o2, t_limit, max_cells):
    """First disk hit of the straight flight from ``(x, y)`` (relative to cell 0); one disk ``p`` per cell.

    Walks the cells as :func:`cells.walk_hit` does (face times from the
    flight's start, here times the reciprocal rate) and tests the disk of
    each cell but the one just hit (in cell ``(cur_o1, cur_o2)``); the disk
    lies inside its cell, so the first hit found is the earliest.  Along the
    first ``INCREMENTAL_CELLS`` cells the offset ``d`` from the disk's centre
    is updated by one lattice vector per step (each step rounds once); later
    cells form it from the cell indices, so its error stays within a few
    rounding errors of the direct form's however long the flight.

    Returns ``(t, o1, o2, hx, hy, status)``: the hit cell, the hit point
    relative to the centre, and ``status`` as in :func:`cells.walk_hit`
    (0 hit, 1 past ``t_limit``, 2 past ``max_cells``).
    """
    a0, b0 = lattice_coordinates(B, x, y)
    a1, b1 = lattice_coordinates(B, vx, vy)
    vv = vx * vx + vy * vy
    ivv = 1.0 / vv
    s1 = 1 if a1 > 0.0 else -1
    s2 = 1 if b1 > 0.0 else -1
    ia = 1.0 / a1
    ib = 1.0 / b1
    ta = max((0.5 * s1 - a0) * ia, 0.0) if a1 != 0.0 else INF
    tb = max((0.5 * s2 - b0) * ib, 0.0) if b1 != 0.0 else INF
    r = p[2]
    rr = vv * (r * r)
    ux = s1 * A[0, 0]
    uy = s1 * A[1, 0]
    wx = s2 * A[0, 1]
    wy = s2 * A[1, 1]
    dx = x - p[0]
    dy = y - p[1]
    d1 = 0
    d2 = 0
    for k in range(max_cells):
        if not (d1 == cur_o1 and d2 == cur_o2):
            if k >= INCREMENTAL_CELLS:
                sx, sy = lattice_shift(A, d1, d2)
                dx = (x - sx) - p[0]
                dy = (y - sy) - p[1]
            t, hx, hy = _line_disk(dx, dy, vx, vy, ivv, rr)
            if t < INF:
                return t, d1, d2, hx, hy, 0
        t_out = min(ta, tb)
        if t_out >= t_limit:
            return INF, 0, 0, 0.0, 0.0, 1
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
    return INF, 0, 0, 0.0, 0.0, 2


@functools.lru_cache(maxsize=None)
def disk_lattice_kernel(spin=None, mode=None):
    """The event loop for one disk per lattice cell without force, with :func:`loop.run_orbit`'s signature.

    ``spin`` and ``mode`` are compile-time flags as in :func:`loop.orbit_kernel`
    (``None``: read the law or the record mode from the arguments).  Only
    for scenes with :attr:`noslipsim.Scene.one_disk_per_cell`; the
    force, ``kinds``, ``lattice`` and junction arguments are ignored.
    """
    SPIN_RT = spin is None
    SPIN = bool(spin)
    MODE_RT = mode is None
    MODE = RECORD_LOG if mode is None else int(mode)

    @jit
    def run_disk_orbit(kinds, params, copies, A, B, lattice, jstart, jpts, law, c, s, ax, ay, x, y, vx, vy, w,
                       max_collisions, max_time, stop_below, scale, mode, rec, mask, start_element=-1):
        """:func:`loop.run_orbit` for one disk per lattice cell without force (same arguments and outputs)."""
        law = law if SPIN_RT else (NOSLIP if SPIN else SPECULAR)
        mode = mode if MODE_RT else MODE
        e = copies[0, 0]
        p = params[e]
        ir = 1.0 / p[2]
        ir2 = ir * ir
        # the energy kept (energy.settle); no force: |v|^2 (+ w^2 where the law exchanges it with the spin)
        mixes = law == NOSLIP and s != 0.0
        e0 = state_energy(vx, vy, w, mixes, 0.0, 0.0, 0.0, 0.0, False)[0]
        t = 0.0
        # the cell whose disk the flight leaves (none at a start inside the table)
        cur_o1 = 0 if start_element >= 0 else NO_CELL
        cur_o2 = 0
        m1 = 0
        m2 = 0
        n = 0
        n_rec = 0
        stop = STOP_MAX_COLLISIONS
        while n < max_collisions:
            remaining = max_time - t
            t_level = INF
            oy = 0.0
            if stop_below > -INF:
                oy = lattice_shift(A, m1, m2)[1]
                t_level = linear_exit(y + oy - stop_below, vy, INF)
            limit = min(remaining, t_level)
            t_hit, o1, o2, hx, hy, status = disk_walk(p, A, B, x, y, vx, vy, cur_o1, cur_o2, limit,
                                                      MAX_CELLS_PER_FLIGHT)
            if t_level < INF and t_level <= t_hit and t_level <= remaining:
                x = x + t_level * vx
                y = stop_below - oy
                t += t_level
                stop = STOP_LEVEL
                break
            if status == 2 or (status == 1 and limit == INF):
                stop = STOP_ESCAPE
                break
            if status != 0 or t_hit > remaining:
                x = x + remaining * vx
                y = y + remaining * vy
                t = max_time
                stop = STOP_MAX_TIME
                break
            # the disk lies inside its cell: the particle is now in cell (o1, o2), at c + h
            x = p[0] + hx
            y = p[1] + hy
            m1 += o1
            m2 += o2
            vx_in = vx
            vy_in = vy
            w_in = w
            nx = 0.0
            ny = 0.0
            if law == NOSLIP or mode == RECORD_PORTRAIT:
                # n = -h/|h| with no division or square root waiting on h: with a = h/r and g = |a|^2 - 1
                # (a few ulps; by fma, so nothing is rounded at 1), h/|h| = a (1 - g/2) to g^2, and the
                # correction enters each component before its one rounding (docs/algorithm.md section 0)
                ax_ = hx * ir
                ay_ = hy * ir
                g = fma(ax_, ax_, fma(ay_, ay_, -1.0))
                if abs(g) < NEWTON_DELTA:
                    hg = 0.5 * g
                    nx = -fma(hx, ir, -hg * ax_)
                    ny = -fma(hy, ir, -hg * ay_)
                else:  # a hit point far off the circle (the end of a very long flight)
                    irho = 1.0 / math.sqrt(hx * hx + hy * hy)
                    nx = -hx * irho
                    ny = -hy * irho
            if law == NOSLIP:
                vx, vy, w = collide(law, c, s, vx, vy, w, nx, ny)
            else:  # the reflection in the line through h; 1/|h|^2 one Newton step from 1/r^2
                hh = hx * hx + hy * hy
                delta = hh * ir2 - 1.0
                ihh = ir2 * (1.0 - delta) if abs(delta) < NEWTON_DELTA else 1.0 / hh
                k = 2.0 * (vx * hx + vy * hy) * ihh
                vx -= k * hx
                vy -= k * hy
            t += t_hit
            n += 1
            if mode != RECORD_NONE:
                ox, oy = lattice_shift(A, m1, m2)
                n_rec = record(mode, rec, n_rec, mask, t, x, y, ox, oy, m1, m2, vx, vy, w, vx_in, vy_in, w_in,
                               CIRCLE, p, 0.0, 0.0, e, 0.0, nx, ny)
            if n % SETTLE_EVERY == 0:  # the energy measured, given back if off (the next flight's v)
                vx, vy, w = settle(vx, vy, w, mixes, 0.0, 0.0, 0.0, 0.0, False, e0)
            cur_o1 = 0
            cur_o2 = 0
        ox, oy = lattice_shift(A, m1, m2)
        # the final state may lie in another cell (a stop in mid-flight)
        k1, k2 = nearest_cell(B, x, y)
        m1 += k1
        m2 += k2
        return n, stop, 0, n_rec, t, x + ox, y + oy, vx, vy, w, m1, m2

    return run_disk_orbit

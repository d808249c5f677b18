"""The event loop's steps after a flight: onto the cell, the corner pass, the grazing test and the settle.

Each step is a kernel inlined into the event loop (:func:`loop.orbit_kernel`); the ones that
depend on a variant's compile-time constants are closures of small factories (numba prunes their
branches on those constants before typing, so a variant compiles none of what it cannot reach).
docs/algorithm.md, *4. Corner rule and element ends* and *5. Grazing guard*.
"""
import functools
import math

from .energy import settle, settle_velocity, settle_whole, targeted_settle
from .events import leaves_through_contact, slides_off
from .geometry import copy_shift, lattice_shift, nearest_cell, place_on_element
from .jit import jit
from .laws import collide
from .layout import ELEMENT_LAW, PER_ELEMENT, RECORD_NONE, SPECULAR
from .records import record
from .thermostat import drag
from .tolerances import CONTACT_TOL, JUNCTION_GATE, MAX_CORNER_BOUNCES

INF = math.inf


@jit
def _near_junction(jstart, jpts, e, x, y, gate):
    """True if ``(x, y)`` (in element ``e``'s frame) lies within ``gate`` of one of its junctions."""
    for k in range(jstart[e], jstart[e + 1]):
        if abs(x - jpts[k, 0]) <= gate and abs(y - jpts[k, 1]) <= gate:
            return True
    return False


@jit
def _contact(kinds, params, copies, A, lattice, x, y, vx, vy, ax, ay, cur_e, cur_o1, cur_o2, tol, ceiling):
    """First element copy (other than the current one) touched here and left through, or ``(-1, 0, 0)``.

    Copies above ``ceiling`` (a bounded lattice's top, relative to the cell) do not exist.
    """
    for k in range(copies.shape[0]):
        e = copies[k, 0]
        o1 = copies[k, 1]
        o2 = copies[k, 2]
        if e == cur_e and o1 == cur_o1 and o2 == cur_o2:
            continue
        sx, sy = copy_shift(A, o1, o2, lattice)
        if params[e, 1] + sy > ceiling:
            continue
        if leaves_through_contact(kinds[e], params[e], x - sx, y - sy, vx, vy, ax, ay, tol):
            return e, o1, o2
    return -1, 0, 0


@jit(inline="always")
def rebase(A, B, lattice, far, px, py, sx, sy, o1, o2, m1, m2, ox, oy):
    """The hit point ``(px, py)`` (relative to copy ``(o1, o2)``) re-based onto the cell that now holds it.

    Returns ``(x, y, sx, sy, o1, o2, m1, m2, ox, oy)``: the position in its cell, the copy's shift and
    offsets seen from there, the cell's indices and offset.  A far hit is re-based from the point seen
    from its copy (``px + sx - k a`` would carry ``eps |sx|``, the flight's length).
    """
    x = px + sx
    y = py + sy
    if not lattice:
        return x, y, sx, sy, o1, o2, m1, m2, ox, oy
    if far:
        j1, j2 = nearest_cell(B, px, py)
        k1 = o1 + j1
        k2 = o2 + j2
        dx, dy = lattice_shift(A, j1, j2)
        x = px - dx
        y = py - dy
    else:
        k1, k2 = nearest_cell(B, x, y)
        if k1 != 0 or k2 != 0:
            dx, dy = lattice_shift(A, k1, k2)
            x -= dx
            y -= dy
    if k1 != 0 or k2 != 0:
        m1 += k1
        m2 += k2
        o1 -= k1
        o2 -= k2
        ox, oy = lattice_shift(A, m1, m2)
        sx, sy = lattice_shift(A, o1, o2)
    return x, y, sx, sy, o1, o2, m1, m2, ox, oy


@functools.cache
def element_law(MIXED_ANY, MIXED_ALWAYS):
    """``law_of(law, p)``: the law of a collision on element ``p`` (a mixed table: the element's own)."""
    @jit(inline="always")
    def law_of(law, p):
        if MIXED_ANY:
            if MIXED_ALWAYS or law == PER_ELEMENT:
                return int(p[ELEMENT_LAW])
        return law

    return law_of


@functools.cache
def local_acceleration(THERMO_ANY, THERMO_ALWAYS, MAG_ANY, MAG_ALWAYS):
    """``acceleration(thermo, mag, vx, vy, ax, ay, W)``: the flight's acceleration at a contact.

    The force; a thermostatted flight's ``F - alpha v``; a magnetic one's ``W J v``.
    """
    @jit(inline="always")
    def acceleration(thermo, mag, vx, vy, ax, ay, W):
        if THERMO_ALWAYS or (THERMO_ANY and thermo):
            return drag(vx, vy, ax, ay)
        if MAG_ALWAYS or (MAG_ANY and mag):
            return -W * vy, W * vx
        return ax, ay

    return acceleration


@functools.cache
def corner_pass(law_of, acceleration):
    """The corner rule after a hit on copy ``(cur_e, cur_o1, cur_o2)`` (docs/algorithm.md, *4. Corner rule*).

    ``corners(table, ..., cell, ..., current, ..., flight, law_e, nx, ny)`` (``table = (kinds, params, copies,
    A, lattice, jstart, jpts)``, ``cell = (m1, m2, ox, oy)``, ``current = (cur_e, cur_o1, cur_o2)``,
    ``flight = (thermo, mag, ax, ay, W)``: grouped, as a call of more than 30 arguments is compiled as
    ``f(*args)``, which numba cannot inline) returns ``(corner, vx, vy, w, n, n_rec, n_corner, cur_e, cur_o1,
    cur_o2, law_e, nx, ny)``: ``corner`` true when more than ``MAX_CORNER_BOUNCES`` came in a row (the orbit
    stops), the state after the last collision, its copy, law and normal.
    """
    @jit(inline="always")
    def corners(table, law, c, s, mode, rec, mask, t, x, y, cell, vx, vy, w, n, n_rec, n_corner, current, sx, sy,
                length, max_collisions, top, flight, law_e, nx, ny):
        kinds, params, copies, A, lattice, jstart, jpts = table
        m1, m2, ox, oy = cell
        cur_e, cur_o1, cur_o2 = current
        thermo, mag, ax, ay, W = flight
        bounces = 0
        near = _near_junction(jstart, jpts, cur_e, x - sx, y - sy, JUNCTION_GATE * length)
        while near and n < max_collisions:
            aex, aey = acceleration(thermo, mag, vx, vy, ax, ay, W)
            j, o1, o2 = _contact(kinds, params, copies, A, lattice, x, y, vx, vy, aex, aey, cur_e, cur_o1, cur_o2,
                                 CONTACT_TOL * length, top)
            if j < 0:
                break
            bounces += 1
            if bounces > MAX_CORNER_BOUNCES:
                return True, vx, vy, w, n, n_rec, n_corner, cur_e, cur_o1, cur_o2, law_e, nx, ny
            kind = kinds[j]
            p = params[j]
            sx, sy = copy_shift(A, o1, o2, lattice)
            nx, ny = place_on_element(kind, p, x - sx, y - sy)[2:]
            vx_in = vx
            vy_in = vy
            law_e = law_of(law, p)
            vx, vy, w_out = collide(law_e, c, s, vx_in, vy_in, w, nx, ny)
            if mode != RECORD_NONE:
                n_rec = record(mode, rec, n_rec, mask, t, x, y, ox, oy, m1, m2, vx, vy, w_out, vx_in, vy_in, w, kind,
                               p, sx, sy, j, 1.0, nx, ny)
            w = w_out
            n += 1
            n_corner += 1
            cur_e = j
            cur_o1 = o1
            cur_o2 = o2
        return False, vx, vy, w, n, n_rec, n_corner, cur_e, cur_o1, cur_o2, law_e, nx, ny

    return corners


@functools.cache
def grazing(acceleration):
    """``grazes(...)``: just after the last collision, the flight leaves through its copy at once
    (:func:`events.slides_off`; the event model cannot go on)."""
    @jit(inline="always")
    def grazes(kinds, params, A, lattice, cur_e, cur_o1, cur_o2, x, y, vx, vy, thermo, mag, ax, ay, W):
        sx, sy = copy_shift(A, cur_o1, cur_o2, lattice)
        aex, aey = acceleration(thermo, mag, vx, vy, ax, ay, W)
        return slides_off(kinds[cur_e], params[cur_e], x - sx, y - sy, vx, vy, aex, aey)

    return grazes


@functools.cache
def settle_step(MIXED_ANY, SETTLE_WHOLE, SETTLE_RT):
    """``(form, settled)``: the settle's form for an orbit, and the energy given back in that form.

    ``form(kinds, law, potential, mixes, bends)``: True for the whole-state settle (``SETTLE_WHOLE``, or
    where ``SETTLE_RT`` by the table's rule, :func:`energy.targeted_settle`).  ``settled(..., whole, law_e,
    nx, ny)``: the whole state scaled (:func:`energy.settle_whole`) or the targeted part
    (:func:`energy.settle`); after a specular element of a mixed table, the velocity only, so the spin
    keeps its bits (:func:`energy.settle_velocity`).  The form is tested on these constants, so a kernel
    of one form compiles that form only.
    """
    @jit(inline="always")
    def form(kinds, law, potential, mixes, bends):
        if SETTLE_RT:
            return not targeted_settle(kinds, law == PER_ELEMENT, potential, mixes, bends)
        return SETTLE_WHOLE

    @jit(inline="always")
    def settled(vx, vy, w, mixes, ax, ay, x, y, potential, e0, how, whole, law_e, nx, ny):
        if SETTLE_WHOLE or (SETTLE_RT and whole):
            return settle_whole(vx, vy, w, mixes, ax, ay, x, y, potential, e0)
        if MIXED_ANY and mixes and law_e == SPECULAR:
            return settle_velocity(vx, vy, w, mixes, ax, ay, x, y, potential, e0, how)
        return settle(vx, vy, w, mixes, ax, ay, x, y, potential, e0, how, nx, ny)

    return form, settled

"""The event loop: one orbit, collision after collision.

One bounce is three named steps (as in DynamicalBilliards.jl):

1. next hit: the earliest exit root over the element copies the flight can
   reach (:func:`events.hit_in_cell`; on a lattice, cell by cell with
   :func:`cells.walk_hit`);
2. relocate: evaluate the flight at that root and project onto the element
   (:func:`geometry.place_on_element`), so rounding never leaves the particle
   outside;
3. resolve: apply the collision law (:func:`laws.collide`).

Corner rule: after a hit, every other element copy that touches the hit point
(within ``CONTACT_TOL``) and whose supporting line or circle the new velocity
leaves through is hit at once, in index order, each counted as a collision
with ``corner = 1``.  More than ``MAX_CORNER_BOUNCES`` in a row stop the orbit.

Positions are relative to the particle's current lattice cell (plain scenes:
one cell, ``A = 0``) and flights start from the last collision; only the total
time is a running sum.
"""
import functools
import math

from . import magnetic_flight, thermo_flight
from .cells import FAR_CELLS, far_hit_point, far_move, walk_hit
from .disks import disk_lattice_kernel
from .energy import SETTLE_EVERY, settle, settle_mode, settle_velocity, state_energy
from .events import advance, exact_line_hit, hit_in_cell, leaves_through_contact, slides_off
from .geometry import copy_shift, lattice_shift, nearest_cell, place_on_element
from .jit import SOURCE_STAMP, jit
from .laws import collide
from .layout import (
    ELEMENT_LAW,
    LONG_WALL,
    NOSLIP,
    PER_ELEMENT,
    RECORD_LOG,
    RECORD_NONE,
    SPECULAR,
    STOP_CORNER,
    STOP_ESCAPE,
    STOP_GRAZING,
    STOP_LEVEL,
    STOP_MAX_COLLISIONS,
    STOP_MAX_TIME,
    STOP_PINNED,
    STOP_SEARCH_LIMIT,
)
from .magnetic import period as magnetic_period
from .records import record
from .roots import quadratic_exit
from .search import SEARCH_FAILED, event_search
from .thermostat import drag, field
from .thermostat import flight as thermo_path
from .tolerances import CONTACT_TOL, EXTENT_TOL, JUNCTION_GATE, MAX_CELLS_PER_FLIGHT, MAX_CORNER_BOUNCES
from .variant import flight_switches, normalise, variant_code

INF = math.inf
#: The closed-form flights' event searches (search.py), one per flight module.
thermo_hit_in_cell, thermo_walk_hit, thermo_exact_line_hit = event_search(thermo_flight)
magnetic_hit_in_cell, magnetic_walk_hit, magnetic_exact_line_hit = event_search(magnetic_flight)
thermo_state = thermo_flight.state_at
thermo_line_exit = thermo_flight.line_exit
magnetic_state = magnetic_flight.state_at
magnetic_line_exit = magnetic_flight.line_exit


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


@jit
def _above_top(params, y, top):
    """True if height ``y`` lies above every copy of a bounded lattice whose top is ``top`` (circles only).

    With no downward velocity or force the particle then never meets a copy again (an escape),
    which the cell walk would only find after ``MAX_CELLS_PER_FLIGHT`` empty cells.
    """
    reach = 0.0
    for e in range(params.shape[0]):
        reach = max(reach, params[e, 2])
    return y > top + reach


def kernel_flags(has_force, noslip, lattice, mode, disks=False, walls=False, flight=0, mixed=False):
    """The variant key for a scene: what its kernel needs, fixed at compile time."""
    return (bool(has_force), bool(noslip), bool(lattice), int(mode), bool(disks), bool(walls), int(flight),
            bool(mixed))


@functools.cache
def orbit_kernel(spin=None, lattice=None, mode=None, disks=None, walls=None, flight=None, mixed=None):
    """The event loop compiled for one kind of scene: a scene pays only for what it needs.

    The arguments are the slots of a :class:`variant.Variant`
    (``orbit_kernel(*variant)``).  Each is a compile-time constant
    (``True``/``False``, a record mode, a flight), so the compiler drops the
    code a scene cannot reach: the cubic and quartic exits without a force,
    the spin update for specular laws, the cell walk for plain scenes, the
    recorder when nothing is recorded.  A slot left ``None`` is read from the
    arguments at run time; ``orbit_kernel()`` is the general path
    (:data:`run_orbit`).  A combination no scene has raises ``ValueError``
    (:func:`variant.normalise`).  Every variant makes the same
    floating-point operations on the scenes it serves, so results are
    identical to the general path's, bit for bit.

    ``disks=True`` (disjoint disks on a lattice, no force: the Sinai torus,
    the Lorentz gas with one or several disks per cell) selects another loop,
    :func:`disks.disk_lattice_kernel`,
    with the same arguments and outputs; it skips what such a scene cannot
    need and agrees with the general path to rounding, not bit for bit.

    ``walls=False`` (no element flagged ``layout.LONG_WALL``: every polygon,
    box or disk table whose walls are short against its smallest feature)
    compiles the loop without the long-wall check (:func:`events.exact_line_hit`);
    ``True`` or ``None`` test each line or segment hit for the flag.  The
    check's code alone, never run, cost such scenes 2 to 20 % (the Galton
    board the most; ``benchmarks/RESULTS.md``).

    ``flight`` (:mod:`variant`): ``STRAIGHT`` flies straight lines (no
    force), ``FORCE`` free fall under the force ``ax, ay``, ``THERMOSTAT``
    the force with the Gaussian isokinetic thermostat (:mod:`thermostat`,
    :mod:`thermo_flight`), ``MAGNETIC`` turns the velocity at the cyclotron
    frequency ``W`` of a field normal to the table (:mod:`magnetic_flight`;
    never with a force); ``None`` reads ``ax, ay``, the ``thermostat`` and
    ``W`` arguments.  A variant compiles no code of a flight it cannot fly:
    each of their branches opens with a compile-time constant
    (:func:`variant.flight_switches`: ``THERMO_ANY``, ``MAG_ANY``, ...), which
    numba prunes before typing (and a fixed flight prunes the free fall
    likewise).  Both closed-form flights search their events with
    :func:`search.event_search`.

    ``mixed=True`` (a table whose elements do not all share one law) gives each
    collision, the corner rule's included, the law of the element hit,
    ``params[e, layout.ELEMENT_LAW]``; ``None`` does so when the ``law``
    argument is ``layout.PER_ELEMENT``; ``False`` compiles none of it (its
    branches open with the constant ``MIXED_ANY``), so a table of one law runs
    the code it ran before per-element laws existed, bit for bit.  A mixed
    table has a no-slip element, so ``mixed=True`` needs the spin
    (``spin=False`` is the specular law everywhere, whatever the table says).
    """
    variant = normalise(spin, lattice, mode, disks, walls, flight, mixed)  # raises on impossible combinations
    if variant.disks:
        return disk_lattice_kernel(spin, mode)
    VARIANT = variant_code(variant)  # reported with results
    spin, lattice, mode, disks, walls, flight, mixed = variant
    # the flights: each branch of one opens with one of these constants (never a thermostat or field for nothing)
    FORCE_RT, FORCE, THERMO_ANY, THERMO_ALWAYS, THERMO_RT, MAG_ANY, MAG_ALWAYS, FAR_MOVE = flight_switches(variant)
    SPIN_RT = spin is None
    SPIN = bool(spin)
    LATTICE_RT = lattice is None
    LATTICE = bool(lattice)
    LATTICE_ALWAYS = lattice is True  # branches open with these constants: numba prunes them before typing
    MODE_RT = mode is None
    MODE = RECORD_LOG if mode is None else int(mode)
    WALLS = walls is None or bool(walls)  # a compile-time constant: False drops the long-wall check
    # per-element laws: compiled in only where a table may mix them
    MIXED_ANY = mixed is not False
    MIXED_ALWAYS = mixed is True
    # the law argument read at run time (PER_ELEMENT for a mixed table); spin=False is the specular law throughout
    LAW_KEPT = SPIN_RT or (SPIN and MIXED_ANY)

    @jit
    def run_orbit(kinds, params, copies, A, B, lattice, jstart, jpts, law, c, s, ax, ay, thermostat, x, y, vx, vy, w,
                  max_collisions, max_time, stop_below, scale, mode, rec, mask, start_element=-1, ceiling=INF, W=0.0):
        """Run one orbit from a state strictly inside the table.

        Parameters
        ----------
        kinds, params : arrays
            Scene elements (see :mod:`noslipsim.core.layout`).
        copies : int64 array (K, 3)
            Element copies ``(element, o1, o2)`` that reach a cell; a plain scene
            lists each element once with zero offsets.
        A, B : float64 arrays (2, 2)
            Lattice vectors as columns and the inverse matrix (zeros for plain scenes).
        lattice : bool
            Walk cells (periodic scene) or not.
        jstart, jpts : arrays
            Junction points of element ``e`` (in its own frame) are
            ``jpts[jstart[e]:jstart[e + 1]]``; the corner pass runs only for hits
            near one (:mod:`noslipsim.junctions`).
        law : int
            ``SPECULAR`` or ``NOSLIP``, or ``PER_ELEMENT``: each collision by the
            law of the element hit, ``params[e, ELEMENT_LAW]`` (a mixed table);
            ``c, s`` are the no-slip coefficients.
        ax, ay : float
            Constant acceleration (force per unit mass).
        thermostat : bool
            Fly the force with the Gaussian isokinetic thermostat (speed kept in
            flight; :mod:`noslipsim.core.thermostat`) instead of free fall.
        x, y, vx, vy, w : float
            Initial position (in cell 0), velocity and scaled spin ``w = gamma R omega``.
        max_collisions : int
            Stop after this many collisions (corner collisions included).
        max_time : float
            Stop at this time (the state is advanced to it); ``inf`` for none.
        stop_below : float
            Stop when the particle crosses this height downwards; ``-inf`` for none.
        scale : float
            Length scale of the scene, for the relative tolerances.
        mode : int
            ``RECORD_NONE``, ``RECORD_LOG`` or ``RECORD_PORTRAIT``.
        rec : float64 array
            Output rows for the records (as many as fit are written).
        mask : bool array (n_elements,)
            Elements whose collisions a portrait records.
        start_element : int
            ``-1`` for a start strictly inside the table; otherwise the particle
            starts on this element (in cell 0) as if just reflected by it, so its
            ``t = 0`` root is deflated (boundary initial conditions).
        ceiling : float
            The top of a bounded lattice (``Scene.top``) relative to the start
            cell: element copies (circles) whose centre lies above it do not
            exist; ``inf`` (the default) for an unbounded lattice or a plain scene.
            Not supported with the thermostat (``Scene`` refuses the pair).
        W : float
            The cyclotron angular frequency of a magnetic field normal to the
            table (``Scene.magnetic``; 0 for none; never with a force).  A
            magnetic orbit whose closed path meets nothing stops ``pinned``.

        Returns
        -------
        n, stop, n_corner, n_rec, t, x, y, vx, vy, w, m1, m2, variant
            Collision count, stop code, corner collisions, records written, the
            final state with unfolded position and cell indices, and the variant
            this code was compiled for (:func:`variant.report`).
        """
        has_force = (ax != 0.0 or ay != 0.0) if FORCE_RT else FORCE
        law = law if LAW_KEPT else (NOSLIP if SPIN else SPECULAR)
        lattice = lattice if LATTICE_RT else LATTICE
        mode = mode if MODE_RT else MODE
        # thermostatted flights keep |v| and w, collisions |v|^2 + w^2: no potential energy to keep
        thermo = False
        potential = has_force
        E = 0.0
        if THERMO_ANY:
            thermo = has_force and (thermostat if THERMO_RT else True)
            if thermo:
                potential = False
                E = field(ax, ay)[0]
        mag = False
        pin = INF  # a magnetic path is closed: what it has not met in one period it never meets
        if MAG_ANY:
            mag = MAG_ALWAYS or W != 0.0
            if mag:
                pin = magnetic_period(W)
        # the energy to keep (energy.settle), twice the start's (gamma = 0 keeps the spin's apart, as specular)
        mixes = law != SPECULAR and s != 0.0  # the spin takes part in the energy exchange (some no-slip element)
        e0 = state_energy(vx, vy, w, mixes, ax, ay, x, y, potential)[0]
        how = settle_mode(potential, mixes, thermo or mag)  # where a correction goes (energy.settle)
        t = 0.0
        cur_e = start_element
        cur_o1 = 0
        cur_o2 = 0
        m1 = 0
        m2 = 0
        ox = 0.0
        oy = 0.0
        n = 0
        n_rec = 0
        n_corner = 0
        stop = STOP_MAX_COLLISIONS
        # the energy measured and given back every SETTLE_EVERY collisions (energy.settle), at the end of the
        # collision that reaches settle_next (corner bounces may step past it), with that collision's normal: a
        # value of one pass, never carried to the next (carried, and the settle in a loop around the collision
        # loop, the no-slip Galton board ran 6 to 12 % slower; benchmarks/RESULTS.md)
        settle_next = SETTLE_EVERY
        while True:  # around the collision loop: only for a far hit's moved start
            while n < max_collisions:
                length = max(scale, abs(x), abs(y))
                extent_tol = EXTENT_TOL * length
                remaining = max_time - t
                t_level = INF
                pinned = False
                if THERMO_ALWAYS or (THERMO_ANY and thermo):
                    fl = (thermo_path(x, y, vx, vy, ax, ay), E)
                    if stop_below > -INF:
                        t_level = thermo_line_exit(fl, y + oy - stop_below, 0.0, 1.0)
                elif MAG_ALWAYS or (MAG_ANY and mag):
                    mf = (x, y, vx, vy, W)
                    if stop_below > -INF:
                        t_level = magnetic_line_exit(mf, y + oy - stop_below, 0.0, 1.0)
                elif stop_below > -INF:
                    t_level = quadratic_exit(y + oy - stop_below, vy, 0.5 * ay, INF)
                if THERMO_ALWAYS or (THERMO_ANY and thermo):
                    if lattice:
                        limit = min(remaining, t_level)
                        t_hit, e, o1, o2, status = thermo_walk_hit(kinds, params, copies, A, B, fl, cur_e, cur_o1,
                                                                   cur_o2, limit, extent_tol, MAX_CELLS_PER_FLIGHT)
                        escape = status == 2 or (status == 1 and limit == INF)
                    else:
                        t_hit, e, o1, o2 = thermo_hit_in_cell(kinds, params, copies, A, 0, 0, fl, cur_e, cur_o1,
                                                              cur_o2, INF, extent_tol, 0.0, False)
                        escape = e < 0
                    if e == SEARCH_FAILED:  # the circle search gave up: stop here, never fly past a hit
                        stop = STOP_SEARCH_LIMIT
                        break
                elif MAG_ALWAYS or (MAG_ANY and mag):
                    escape = False
                    if lattice:  # the walk follows one period at most
                        limit = min(remaining, t_level, pin)
                        t_hit, e, o1, o2, status = magnetic_walk_hit(kinds, params, copies, A, B, mf, cur_e, cur_o1,
                                                                     cur_o2, limit, extent_tol, MAX_CELLS_PER_FLIGHT)
                        escape = status == 2
                        pinned = status == 1 and limit == pin
                    else:
                        t_hit, e, o1, o2 = magnetic_hit_in_cell(kinds, params, copies, A, 0, 0, mf, cur_e, cur_o1,
                                                                cur_o2, INF, extent_tol, 0.0, False)
                        pinned = e < 0
                elif LATTICE_ALWAYS or (LATTICE_RT and lattice):
                    limit = min(remaining, t_level)
                    if ceiling < INF and vy >= 0.0 and ay >= 0.0 and _above_top(params, y, ceiling - oy):
                        t_hit, e, o1, o2, status = INF, -1, 0, 0, 2  # rising above a bounded lattice for good
                    else:
                        t_hit, e, o1, o2, status = walk_hit(kinds, params, copies, A, B, x, y, vx, vy, ax, ay,
                                                            has_force, cur_e, cur_o1, cur_o2, limit, extent_tol,
                                                            MAX_CELLS_PER_FLIGHT, ceiling - oy)
                    # status 2 with t_hit finite (a hit after the walk got FAR_CELLS from the start, under a
                    # force) leaves as an escape: the outer loop moves the start near the hit (far_move, below)
                    escape = status == 2 or (status == 1 and limit == INF)
                else:
                    t_hit, e, o1, o2 = hit_in_cell(kinds, params, copies, A, 0, 0, x, y, vx, vy, ax, ay,
                                                   has_force, cur_e, cur_o1, cur_o2, INF, extent_tol, 0.0, False)
                    escape = e < 0  # no element ahead: the orbit leaves for good
                if t_level < INF and t_level <= t_hit and t_level <= remaining:
                    if THERMO_ALWAYS or (THERMO_ANY and thermo):
                        x, y, vx, vy = thermo_state(fl, t_level)
                    elif MAG_ALWAYS or (MAG_ANY and mag):
                        x, y, vx, vy = magnetic_state(mf, t_level)
                    else:
                        x, y, vx, vy = advance(x, y, vx, vy, ax, ay, t_level, has_force)
                    y = stop_below - oy
                    t += t_level
                    stop = STOP_LEVEL
                    break
                if escape:
                    stop = STOP_ESCAPE
                    break
                if pinned:  # a closed cyclotron path that meets nothing: it circles for ever
                    stop = STOP_PINNED
                    break
                if e < 0 or t_hit > remaining:
                    if THERMO_ALWAYS or (THERMO_ANY and thermo):
                        x, y, vx, vy = thermo_state(fl, remaining)
                    elif MAG_ALWAYS or (MAG_ANY and mag):
                        x, y, vx, vy = magnetic_state(mf, remaining)
                    else:
                        x, y, vx, vy = advance(x, y, vx, vy, ax, ay, remaining, has_force)
                    t = max_time
                    stop = STOP_MAX_TIME
                    break
                # relocate onto the element copy, then resolve the collision
                if THERMO_ALWAYS or (THERMO_ANY and thermo):
                    hx, hy, vx_in, vy_in = thermo_state(fl, t_hit)
                elif MAG_ALWAYS or (MAG_ANY and mag):
                    hx, hy, vx_in, vy_in = magnetic_state(mf, t_hit)
                else:
                    hx, hy, vx_in, vy_in = advance(x, y, vx, vy, ax, ay, t_hit, has_force)
                kind = kinds[e]
                p = params[e]
                sx, sy = copy_shift(A, o1, o2, lattice)
                rx = hx - sx
                ry = hy - sy
                # a straight flight's far hit: eps x flight length (under a force no far hit comes here: the walk
                # reports it as an escape with a finite time, and the outer loop moves the start near it)
                far = lattice and not has_force and not mag and max(abs(o1), abs(o2)) >= FAR_CELLS
                if far:
                    rx, ry = far_hit_point(kind, p, A, o1, o2, x, y, vx, vy, t_hit)
                px, py, nx, ny = place_on_element(kind, p, rx, ry)
                if THERMO_ALWAYS or (THERMO_ANY and thermo):
                    if WALLS and p[LONG_WALL] != 0.0:
                        t_hit, px, py, vx_in, vy_in = thermo_exact_line_hit(
                            kind, p, fl, sx, sy, e == cur_e and o1 == cur_o1 and o2 == cur_o2, t_hit, rx, ry, px, py,
                            vx_in, vy_in)
                elif MAG_ALWAYS or (MAG_ANY and mag):
                    if WALLS and p[LONG_WALL] != 0.0:
                        t_hit, px, py, vx_in, vy_in = magnetic_exact_line_hit(
                            kind, p, mf, sx, sy, e == cur_e and o1 == cur_o1 and o2 == cur_o2, t_hit, rx, ry, px, py,
                            vx_in, vy_in)
                elif WALLS and p[LONG_WALL] != 0.0 and not far:  # a long line or segment: eps x distance along it
                    t_hit, px, py, vx_in, vy_in = exact_line_hit(
                        kind, p, x - sx, y - sy, vx, vy, ax, ay, has_force,
                        e == cur_e and o1 == cur_o1 and o2 == cur_o2,
                        t_hit, rx, ry, px, py, vx_in, vy_in)
                x = px + sx
                y = py + sy
                if lattice:  # re-base onto the cell that now holds the particle
                    if far:  # from the hit seen from its copy: px + sx - k a would carry eps |sx|, the flight's length
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
                law_e = law
                if MIXED_ANY:  # a mixed table: the law of the element hit
                    if MIXED_ALWAYS or law == PER_ELEMENT:
                        law_e = int(p[ELEMENT_LAW])
                vx, vy, w_out = collide(law_e, c, s, vx_in, vy_in, w, nx, ny)
                t += t_hit
                if mode != RECORD_NONE:
                    n_rec = record(mode, rec, n_rec, mask, t, x, y, ox, oy, m1, m2, vx, vy, w_out, vx_in, vy_in, w,
                                    kind, p, sx, sy, e, 0.0, nx, ny)
                w = w_out
                n += 1
                cur_e = e
                cur_o1 = o1
                cur_o2 = o2
                # corner rule: other element copies touched here that the particle would leave through;
                # a thermostatted flight leaves a contact with its acceleration there, F - alpha v, a magnetic one
                # with W J v
                aex = ax
                aey = ay
                bounces = 0
                near = _near_junction(jstart, jpts, e, x - sx, y - sy, JUNCTION_GATE * length)
                while near and n < max_collisions:
                    if THERMO_ALWAYS or (THERMO_ANY and thermo):
                        aex, aey = drag(vx, vy, ax, ay)
                    elif MAG_ALWAYS or (MAG_ANY and mag):
                        aex, aey = -W * vy, W * vx
                    j, o1, o2 = _contact(kinds, params, copies, A, lattice, x, y, vx, vy, aex, aey,
                                         cur_e, cur_o1, cur_o2, CONTACT_TOL * length, ceiling - oy)
                    if j < 0:
                        break
                    bounces += 1
                    if bounces > MAX_CORNER_BOUNCES:
                        stop = STOP_CORNER
                        break
                    kind = kinds[j]
                    p = params[j]
                    sx, sy = copy_shift(A, o1, o2, lattice)
                    nx, ny = place_on_element(kind, p, x - sx, y - sy)[2:]
                    vx_in = vx
                    vy_in = vy
                    law_e = law
                    if MIXED_ANY:
                        if MIXED_ALWAYS or law == PER_ELEMENT:
                            law_e = int(p[ELEMENT_LAW])
                    vx, vy, w_out = collide(law_e, c, s, vx_in, vy_in, w, nx, ny)
                    if mode != RECORD_NONE:
                        n_rec = record(mode, rec, n_rec, mask, t, x, y, ox, oy, m1, m2, vx, vy, w_out, vx_in, vy_in,
                                        w, kind, p, sx, sy, j, 1.0, nx, ny)
                    w = w_out
                    n += 1
                    n_corner += 1
                    cur_e = j
                    cur_o1 = o1
                    cur_o2 = o2
                if stop == STOP_CORNER:
                    break
                sx, sy = copy_shift(A, cur_o1, cur_o2, lattice)
                if THERMO_ALWAYS or (THERMO_ANY and thermo):
                    aex, aey = drag(vx, vy, ax, ay)
                elif MAG_ALWAYS or (MAG_ANY and mag):
                    aex, aey = -W * vy, W * vx
                if slides_off(kinds[cur_e], params[cur_e], x - sx, y - sy, vx, vy, aex, aey):
                    stop = STOP_GRAZING
                    break
                if n >= settle_next and n < max_collisions:  # (none after the last collision, as before)
                    if MIXED_ANY and mixes and law_e == SPECULAR:  # a specular element of a mixed table: the spin
                        vx, vy, w = settle_velocity(vx, vy, w, mixes, ax, ay, x + ox, y + oy, potential, e0, how)
                    else:                                          # keeps its bits (energy.settle_velocity)
                        vx, vy, w = settle(vx, vy, w, mixes, ax, ay, x + ox, y + oy, potential, e0, how, nx, ny)
                    settle_next = n + SETTLE_EVERY
            if FAR_MOVE and stop == STOP_ESCAPE and t_hit < INF and has_force and lattice:
                # a far hit under a force (walk status 2, t_hit finite): the plain hit point would carry eps x the
                # flight's length.  The start moves exactly to shortly before the hit (in free space: no
                # collision, no record), re-based onto the cell reached, and the collision loop finds the
                # hit from there, near; or, with max_time before that, to max_time, where the orbit stops
                remaining = max_time - t
                t_move, k1, k2, x, y, vx, vy = far_move(A, B, x, y, vx, vy, ax, ay, t_hit, remaining)
                m1 += k1
                m2 += k2
                ox, oy = lattice_shift(A, m1, m2)
                cur_e = -1  # in free space: no root at the start to deflate
                cur_o1 = 0
                cur_o2 = 0
                if t_move < remaining:  # on to the hit
                    t += t_move
                    stop = STOP_MAX_COLLISIONS
                    continue
                t = max_time
                stop = STOP_MAX_TIME
            break
        if lattice:  # the final state may lie in another cell (a stop in mid-flight)
            k1, k2 = nearest_cell(B, x, y)
            m1 += k1
            m2 += k2
        return n, stop, n_corner, n_rec, t, x + ox, y + oy, vx, vy, w, m1, m2, (VARIANT << 32) | SOURCE_STAMP

    return run_orbit


#: The general path: every flag read at run time.
run_orbit = orbit_kernel()

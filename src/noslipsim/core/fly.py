"""One flight of the event loop, for each kind of flight: from a collision to the next event.

:func:`flight_step` builds, from five functions of a flight, the step that takes the state after
a collision to the next event: the stop level's time, the next hit (:mod:`search`, :mod:`cells`),
the stops that come before it (the level, an escape, a closed path that meets nothing, the time
limit, a search that gave up), and at a hit the state there placed on the element copy
(:func:`geometry.place_on_element`) with a long wall's hit redone from its exact distance.

Every step returns the same tuple, whatever its flight, so the event loop calls the one its
variant flies (:func:`loop.orbit_kernel`):
``(stop, t, e, o1, o2, x, y, vx, vy, nx, ny, sx, sy, far)``.  ``stop >= 0`` is a stop code: ``(x, y,
vx, vy)`` is the state there, ``t`` the time flown (the time limit's: the limit itself), and for
an escape under a force ``t`` the time of a far hit (:func:`cells.far_move`).  ``stop = -1`` is a
hit at time ``t`` on copy ``(e, o1, o2)`` shifted by ``(sx, sy)``: ``(x, y)`` the hit point relative
to the copy, ``(vx, vy)`` the velocity arriving, ``(nx, ny)`` the normal; ``far`` a straight
flight's hit 16 or more cells away, placed from its exact point (:func:`cells.far_hit_point`).
"""
import functools
import math

from . import free_flight, magnetic_flight, thermo_flight
from .cells import FAR_CELLS, far_hit_point, lattice_walk
from .events import exact_line_hit
from .geometry import copy_shift, place_on_element
from .jit import OUT_OF_LINE, jit
from .layout import LONG_WALL, STOP_ESCAPE, STOP_LEVEL, STOP_MAX_TIME, STOP_PINNED, STOP_SEARCH_LIMIT
from .magnetic import period as magnetic_period
from .roots import quadratic_exit
from .search import SEARCH_FAILED, box_search, cell_search, event_search, long_wall_hit
from .thermostat import field
from .thermostat import flight as thermo_path
from .tolerances import MAX_CELLS_PER_FLIGHT

INF = math.inf
#: ``stop`` of a flight that ends on a hit.
HIT = -1


@jit(inline="always")
def stop_before_hit(t_level, t_hit, remaining, e, escape, pinned, failed):
    """The stop code of the event that comes before the hit (in this order), or :data:`HIT`."""
    if failed:
        return STOP_SEARCH_LIMIT
    if t_level < INF and t_level <= t_hit and t_level <= remaining:
        return STOP_LEVEL
    if escape:
        return STOP_ESCAPE
    if pinned:
        return STOP_PINNED
    return STOP_MAX_TIME if e < 0 or t_hit > remaining else HIT


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


def flight_step(begin, level_exit, search, state_at, land):
    """The flight step (module docstring) from a flight's functions.

    ``begin(x, y, vx, vy, ax, ay, has_force, E, W)``: the flight's state ``F``;
    ``level_exit(F, f0)``: the first time ``y`` falls by ``f0``;
    ``search(kinds, params, copies, A, B, lattice, F, cur_e, cur_o1, cur_o2, limit, extent_tol, pin, top)``:
    ``(t, e, o1, o2, escape, pinned, failed)``;
    ``state_at(F, t)``; ``land(kind, p, A, lattice, F, o1, o2, deflated, t, hx, hy, vx, vy, extent_tol)``:
    the hit placed, ``(t, x, y, vx, vy, nx, ny, sx, sy, far)``.
    """
    @jit(inline="always")
    def fly(kinds, params, copies, A, B, lattice, x, y, vx, vy, ax, ay, has_force, E, W, pin, cur_e, cur_o1,
            cur_o2, remaining, stop_below, oy, top, extent_tol):
        F = begin(x, y, vx, vy, ax, ay, has_force, E, W)
        t_level = level_exit(F, y + oy - stop_below) if stop_below > -INF else INF
        limit = min(remaining, t_level)
        t_hit, e, o1, o2, escape, pinned, failed = search(kinds, params, copies, A, B, lattice, F, cur_e, cur_o1,
                                                          cur_o2, limit, extent_tol, pin, top)
        stop = stop_before_hit(t_level, t_hit, remaining, e, escape, pinned, failed)
        if stop == STOP_LEVEL:
            qx, qy, qvx, qvy = state_at(F, t_level)
            return stop, t_level, e, o1, o2, qx, stop_below - oy, qvx, qvy, 0.0, 0.0, 0.0, 0.0, False
        if stop == STOP_MAX_TIME:
            qx, qy, qvx, qvy = state_at(F, remaining)
            return stop, remaining, e, o1, o2, qx, qy, qvx, qvy, 0.0, 0.0, 0.0, 0.0, False
        if stop != HIT:
            return stop, t_hit, e, o1, o2, x, y, vx, vy, 0.0, 0.0, 0.0, 0.0, False
        hx, hy, vx_in, vy_in = state_at(F, t_hit)
        t_hit, px, py, vx_in, vy_in, nx, ny, sx, sy, far = land(
            kinds[e], params[e], A, lattice, F, o1, o2, e == cur_e and o1 == cur_o1 and o2 == cur_o2, t_hit, hx, hy,
            vx_in, vy_in, extent_tol)
        return HIT, t_hit, e, o1, o2, px, py, vx_in, vy_in, nx, ny, sx, sy, far

    return fly


# ---------------------------------------------------------------------------- free flight
@jit(inline="always")
def _free_begin(x, y, vx, vy, ax, ay, has_force, E, W):
    return x, y, vx, vy, ax, ay


@jit(inline="always")
def _free_level(F, f0):
    return quadratic_exit(f0, F[3], 0.5 * F[5], INF)


@functools.cache
def free_search(LATTICE_ALWAYS, LATTICE_RT, OPEN_ENDS, FALLING):
    """Free flight's next hit: the cell walk on a lattice (``LATTICE_*``: compile-time), else one cell;
    ``OPEN_ENDS``: the open-end rule compiled in (:func:`search.cell_search`); ``FALLING``: under the force
    (a constant: :mod:`free_flight`)."""
    hit_in_cell = cell_search(free_flight.free_flight(FALLING), open_ends=OPEN_ENDS)
    walk_hit = lattice_walk(OPEN_ENDS, FALLING)

    @jit(inline="always")
    def search(kinds, params, copies, A, B, lattice, F, cur_e, cur_o1, cur_o2, limit, extent_tol, pin, top):
        x, y, vx, vy, ax, ay = F
        if LATTICE_ALWAYS or (LATTICE_RT and lattice):
            if top < INF and vy >= 0.0 and ay >= 0.0 and _above_top(params, y, top):
                return INF, -1, 0, 0, True, False, False  # rising above a bounded lattice for good
            t_hit, e, o1, o2, status = walk_hit(kinds, params, copies, A, B, x, y, vx, vy, ax, ay, cur_e, cur_o1,
                                                cur_o2, limit, extent_tol, MAX_CELLS_PER_FLIGHT, top)
            # status 2 with t_hit finite (a hit after the walk got FAR_CELLS from the start, under a force) leaves
            # as an escape: the event loop moves the start near the hit (cells.far_move)
            return t_hit, e, o1, o2, status == 2 or (status == 1 and limit == INF), False, False
        t_hit, e, o1, o2 = hit_in_cell(kinds, params, copies, A, 0, 0, F, cur_e, cur_o1, cur_o2, INF, extent_tol,
                                       0.0, False)
        return t_hit, e, o1, o2, e < 0, False, False  # no element ahead: the orbit leaves for good

    return search


@functools.cache
def free_land(WALLS, FALLING):
    """Free flight's hit placed: a far straight hit from its exact point; a long wall's (``WALLS``) redone."""
    @jit(inline="always")
    def land(kind, p, A, lattice, F, o1, o2, deflated, t_hit, hx, hy, vx_in, vy_in, extent_tol):
        x, y, vx, vy, ax, ay = F
        sx, sy = copy_shift(A, o1, o2, lattice)
        rx = hx - sx
        ry = hy - sy
        # a straight flight's far hit: eps x flight length (under a force no far hit comes here: the walk
        # reports it as an escape with a finite time, and the event loop moves the start near it)
        far = False
        if not FALLING:
            far = lattice and max(abs(o1), abs(o2)) >= FAR_CELLS
            if far:
                rx, ry = far_hit_point(kind, p, A, o1, o2, x, y, vx, vy, t_hit)
        px, py, nx, ny = place_on_element(kind, p, rx, ry)
        if WALLS and p[LONG_WALL] != 0.0 and not far:  # a long line or segment: eps x distance along it
            t_hit, px, py, vx_in, vy_in = exact_line_hit(kind, p, x - sx, y - sy, vx, vy, ax, ay, FALLING, deflated,
                                                         t_hit, rx, ry, px, py, vx_in, vy_in)
        return t_hit, px, py, vx_in, vy_in, nx, ny, sx, sy, far

    return land


# ---------------------------------------------------------------------------- closed-form flights
@functools.cache
def closed_form_search(flight, pinning, LATTICE_ALWAYS, LATTICE_RT, OPEN_ENDS):
    """A closed-form flight's next hit (:func:`search.event_search`); ``pinning``: its path is closed (one period
    ``pin`` searched at most, on a lattice over the cells its box covers where they are few,
    :func:`search.box_search`; a miss is a path that meets nothing); ``LATTICE_*``, ``OPEN_ENDS`` as for free
    flight (a plain table compiles no walk); no copy above ``top``, a bounded lattice's top."""
    # a lattice read at run time (the general kernel: tests and ablations) calls the searches out of line: the
    # same bits for a fraction of the compile
    compile = OUT_OF_LINE if LATTICE_RT else jit
    hit_in_cell, walk_hit, _ = event_search(flight, compile=compile, open_ends=OPEN_ENDS)
    box_hit = box_search(flight, compile=compile, open_ends=OPEN_ENDS) if pinning else None

    @jit(inline="always")
    def search(kinds, params, copies, A, B, lattice, F, cur_e, cur_o1, cur_o2, limit, extent_tol, pin, top):
        if LATTICE_ALWAYS or (LATTICE_RT and lattice):
            limit = min(limit, pin)
            status = 2
            if pinning:  # a closed path over a few cells: search them all
                t_hit, e, o1, o2, status = box_hit(kinds, params, copies, A, B, F, cur_e, cur_o1, cur_o2, limit,
                                                   extent_tol, top)
            if status == 2:
                t_hit, e, o1, o2, status = walk_hit(kinds, params, copies, A, B, F, cur_e, cur_o1, cur_o2, limit,
                                                    extent_tol, MAX_CELLS_PER_FLIGHT, top)
            if pinning:
                return t_hit, e, o1, o2, status == 2, status == 1 and limit == pin, False
            return t_hit, e, o1, o2, status == 2 or (status == 1 and limit == INF), False, e == SEARCH_FAILED
        t_hit, e, o1, o2 = hit_in_cell(kinds, params, copies, A, 0, 0, F, cur_e, cur_o1, cur_o2, INF, extent_tol,
                                       0.0, False)
        return t_hit, e, o1, o2, e < 0 and not pinning, e < 0 and pinning, e == SEARCH_FAILED

    return search


@functools.cache
def closed_form_land(flight, WALLS):
    """A closed-form flight's hit placed, a long wall's (``WALLS``) redone (:func:`search.long_wall_hit`)."""
    exact_hit = long_wall_hit(flight)

    @jit(inline="always")
    def land(kind, p, A, lattice, F, o1, o2, deflated, t_hit, hx, hy, vx_in, vy_in, extent_tol):
        sx, sy = copy_shift(A, o1, o2, lattice)
        rx = hx - sx
        ry = hy - sy
        px, py, nx, ny = place_on_element(kind, p, rx, ry)
        if WALLS and p[LONG_WALL] != 0.0:
            t_hit, px, py, vx_in, vy_in = exact_hit(kind, p, F, sx, sy, deflated, t_hit, rx, ry, px, py, vx_in, vy_in)
        return t_hit, px, py, vx_in, vy_in, nx, ny, sx, sy, False

    return land


@jit(inline="always")
def _thermo_begin(x, y, vx, vy, ax, ay, has_force, E, W):
    return thermo_path(x, y, vx, vy, ax, ay), E


@jit(inline="always")
def _thermo_level(F, f0):
    return thermo_flight.line_exit(F, f0, 0.0, 1.0)


@jit(inline="always")
def _magnetic_begin(x, y, vx, vy, ax, ay, has_force, E, W):
    return x, y, vx, vy, W


@jit(inline="always")
def _magnetic_level(F, f0):
    return magnetic_flight.line_exit(F, f0, 0.0, 1.0)


@functools.cache
def choose_flight(switches, LATTICE_ALWAYS, LATTICE_RT, WALLS, OPEN_ENDS):
    """``fly(thermo, mag, ...)``: the one place a flight is chosen, for a variant's constants.

    ``switches``: the variant's :class:`variant.FlightSwitches`; ``thermo``, ``mag``, ``has_force``: the orbit's
    run-time choice (:func:`flight_setup`), read only where a switch leaves it open.  Each branch opens with a
    constant captured here, so numba prunes the flights a variant cannot fly before typing them (a switch
    passed in a tuple or a run-time variable would be typed and compiled on both sides).  The force is a constant
    of each free flight (:mod:`free_flight`), so straight and falling are two steps.
    """
    FORCE_RT, FORCE, THERMO_ANY, THERMO_ALWAYS, _, MAG_ANY, MAG_ALWAYS, _ = switches
    straight, falling = (flight_step(_free_begin, _free_level, free_search(LATTICE_ALWAYS, LATTICE_RT, OPEN_ENDS, f),
                                     free_flight.free_flight(f).state_at, free_land(WALLS, f)) for f in (False, True))
    thermostatted = flight_step(
        _thermo_begin, _thermo_level, closed_form_search(thermo_flight, False, LATTICE_ALWAYS, LATTICE_RT, OPEN_ENDS),
        thermo_flight.state_at, closed_form_land(thermo_flight, WALLS))
    magnetic = flight_step(
        _magnetic_begin, _magnetic_level, closed_form_search(magnetic_flight, True, LATTICE_ALWAYS, LATTICE_RT,
                                                             OPEN_ENDS),
        magnetic_flight.state_at, closed_form_land(magnetic_flight, WALLS))

    @jit(inline="always")
    def fly(thermo, mag, kinds, params, copies, A, B, lattice, x, y, vx, vy, ax, ay, has_force, E, W, pin, cur_e,
            cur_o1, cur_o2, remaining, stop_below, oy, top, extent_tol):
        if THERMO_ALWAYS or (THERMO_ANY and thermo):
            return thermostatted(kinds, params, copies, A, B, lattice, x, y, vx, vy, ax, ay, has_force, E, W, pin,
                                 cur_e, cur_o1, cur_o2, remaining, stop_below, oy, top, extent_tol)
        if MAG_ALWAYS or (MAG_ANY and mag):
            return magnetic(kinds, params, copies, A, B, lattice, x, y, vx, vy, ax, ay, has_force, E, W, pin, cur_e,
                            cur_o1, cur_o2, remaining, stop_below, oy, top, extent_tol)
        if FORCE or (FORCE_RT and has_force):
            return falling(kinds, params, copies, A, B, lattice, x, y, vx, vy, ax, ay, has_force, E, W, pin, cur_e,
                           cur_o1, cur_o2, remaining, stop_below, oy, top, extent_tol)
        return straight(kinds, params, copies, A, B, lattice, x, y, vx, vy, ax, ay, has_force, E, W, pin, cur_e,
                        cur_o1, cur_o2, remaining, stop_below, oy, top, extent_tol)

    return fly


@functools.cache
def flight_setup(THERMO_ANY, THERMO_RT, MAG_ANY, MAG_ALWAYS):
    """``setup(has_force, thermostat, ax, ay, W)``: ``(thermo, mag, potential, E, pin)`` for an orbit.

    ``thermo``/``mag``: the orbit flies the thermostat or the field (compiled in only where a variant
    may: ``THERMO_ANY``, ``MAG_ANY``); ``potential``: free fall keeps a potential energy (a
    thermostatted flight keeps ``|v|`` and ``w``, collisions ``|v|^2 + w^2``); ``E`` the thermostat's
    field strength; ``pin`` a magnetic path's period (what it has not met in one period it never meets).
    """
    @jit(inline="always")
    def setup(has_force, thermostat, ax, ay, W):
        thermo = False
        potential = has_force
        E = 0.0
        if THERMO_ANY:
            thermo = has_force and (thermostat if THERMO_RT else True)
            if thermo:
                potential = False
                E = field(ax, ay)[0]
        mag = False
        pin = INF
        if MAG_ANY:
            mag = MAG_ALWAYS or W != 0.0
            if mag:
                pin = magnetic_period(W)
        return thermo, mag, potential, E, pin

    return setup

"""The event loop: one orbit, collision after collision, as named steps.

1. fly (:mod:`fly`): the next hit, the earliest exit root over the element
   copies the flight can reach (:func:`search.cell_search`; on a lattice,
   cell by cell), the stops that come before it, and the relocation: the
   flight at that root projected onto the element
   (:func:`geometry.place_on_element`), so rounding never leaves the particle
   outside;
2. onto the cell (:func:`bounce.rebase`) and resolve: the collision law
   (:func:`laws.collide`), the record;
3. the corner pass (:func:`bounce.corner_pass`): every other element copy
   that touches the hit point (within ``CONTACT_TOL``) and whose supporting
   line or circle the new velocity leaves through is hit at once, in index
   order, each counted as a collision with ``corner = 1``; more than
   ``MAX_CORNER_BOUNCES`` in a row stop the orbit;
4. the grazing test and the settle (:mod:`bounce`).

Positions are relative to the particle's current lattice cell (plain scenes:
one cell, ``A = 0``) and flights start from the last collision; only the total
time is a running sum.
"""
import functools
import math

from .bounce import corner_pass, element_law, grazing, local_acceleration, rebase, settle_step
from .cells import far_move
from .disks import disk_lattice_kernel
from .energy import SETTLE_EVERY, settle_mode, state_energy
from .fly import HIT, choose_flight, flight_setup
from .geometry import lattice_shift, nearest_cell
from .jit import SOURCE_STAMP, jit
from .laws import collide
from .layout import (
    NOSLIP,
    RECORD_LOG,
    RECORD_NONE,
    SPECULAR,
    STOP_CORNER,
    STOP_ESCAPE,
    STOP_GRAZING,
    STOP_LEVEL,
    STOP_MAX_COLLISIONS,
    STOP_MAX_TIME,
)
from .records import record
from .tolerances import EXTENT_TOL
from .variant import WHOLE, flight_switches, normalise, variant_code

INF = math.inf
@functools.cache
def orbit_kernel(spin=None, lattice=None, mode=None, disks=None, walls=None, flight=None, mixed=None,
                 open_ends=None, settle=None):
    """The event loop compiled for one kind of scene: a scene pays only for what it needs.

    The arguments are the slots of a :class:`variant.Variant` (``orbit_kernel(*variant)``; each documented
    there).  Each is a compile-time constant, so numba drops the code a scene cannot reach: the cubic and
    quartic exits without a force, the spin update for specular laws, the cell walk for plain scenes, the
    recorder when nothing is recorded, the long-wall check (``walls=False``), the open-end rule
    (``open_ends=False``), the flights a variant cannot fly (:func:`fly.choose_flight`), per-element laws
    (``mixed=False``), the settle form not chosen (:func:`bounce.settle_step`).  A slot left ``None`` is
    read from the arguments at run time; ``orbit_kernel()`` is the general path (:data:`run_orbit`).  A
    combination no scene has raises ``ValueError`` (:func:`variant.normalise`).

    Every variant makes the same floating-point operations on the scenes it serves, so results are
    identical to the general path's, bit for bit.  ``disks=True`` selects another loop,
    :func:`disks.disk_lattice_kernel`, with the same arguments and outputs, which agrees with the general
    path to rounding only.  docs/algorithm.md, "Paying only for what a scene needs", has the measured gains.
    """
    variant = normalise(spin, lattice, mode, disks, walls, flight, mixed, open_ends, settle)  # raises on impossible
    if variant.disks:
        return disk_lattice_kernel(spin, mode)
    VARIANT = variant_code(variant)  # reported with results
    spin, lattice, mode, disks, walls, flight, mixed, open_ends, settle = variant
    # the flights: each branch of one opens with one of these constants (never a thermostat or field for nothing)
    switches = flight_switches(variant)
    FORCE_RT, FORCE, THERMO_ANY, THERMO_ALWAYS, THERMO_RT, MAG_ANY, MAG_ALWAYS, FAR_MOVE = switches
    SPIN_RT = spin is None
    SPIN = bool(spin)
    LATTICE_RT = lattice is None
    LATTICE = bool(lattice)
    LATTICE_ALWAYS = lattice is True  # branches open with these constants: numba prunes them before typing
    MODE_RT = mode is None
    MODE = RECORD_LOG if mode is None else int(mode)
    WALLS = walls is None or bool(walls)  # a compile-time constant: False drops the long-wall check
    OPEN_ENDS = open_ends is None or bool(open_ends)  # False drops the open-end rule (search.cell_search)
    # per-element laws: compiled in only where a table may mix them
    MIXED_ANY = mixed is not False
    MIXED_ALWAYS = mixed is True
    # the law argument read at run time (PER_ELEMENT for a mixed table); spin=False is the specular law throughout
    LAW_KEPT = SPIN_RT or (SPIN and MIXED_ANY)
    # the steps (fly.py, bounce.py), each compiled with the constants it reads
    setup = flight_setup(THERMO_ANY, THERMO_RT, MAG_ANY, MAG_ALWAYS)
    fly = choose_flight(switches, LATTICE_ALWAYS, LATTICE_RT, WALLS, OPEN_ENDS)  # the one place a flight is chosen
    law_of = element_law(MIXED_ANY, MIXED_ALWAYS)
    acceleration = local_acceleration(THERMO_ANY, THERMO_ALWAYS, MAG_ANY, MAG_ALWAYS)
    corners = corner_pass(law_of, acceleration)
    grazes = grazing(acceleration)
    settle_form, settled = settle_step(MIXED_ANY, settle == WHOLE, settle is None)

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
        thermo, mag, potential, E, pin = setup(has_force, thermostat, ax, ay, W)
        # the energy to keep (energy.settle), twice the start's (gamma = 0 keeps the spin's apart, as specular)
        mixes = law != SPECULAR and s != 0.0  # the spin takes part in the energy exchange (some no-slip element)
        e0 = state_energy(vx, vy, w, mixes, ax, ay, x, y, potential)[0]
        how = settle_mode(potential, mixes, thermo or mag)  # where a targeted correction goes (energy.settle)
        whole = settle_form(kinds, law, potential, mixes, thermo or mag)  # the whole-state settle, or the targeted
        t = 0.0
        t_hit = INF
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
                # next hit, and the stops that come before it (fly.py)
                remaining = max_time - t
                top = ceiling - oy
                extent_tol = EXTENT_TOL * length
                flown = fly(thermo, mag, kinds, params, copies, A, B, lattice, x, y, vx, vy, ax, ay, has_force, E, W,
                            pin, cur_e, cur_o1, cur_o2, remaining, stop_below, oy, top, extent_tol)
                stop, t_hit, e, o1, o2, px, py, vx_in, vy_in, nx, ny, sx, sy, far = flown
                if stop != HIT:
                    x, y, vx, vy = px, py, vx_in, vy_in
                    t = max_time if stop == STOP_MAX_TIME else (t + t_hit if stop == STOP_LEVEL else t)
                    break
                stop = STOP_MAX_COLLISIONS
                # onto the cell, then resolve the collision
                kind = kinds[e]
                p = params[e]
                x, y, sx, sy, o1, o2, m1, m2, ox, oy = rebase(A, B, lattice, far, px, py, sx, sy, o1, o2, m1, m2,
                                                              ox, oy)
                law_e = law_of(law, p)
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
                corner, vx, vy, w, n, n_rec, n_corner, cur_e, cur_o1, cur_o2, law_e, nx, ny = corners(
                    (kinds, params, copies, A, lattice, jstart, jpts), law, c, s, mode, rec, mask, t, x, y,
                    (m1, m2, ox, oy), vx, vy, w, n, n_rec, n_corner, (cur_e, cur_o1, cur_o2), sx, sy, length,
                    max_collisions, ceiling - oy, (thermo, mag, ax, ay, W), law_e, nx, ny)
                if corner:
                    stop = STOP_CORNER
                    break
                if grazes(kinds, params, A, lattice, cur_e, cur_o1, cur_o2, x, y, vx, vy, thermo, mag, ax, ay, W):
                    stop = STOP_GRAZING
                    break
                if n >= settle_next and n < max_collisions:  # (none after the last collision, as before)
                    vx, vy, w = settled(vx, vy, w, mixes, ax, ay, x + ox, y + oy, potential, e0, how, whole, law_e,
                                        nx, ny)
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

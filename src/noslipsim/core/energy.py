"""The energy an orbit starts with, kept: measured every ``SETTLE_EVERY`` collisions, given back when off.

In exact arithmetic a collision keeps ``|v|^2 + w^2`` (the no-slip law is a
rotation of ``(v_t, w)``, specular a reflection) and a flight under a constant
force keeps ``E = (|v|^2 + w^2)/2 - a . q``.  In floating point each collision
changes ``E`` by 1e-18 to 1e-16 relative, with a sign, so the error grew
linearly.  :func:`settle` measures ``E`` and, when it is off the start value
by more than ``SETTLE_AT``, scales a part ``p`` of ``(v, w)`` by ``1 + f`` to
give the excess back; every correction aims at the start value, so nothing
accumulates.  The part is where the rounding arose (:func:`settle_mode`), so
a component the dynamics keeps exactly keeps its bits; a kernel compiles that
targeted form only where its table keeps such an invariant
(:func:`targeted_settle`), else the whole state (:func:`settle_whole`).
The measured terms, the invariants per table class and the cost:
docs/algorithm.md, section 0 ("Where the bias comes from", "Which form, per table").
"""
import math

from .jit import jit
from .layout import LINE, SEGMENT

#: Collisions between two measurements of the energy.
SETTLE_EVERY = 256
#: Relative energy error above which :func:`settle` restores the start value.
SETTLE_AT = 1e-14
#: Largest relative energy error :func:`settle` gives back.  Rounding makes some 1e-16 per
#: collision, a few 1e-14 between two measurements; an error this large is not rounding but a
#: defect (a wrong law, a missed collision), and stays for the energy tests to see.
MAX_EXCESS = 1e-11
#: Largest relative correction :func:`settle` applies; a larger one would mean a particle all but
#: at rest, whose tiny kinetic energy cannot take the potential energy's rounding: it is left alone.
MAX_SETTLE = 1e-8

#: Where :func:`settle` puts the correction: the whole state ``(v, w)``,
SETTLE_ALL = 0
#: the velocity along the force,
SETTLE_FORCE = 1
#: the last collision's ``(v_t, w)``.
SETTLE_PAIR = 2


@jit(inline="always")
def settle_mode(potential, mixes, thermo):
    """Where an orbit's energy corrections go: ``SETTLE_FORCE``, ``SETTLE_PAIR`` or ``SETTLE_ALL``.

    ``potential``: a force without thermostat (the energy has a potential part); ``mixes``: the law exchanges energy
    with the spin (no-slip, ``gamma > 0``); ``thermo``: the isokinetic thermostat drives the flights.
    """
    if potential:
        return SETTLE_FORCE
    if mixes and not thermo:
        return SETTLE_PAIR
    return SETTLE_ALL


@jit(inline="always")
def targeted_settle(kinds, mixed, potential, mixes, bends):
    """True: the table keeps an invariant only the targeted settle keeps (``variant.TARGETED``); False: ``WHOLE``.

    ``kinds``: the elements' kinds (``layout.LINE`` ... ``layout.ARC``); ``mixed``: a table of mixed laws;
    ``potential``, ``mixes``: as in :func:`settle_mode`; ``bends``: the thermostat or a magnetic field flies the
    orbit (its flight rounds every component of ``v``).  One rule for the kernel table (``KernelTable.settle``)
    and the general kernel, which reads it at run time (docs/algorithm.md, "Which form, per table").
    """
    if mixed:  # the spin over specular elements (settle_velocity)
        return True
    if bends:  # nothing but the energy is exact
        return False
    if potential and mixes:  # the spin in flight (the velocity along the force takes the correction)
        return True
    for kind in kinds:  # the normal speed on flat walls: parallel to the force, or a strip's
        if kind == LINE or kind == SEGMENT:
            return True
    return False


@jit(inline="always")
def state_energy(vx, vy, w, spin, ax, ay, qx, qy, has_force):
    """``(E, K)``: twice the energy, ``|v|^2 + w^2 - 2 a . q`` (``w`` only if ``spin``), and the kinetic part.

    Plain floating point: its rounding (~1e-16, either sign) starts afresh at each measurement.
    """
    kin = vx * vx + vy * vy
    if spin:
        kin += w * w
    if has_force:
        return kin - 2.0 * (ax * qx + ay * qy), kin
    return kin, kin


@jit  # not inlined: the hot loop stays as it was (inlined, the pentagon ran at half its rate)
def settle(vx, vy, w, spin, ax, ay, qx, qy, has_force, e0, how=SETTLE_ALL, nx=0.0, ny=0.0):
    """``(vx, vy, w)`` with the energy given back to ``e0`` (:func:`state_energy` at the start) if off by ``SETTLE_AT``.

    A part ``p`` is scaled by ``1 + f``, ``f = -(E - e0) / (2 |p|^2)`` (many ulps, so ``x + x f`` rounds
    unbiased): ``how = SETTLE_ALL`` the whole ``(v, w)``; ``SETTLE_FORCE`` the velocity along ``(ax, ay)``;
    ``SETTLE_PAIR`` ``(v . t, w)``, ``t = (-ny, nx)`` the tangent of the last collision's unit normal.  A
    component along an axis leaves the other axis's bits as they were (it adds ``k * 0``).  A part too small
    (``|f| >= MAX_SETTLE``) hands the correction on: to the last pair if the law mixes the spin in, then to
    the whole state.  Only rounding is given back: an error above ``MAX_EXCESS`` is left as it is.
    """
    half, kin = _half_excess(vx, vy, w, spin, ax, ay, qx, qy, has_force, e0)
    if half != 0.0:
        if how == SETTLE_FORCE:
            fx, fy, done = _along_force(vx, vy, ax, ay, half)
            if done:
                return fx, fy, w
        if spin and how != SETTLE_ALL:  # the last pair: the first choice without force, the second with
            vt = vy * nx - vx * ny
            f = half / (vt * vt + w * w)
            if abs(f) < MAX_SETTLE:
                k = vt * f
                return vx - k * ny, vy + k * nx, w + w * f
        return _scale_state(vx, vy, w, spin, half, kin)
    return vx, vy, w


@jit  # not inlined, as settle
def settle_whole(vx, vy, w, spin, ax, ay, qx, qy, has_force, e0):
    """:func:`settle` of the whole-state form (``variant.WHOLE``): the numbers of ``settle(..., how=SETTLE_ALL)``,
    compiled without the targeted forms (:func:`targeted_settle`)."""
    half, kin = _half_excess(vx, vy, w, spin, ax, ay, qx, qy, has_force, e0)
    if half != 0.0:
        return _scale_state(vx, vy, w, spin, half, kin)
    return vx, vy, w


@jit(inline="always")
def _scale_state(vx, vy, w, spin, half, kin):
    """``(v, w)`` (``w`` only if ``spin``) scaled to give ``half`` back, unless that is too large a change."""
    f = half / kin
    if abs(f) < MAX_SETTLE:
        vx += vx * f
        vy += vy * f
        if spin:
            w += w * f
    return vx, vy, w


@jit  # not inlined, as settle
def settle_velocity(vx, vy, w, spin, ax, ay, qx, qy, has_force, e0, how=SETTLE_ALL):
    """:func:`settle` after a collision that rotated no pair with the spin: the spin keeps its bits.

    A specular element of a mixed table keeps ``w`` exactly, as the flight does, so the rounding is in ``v``:
    under a force (``how == SETTLE_FORCE``) the velocity along the force takes it, otherwise (or when that
    part is too small) the whole ``v``.
    """
    half = _half_excess(vx, vy, w, spin, ax, ay, qx, qy, has_force, e0)[0]
    if half != 0.0:
        if how == SETTLE_FORCE:
            fx, fy, done = _along_force(vx, vy, ax, ay, half)
            if done:
                return fx, fy, w
        f = half / (vx * vx + vy * vy)
        if abs(f) < MAX_SETTLE:
            vx += vx * f
            vy += vy * f
    return vx, vy, w


@jit(inline="always")
def _half_excess(vx, vy, w, spin, ax, ay, qx, qy, has_force, e0):
    """``(-(E - e0) / 2, K)`` if ``E`` is off ``e0`` by more than ``SETTLE_AT`` (and less than ``MAX_EXCESS``)
    of the size of its terms, else ``(0, K)`` (:func:`state_energy`)."""
    e, kin = state_energy(vx, vy, w, spin, ax, ay, qx, qy, has_force)
    excess = e - e0
    size = kin + abs(e - kin)  # the size of the terms
    if SETTLE_AT * size < abs(excess) < MAX_EXCESS * size:
        return -0.5 * excess, kin
    return 0.0, kin


@jit(inline="always")
def _along_force(vx, vy, ax, ay, half):
    """``(vx, vy, done)``: ``half`` given to the velocity's component along ``(ax, ay)``, if it is large enough."""
    norm = math.hypot(ax, ay)
    ux = ax / norm
    uy = ay / norm
    va = vx * ux + vy * uy
    f = half / (va * va)
    if abs(f) < MAX_SETTLE:
        k = va * f
        return vx + k * ux, vy + k * uy, True
    return vx, vy, False

"""The energy an orbit starts with, kept: measured every ``SETTLE_EVERY`` collisions, given back when off.

In exact arithmetic a collision keeps ``|v|^2 + w^2`` (the no-slip law is a
rotation of ``(v_t, w)``, specular a reflection) and a flight under a constant
force keeps ``E = (|v|^2 + w^2)/2 - a . q``.  In floating point each collision
changes ``E`` by some 1e-16 relative, and not at random: the mean change is
1e-18 to 1e-16 per collision, so the error grew linearly (4e-13 to 1e-10 per
10^6 collisions).  Measured term by term (``benchmarks/energy_terms.py``,
docs/algorithm.md section 0):

* the law, with a normal or rotation unit only to rounding: a specular hit
  scales ``|v|^2`` by ``(|n|^2)^2``, so a stored line normal with
  ``|n|^2 = 1 + delta`` adds ``2 delta`` at every hit (the pentagon: ``delta`` =
  4.2e-18, 7.5e-18), and a circle normal ``d / hypot(d)`` has ``|n|^2 - 1``
  = +4e-18 on average; no-slip adds ``c^2 + s^2 - 1`` (6.6e-18 at
  ``gamma = 1/sqrt 2``, where ``c = 1/3``) and its products with ``c`` and
  ``s`` round with a sign on average (+1.8e-18).  No float pair but the axes'
  is exactly unit;
* the lean loop's Newton steps: its normal ``(1/r)(1 - delta/2) h`` was
  rounded next to ``1/r`` (-1.05e-16 per no-slip collision at r = 0.3), now
  formed with fused multiply-adds (+9e-18, :mod:`disks`); its specular
  ``1 - delta`` rounds on the uneven float grid at 1 (-2e-18 per collision in
  orbits, up to +6.6e-17 for points exactly on the circle);
* under a force, the projection onto the element: it moves the particle by a
  rounding-sized step along the normal and leaves ``v`` alone, so ``E`` changes
  by ``-a . dq``, one-signed because the root is approached from one side
  (the circle container under gravity: -4e-17 per collision, the largest
  term there); the flight itself is unbiased to 1e-18.

:func:`settle`, called by the event loops every ``SETTLE_EVERY`` collisions,
measures ``E`` (:func:`state_energy`, plain floating point: its own rounding,
about 1e-16, is not carried from one measurement to the next) and, when it is
off the start value by more than ``SETTLE_AT`` (relative to the size of its
terms), scales ``(v, w)`` by ``1 + f`` to give the excess back.  ``|f|`` is
then at least ``SETTLE_AT / 2``, dozens of ulps, so ``x + x f`` rounds a value
that is not near ``x``'s grid point (unbiased, unlike a factor ``1 + f``
rounded at 1, the rescaling docs/algorithm.md records as rejected); and
every correction aims at the *start* value, so nothing is carried either:
the error stays below ``SETTLE_AT`` plus ``SETTLE_EVERY`` collisions' bias
(a few 1e-14) for any number of collisions.  No collision or flight is
computed differently; the correction is a change of speed of ~1e-14 every
few hundred collisions.  :func:`settle` is a call, not inlined: inlined, it
halved the pentagon's rate (the event loop's registers), called, it costs
nothing measurable (``benchmarks/RESULTS.md``).

The correction goes where the rounding arose, never into a component that
neither the law nor the flight touches (``how``, chosen once per orbit by
:func:`settle_mode`).  Under a force it is the velocity along the force, the
one component a flight changes (the projection's ``-a . dq`` is the largest
term there); the velocity across the force keeps its bits, so the normal speed
on flat walls parallel to the force stays exact, as it is in exact arithmetic
(scaling the whole state random-walked it by 1e-11 over 10^6 collisions).  With
no force and a spin that the law exchanges, it is the pair ``(v_t, w)`` the
last collision rotated; the normal speed it reversed is left alone.  A
specular law without force, and a thermostat (whose flight rounds the speed in
every direction), scale the whole state.  After a specular element of a table
whose spin takes part (a no-slip element elsewhere: :func:`settle_velocity`),
which rotates no pair with the spin, the velocity takes it and the spin keeps
its bits.  Where the chosen part is too small to take the correction (no
velocity along the force, a grazing hit without spin), the next choice takes
it (under a force the last pair, if the law mixes the spin in, then the whole
state).

Which form: the invariants of each table class
----------------------------------------------
A kernel compiles one form (the variant's ``settle`` slot,
``KernelTable.settle``): the **targeted** one above (:func:`settle`,
:func:`settle_velocity`, the part chosen per orbit by :func:`settle_mode`), or
the **whole** state scaled (:func:`settle_whole`), less code.  The
targeted form exists to keep a quantity the dynamics keeps exactly, bit for
bit; a table that has none runs the whole-state form, which keeps the energy
and breaks nothing such a table can show.  The rule, :func:`targeted_settle`,
one for the kernel table and for the general kernel (``settle=None``, read at
run time); this list is the one place the invariants are written down
(docs/algorithm.md, section 0, links here):

* every table: the energy, to 1e-12 relative per 10^6 collisions (either form);
* a line or segment, with straight flights or free fall: the velocity across
  the force (free fall adds ``a_x t = 0`` to it), so ``|v_n|`` on walls
  parallel to the force; without force and no-slip, a strip's ``|v_n|`` (axis
  normals reverse it exactly, the pair ``(v_t, w)`` is settled): **targeted**;
* a no-slip law (``gamma > 0``) under free fall, any elements (the no-slip
  Galton board): the spin in flight, each collision meeting the spin the last
  one left (the correction goes along the force, never into ``w``): **targeted**;
* mixed laws, any flight: the spin over specular elements
  (:func:`settle_velocity`): **targeted**;
* disks, circles and arcs only, without force or with a specular law (Sinai
  tori, the specular Galton board, the lemon; the lean disk loop always): the
  energy only: **whole**;
* the thermostat or a magnetic field, one law: the energy only (the flight
  rounds every component of ``v``): **whole**.

A specular table without force settles the whole state in either form
(:func:`settle_mode`): its axis normals keep the energy exactly (no settle
acts), and other normals keep no component's bits.  ``tests/test_settle_form.py``
checks each class over 10^6 collisions.
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

    ``potential``: a force without thermostat (the energy has a potential
    part); ``mixes``: the law exchanges energy with the spin (no-slip,
    ``gamma > 0``); ``thermo``: the isokinetic thermostat drives the flights.
    """
    if potential:
        return SETTLE_FORCE
    if mixes and not thermo:
        return SETTLE_PAIR
    return SETTLE_ALL


@jit(inline="always")
def targeted_settle(kinds, mixed, potential, mixes, bends):
    """The table keeps an invariant only the targeted settle keeps (module docstring, "Which form").

    ``kinds``: the elements' kinds (``layout.LINE`` ... ``layout.ARC``);
    ``mixed``: a table of mixed laws; ``potential``, ``mixes``: as in
    :func:`settle_mode`; ``bends``: the thermostat or a magnetic field flies
    the orbit (its flight rounds every component of ``v``).  True: the
    targeted form (``variant.TARGETED``); False: the whole state
    (``variant.WHOLE``, :func:`settle_whole`).  One rule for the kernel table
    (``KernelTable.settle``) and the kernel that reads the form at run time.
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

    Plain floating point: its rounding, about 1e-16 relative and of either
    sign from one state to the next, does not add up (each measurement starts
    afresh), so it is far below ``SETTLE_AT``.
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

    Only rounding is given back: an error above ``MAX_EXCESS`` is left as it is.

    A part ``p`` of the state takes the correction: ``p`` scaled by
    ``1 + f``, ``f = -(E - e0) / (2 |p|^2)``, some 1e-14 or more, many ulps, so
    the rounding of ``x + x f`` only adds errors of either sign.  ``how``
    chooses ``p`` (module docstring): ``SETTLE_ALL`` the whole ``(v, w)``;
    ``SETTLE_FORCE`` the velocity's component along ``(ax, ay)``;
    ``SETTLE_PAIR`` ``(v . t, w)`` with ``t = (-ny, nx)``, the tangent of the
    last collision's unit normal ``(nx, ny)``.  A component along an axis
    leaves the other axis's bits as they were (it adds ``k * 0``).  When ``p``
    is too small for the correction (``|f| >= MAX_SETTLE``: the velocity along
    the force passing through 0), the next choice takes it: the last pair if
    the law mixes the spin in, then the whole state.
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
    """:func:`settle` of the whole-state form (``variant.WHOLE``): ``(v, w)`` scaled, no part chosen.

    The same numbers as ``settle(..., how=SETTLE_ALL)``, compiled without the
    targeted forms: a table that has no invariant they keep (:func:`targeted_settle`)
    runs this one.
    """
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

    A specular element of a table whose spin takes part (a no-slip element
    elsewhere) reflects ``v`` and keeps ``w`` exactly, as the flight does, so its rounding is in
    ``v`` alone: under a force (``how == SETTLE_FORCE``) the velocity along
    the force takes the correction, as in :func:`settle`; otherwise, or when
    that part is too small, the whole velocity ``v``.
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

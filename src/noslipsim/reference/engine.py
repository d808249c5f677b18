"""The event loop of :mod:`noslipsim.reference` and its entry points.

:func:`simulate_reference` and :func:`resume_reference` validate their inputs
and run :class:`_EventLoop`: one object holding the scene's constants and the
particle's state, with one method per step of the algorithm in the package
docstring (next hit, relocate, resolve, corner pass, stop checks).
"""
from __future__ import annotations

import math

import mpmath
import numpy as np

from .._validate import finite_float, finite_vector
from ..core.tolerances import MAX_CORNER_BOUNCES
from ..scenes import Scene
from ..simulate import check_limits, check_start
from . import magnetic
from .elements import _StraightMp
from .orbit import ReferenceOrbit
from .roots import _exit_roots, _flight
from .thermostat import ThermoPath, accel, first_exit, horizon, line_first_exit
from .walk import _Table, _walk_cells

#: Smallest working precision accepted: the tolerances are ``10^(-dps/2)``.
MIN_DPS = 20

#: How far (relative to the length scale) a resumed position may lie from its element.
RESUME_TOL = 1e-9


def _validated_limits(scene, q, max_collisions, max_time, stop_below, dps):
    """``(max_collisions, max_time, level, dps)`` checked as :func:`noslipsim.simulate` checks them."""
    if isinstance(dps, bool) or not isinstance(dps, (int, np.integer)) or dps < MIN_DPS:
        raise ValueError(f"dps: expected an integer >= {MIN_DPS}, got {dps!r}")
    max_collisions, max_time = check_limits(max_collisions, max_time)
    level = None if stop_below is None else finite_float(stop_below, "stop_below")
    if level is not None and level >= q[1]:
        raise ValueError(f"stop_below: {level} must lie below the start height {q[1]}")
    return max_collisions, max_time, level, int(dps)


def _check_scene(scene):
    """Refuse anything but a :class:`~noslipsim.scenes.Scene`."""
    if not isinstance(scene, Scene):
        raise ValueError(f"scene: expected a noslipsim.Scene, got {type(scene).__name__}")


def simulate_reference(scene: Scene, position, velocity, spin=0.0, max_collisions=1000,
                       max_time=math.inf, stop_below=None, dps=50, as_mpf=False):
    """Simulate one orbit in mpmath at ``dps`` digits (the reference for :func:`noslipsim.simulate`).

    Parameters
    ----------
    scene : Scene
        Table, law, gamma and force (nondimensional), plain or periodic.
    position : (float, float)
        Start ``(x, y)``, strictly inside the table (on a lattice: unfolded, in any cell).
    velocity : (float, float)
        Initial velocity ``(v_x, v_y)``.
    spin : float
        Initial scaled spin ``w = gamma R omega`` (counter-clockwise positive).
    max_collisions : int
        Collision budget (corner collisions count).
    max_time : float
        Time limit; the final state is then advanced to it.
    stop_below : float, optional
        End the orbit when it crosses this height downwards.
    dps : int
        Working precision in decimal digits (>= 20).  Length tolerances are
        ``10^(-floor(dps/2))`` times the scene's scale.
    as_mpf : bool
        Return the :class:`ReferenceOrbit` holding the raw mpf values instead of a dataset.

    Returns
    -------
    xarray.Dataset or ReferenceOrbit
        The dataset has the variables of :func:`noslipsim.simulate` (converted
        to float64; on a lattice also ``cell_a1, cell_a2`` and their final
        values) and the attribute ``dps``.

    Raises
    ------
    ValueError
        On a bad scene, start, limit, level or precision (as :func:`noslipsim.simulate`).

    Notes
    -----
    The algorithm is described in :mod:`noslipsim.reference`.  At 50 digits a
    collision costs about a tenth of a millisecond per line or segment and a
    few milliseconds per circle or arc under a force: use it for tens to
    hundreds of collisions.  On a lattice each cell a flight crosses costs
    about as much as one element: a flight across ``10^5`` cells takes seconds.
    """
    _check_scene(scene)
    q, v, w = check_start(scene, position, velocity, spin)
    limits = _validated_limits(scene, q, max_collisions, max_time, stop_below, dps)
    orbit = _run(scene, q, v, w, None, *limits)
    return orbit if as_mpf else orbit.to_dataset()


def resume_reference(scene: Scene, position, velocity, spin, element, max_collisions=1000,
                     max_time=math.inf, stop_below=None, dps=50, as_mpf=False):
    """Continue an orbit in mpmath from the state just after a collision on ``element``.

    For one-step (shadowing) checks: start the reference from any
    post-collision state of a float64 orbit and compare its next collision
    with the float64 one, so chaos never amplifies the difference.  The
    position is first projected onto ``element`` (it is on it up to the
    rounding of the input; on a lattice, onto the copy of ``element`` nearest
    the position), then the corner rule and the next-hit search run exactly as
    after a hit inside :func:`simulate_reference`.  Times restart at 0.

    Parameters
    ----------
    scene : Scene
        Table, law, gamma and force.
    position, velocity : (float, float)
        Post-collision position (on ``element``; on a lattice unfolded) and velocity.
    spin : float
        Post-collision scaled spin.
    element : int
        Index of the element just hit.
    max_collisions, max_time, stop_below, dps, as_mpf
        As in :func:`simulate_reference`.

    Returns
    -------
    xarray.Dataset or ReferenceOrbit
        As :func:`simulate_reference`; collision 0 is the first event after the given one.

    Raises
    ------
    ValueError
        On a bad scene, state, element index, limit, level or precision, or a
        position farther than ``RESUME_TOL`` (relative to the length scale)
        from ``element``.
    """
    _check_scene(scene)
    q = finite_vector(position, "position")
    v = finite_vector(velocity, "velocity")
    w = finite_float(spin, "spin")
    if isinstance(element, bool) or not isinstance(element, (int, np.integer)) \
            or not 0 <= element < len(scene.elements):
        raise ValueError(f"element: expected an index in [0, {len(scene.elements)}), got {element!r}")
    limits = _validated_limits(scene, q, max_collisions, max_time, stop_below, dps)
    orbit = _run(scene, q, v, w, int(element), *limits)
    return orbit if as_mpf else orbit.to_dataset()


def _resumed_copy(table, e, x, y):
    """The copy of element ``e`` that ``(x, y)`` lies on (the nearest one that holds it in its extent)."""
    length = table.length(x, y)
    tol = RESUME_TOL * length
    best, gap = None, None
    for c in table.copies_at(*table.cell(x, y)):
        if c.index != e or c.extent(x, y, tol) < 0:
            continue
        d = abs(c.distance(x, y))
        if gap is None or d < gap:
            best, gap = c, d
    if best is None or gap > tol:
        found = "no copy holds it" if best is None else f"distance {float(gap / length):.3g} of the length scale"
        raise ValueError(f"position: ({float(x)}, {float(y)}) is not on element {e} ({found})")
    return best


class _Earliest:
    """Step 4: the earliest hit among the copies offered so far.

    Each copy is solved once per flight (``solve(copy)``: its first hit time or
    None); a later copy replaces the best only if it comes earlier by more than a
    relative ``rel_tol``, so ties go to the copy offered first (lower index, then
    earlier cell).
    """

    __slots__ = ("copy", "met", "rel_tol", "solve", "t")

    def __init__(self, solve, rel_tol):
        self.solve, self.rel_tol = solve, rel_tol
        self.met = {}
        self.t = self.copy = None

    def offer(self, copies):
        """Solve every copy not met yet on the whole flight and keep the earliest hit."""
        for c in copies:
            if c.key in self.met:
                continue
            th = self.met[c.key] = self.solve(c)
            if th is not None and (self.t is None or th < self.t * (1 - self.rel_tol)):
                self.t, self.copy = th, c


class _EventLoop:
    """One reference run at ``dps`` digits: the scene's constants, the particle's state, the orbit so far.

    ``x, y, vx, vy, w, t`` is the particle's state (just after the last event),
    ``current`` the element copy hit last (None before the first hit).
    """

    def __init__(self, scene, q, v, w, max_collisions, max_time, level, dps):
        ctx = self.ctx = mpmath.MPContext()
        ctx.dps = dps
        f = ctx.mpf
        self.table = _Table(ctx, scene)
        self.rel_tol = f(10) ** (-(dps // 2))
        self.slope_floor = f(10) ** (-((2 * dps) // 5))
        self.ax, self.ay = f(scene.force[0]), f(scene.force[1])
        # the Gaussian isokinetic thermostat: the force steers, the speed stays (module thermostat)
        self.thermo = scene.thermostat is not None and scene.force != (0.0, 0.0)
        # a magnetic field turns the velocity at the rate W (module magnetic); never with a force
        self.W = f(scene.magnetic)
        self.magnetic = scene.magnetic != 0.0
        self.noslip = [law == "no-slip" for law in scene.element_laws]  # each element's own law
        g = f(scene.gamma)
        self.c_law, self.s_law = (1 - g * g) / (1 + g * g), 2 * g / (1 + g * g)
        self.max_collisions = max_collisions
        self.t_max = ctx.inf if math.isinf(max_time) else f(max_time)
        self.level = None if level is None else f(level)
        self.orbit = ReferenceOrbit(scene=scene, dps=dps,
                                    start=dict(position=[float(c) for c in q], velocity=[float(c) for c in v],
                                               spin=float(w)))
        self.x, self.y, self.vx, self.vy, self.w = f(q[0]), f(q[1]), f(v[0]), f(v[1]), f(w)
        self.t = ctx.zero
        self.current = None

    # -------------------------------------------------------------------- the loop
    def run(self):
        """The event loop: after a hit the corner pass and the grazing check, then the next flight."""
        while True:
            if self.current is not None:
                stop = self.after_hit()
                if stop is not None:
                    return stop
            if len(self.orbit) >= self.max_collisions:
                return "max_collisions"
            stop = self.fly()
            if stop is not None:
                return stop

    def resume_on(self, element):
        """Start on ``element`` (the copy holding the position), placed exactly on it."""
        self.current = _resumed_copy(self.table, element, self.x, self.y)
        self.x, self.y = self.current.place(self.x, self.y)

    def finish(self, stop):
        """The orbit with its stop reason and final state."""
        orbit = self.orbit
        orbit.stop_reason = stop
        orbit.final = dict(t=self.t, x=self.x, y=self.y, vx=self.vx, vy=self.vy, spin=self.w)
        orbit.final_cell = self.table.cell(self.x, self.y)
        return orbit

    # -------------------------------------------------------------------- after a hit (step 6)
    def after_hit(self):
        """Step 6 after a hit on ``current``: the corner pass, then the grazing check; a stop reason or None."""
        if self.corner_pass():
            return "corner"
        if self.slides_off(self.current):
            return "grazing"
        return None

    def corner_pass(self):
        """Step 6: resolve, in index order, each other copy left through at the hit point; True past the cap."""
        bounces = 0
        while len(self.orbit) < self.max_collisions:
            other = self.corner_partner()
            if other is None:
                return False
            bounces += 1
            if bounces > MAX_CORNER_BOUNCES:
                return True
            self.resolve(other, self.vx, self.vy, self.w, 1)
        return False

    def corner_partner(self):
        """Step 6: the first other copy touched here whose line or circle the particle leaves, or None."""
        tol = self.tol()
        for c in self.table.copies_at(*self.table.cell(self.x, self.y)):
            if c.key != self.current.key and self.leaves_through(c, tol) and not self.reflex(c, tol):
                return c
        return None

    def leaves_through(self, copy, tol):
        """Step 6: the particle touches ``copy`` (ends inclusive) and leaves its supporting line or circle."""
        x, y = self.x, self.y
        if abs(copy.distance(x, y)) > tol:
            return False
        if copy.extent(x, y, tol) < 0:
            return False
        rate = copy.rate(x, y, self.vx, self.vy)
        if rate > 0:
            return False
        if rate == 0 and copy.crossing(*self.flight())[2] >= 0:
            return False
        return True

    def reflex(self, other, tol):
        """Step 6: ``current`` and ``other`` meet here at a reflex junction of the table (its angle exceeds pi).

        Where one piece ends at the point, the table lies locally on the table
        side of either piece (the union of the half planes) when that end
        leads off to the other piece's wall side: having just reflected into
        the table side of ``current``, the particle is inside, whatever
        ``other``'s line says.  (A point inside both pieces, a full circle or a
        line has no end here: not reflex.)
        """
        x, y = self.x, self.y
        for a, b in ((other, self.current), (self.current, other)):
            u = a.end_direction(x, y, tol)
            if u is not None:
                nx, ny = b.outward_normal(x, y)
                return u[0] * nx + u[1] * ny > 0  # a's end leads into b's wall side
        return False

    def slides_off(self, copy):
        """Step 6 (grazing): on ``copy``, the flight leaves through it at once (first nonzero derivative < 0)."""
        for c in copy.crossing(*self.flight())[1:]:
            if c != 0:
                return c < 0
        return False

    # -------------------------------------------------------------------- one flight (steps 1-5)
    def fly(self):
        """One flight: the next hit resolved (None), or the stop reason of the event that ends the orbit first."""
        t_level = self.level_time()
        remaining = self.t_max - self.t
        t_limit = remaining if t_level is None else min(remaining, t_level)
        best_t, best, gave_up = self.next_hit(t_limit)
        if t_level is not None and (best_t is None or t_level <= best_t) and t_level <= remaining:
            self.advance(t_level)
            self.y = self.level  # exactly on the level
            self.t += t_level
            return "stop_below"
        if best is None and gave_up:  # nothing ahead: the orbit leaves for good from its last collision
            return magnetic.PINNED if self.magnetic else "escape"  # a closed cyclotron path circles for ever
        if best is None or best_t > remaining:
            self.advance(remaining)
            self.t = self.t_max
            return "max_time"
        vx_in, vy_in = self.relocate(best, best_t)
        self.resolve(best, vx_in, vy_in, self.w, 0)
        return None

    def level_time(self):
        """Stop rule: when the flight crosses ``stop_below`` downwards (exit root of ``y(t) - level``), or None."""
        if self.level is None:
            return None
        if self.thermo:
            return line_first_exit(self.ctx, self.path(), self.ctx.zero, self.ctx.one, self.y - self.level,
                                   self.ctx.zero)
        if self.magnetic:
            return magnetic.level_exit(self.ctx, self.path(), self.level, self.slope_floor)
        roots = _exit_roots(self.ctx, [self.y - self.level, self.vy, self.ay / 2], False, self.slope_floor)
        return roots[0] if roots else None

    def next_hit(self, t_limit):
        """Step 4: ``(t, copy, gave_up)``, the earliest hit ahead (or None) and whether the search gave up.

        Plain scenes: every element, over all times (``gave_up``: nothing ahead).
        Lattices: the cell walk (:func:`~noslipsim.reference.walk._walk_cells`),
        which may stop at ``t_limit`` with no hit found (or one beyond the limit).
        A magnetic flight looks one period ahead (``gave_up``: pinned).
        """
        tol = self.tol()
        earliest = _Earliest(lambda c: self.first_hit(c, tol), self.rel_tol)
        if not self.table.periodic:
            earliest.offer(self.table.copies_at(0, 0))
            return earliest.t, earliest.copy, earliest.copy is None
        path = self.path() if (self.thermo or self.magnetic) else None
        return _walk_cells(self.table, self.flight(), earliest, t_limit, tol, path, self.slope_floor)

    def first_hit(self, copy, tol):
        """Steps 1-3 for one copy: the first exit root of the whole flight within its extent, or None."""
        if self.thermo:
            return self.thermo_first_hit(copy, tol)
        if self.magnetic:
            return magnetic.first_hit(self.ctx, self.path(), copy, self.deflated(copy, tol), tol, self.slope_floor)
        x, y, vx, vy, ax, ay = self.flight()
        coeffs = copy.crossing(x, y, vx, vy, ax, ay)
        deflate = self.deflated(copy, tol)
        for root in _exit_roots(self.ctx, coeffs, deflate, self.slope_floor):
            hx, hy = _flight(x, y, vx, vy, ax, ay, root)
            if copy.extent(hx, hy, tol) >= 0:
                return root
        return None

    def thermo_first_hit(self, copy, tol):
        """:meth:`first_hit` for a thermostatted flight: the certified search of :mod:`.thermostat`."""
        ctx = self.ctx
        path = self.path()
        deflate = self.deflated(copy, tol)
        extent = lambda t: copy.extent(*path.position(t), tol) < 0  # noqa: E731  (True: reject the root)
        el = copy.el
        if isinstance(el, _StraightMp):
            f0 = ctx.zero if deflate else copy.distance(self.x, self.y)
            reach = None
            if el.u is not None:  # a segment: bounded along the field
                ends = [(el.px + copy.sx, el.py + copy.sy),
                        (el.px + copy.sx + el.length * el.u[0], el.py + copy.sy + el.length * el.u[1])]
                reach = max(px * path.fx + py * path.fy for px, py in ends) + tol
            return line_first_exit(ctx, path, el.nx, el.ny, f0, ctx.zero, skip=extent, bounded=reach)
        cx, cy, sg, r = el.cx + copy.sx, el.cy + copy.sy, el.sigma, el.r

        def g(t):
            if deflate and t == 0:
                return ctx.zero
            px, py = path.position(t)
            return sg * ((px - cx) ** 2 + (py - cy) ** 2 - r * r)

        def dg(t):
            px, py = path.position(t)
            vx, vy = path.velocity(t)
            return 2 * sg * ((px - cx) * vx + (py - cy) * vy)

        def bound(a, b):  # |G''| = 2 |c^2 + d . dv/dt| with |d| <= |d(a)| + c (b - a) and |dv/dt| <= E
            px, py = path.position(a)
            return 2 * (path.c ** 2 + (ctx.hypot(px - cx, py - cy) + path.c * (b - a)) * path.E)

        beyond = cx * path.fx + cy * path.fy + r + tol
        T = horizon(ctx, path, lambda T: path.along_field(T) and path.field_coordinate(T) > beyond)
        return first_exit(ctx, g, dg, bound, ctx.zero, T, skip=extent if el.theta0 is not None else None)

    def deflated(self, copy, tol):
        """Steps 1-3: whether ``copy``'s root ``t = 0`` is exact and divided out.

        The copy just hit, and the other piece of a reflex junction just hit at
        its vertex (the start lies on its line within ``tol``, :meth:`reflex`):
        its root ``t = 0`` is exact too, and no collision (the particle, having
        entered the union of the two table sides, is inside).  At the working
        precision that root rounds to either side of zero; a positive one
        would be a hit within ``tol`` of the piece's end, and the particle
        would reverse (docs/algorithm.md, step 4: the float64 engine's rule).
        """
        if copy is self.current:
            return True
        return (self.current is not None and abs(copy.distance(self.x, self.y)) <= tol
                and self.reflex(copy, tol))

    def relocate(self, copy, dt):
        """Step 5 (relocate): fly for ``dt`` and place the particle on ``copy``; the incoming velocity."""
        if self.thermo or self.magnetic:
            path = self.path()
            hx, hy = path.position(dt)
            vx_in, vy_in = path.velocity(dt)
            self.x, self.y = copy.place(hx, hy)
            self.t += dt
            return vx_in, vy_in
        hx, hy = _flight(*self.flight(), dt)
        vx_in, vy_in = self.vx + self.ax * dt, self.vy + self.ay * dt
        self.x, self.y = copy.place(hx, hy)
        self.t += dt
        return vx_in, vy_in

    def resolve(self, copy, vx_in, vy_in, w_in, corner):
        """Step 5 (resolve): apply the collision law on ``copy`` to the incoming state and record the collision."""
        self.vx, self.vy, self.w = self.collide(vx_in, vy_in, w_in, *copy.outward_normal(self.x, self.y),
                                                noslip=self.noslip[copy.index])
        self.record(copy, vx_in, vy_in, w_in, corner)
        self.orbit.n_corner += corner
        self.current = copy

    def collide(self, vx, vy, w, nx, ny, noslip):
        """Step 5 (the law): the state after a collision with outward unit normal ``(nx, ny)``.

        ``noslip``: the law of the element hit (its own, or the scene's).
        """
        tx, ty = -ny, nx  # t = J n, n outward
        vt = vx * tx + vy * ty
        vn = vx * nx + vy * ny
        if noslip:
            vt, w = -self.s_law * w + self.c_law * vt, -self.c_law * w - self.s_law * vt
        vn = -vn
        return vt * tx + vn * nx, vt * ty + vn * ny, w

    def advance(self, dt):
        """Stop rules: the free flight for ``dt`` with no collision (to the level or the time limit)."""
        if self.thermo or self.magnetic:
            path = self.path()
            self.x, self.y = path.position(dt)
            self.vx, self.vy = path.velocity(dt)
            return
        self.x, self.y = _flight(*self.flight(), dt)
        self.vx, self.vy = self.vx + self.ax * dt, self.vy + self.ay * dt

    # -------------------------------------------------------------------- helpers
    def flight(self):
        """``(x, y, vx, vy, ax, ay)``: the flight from the current state.

        Thermostatted: the acceleration now, ``F - alpha v``; magnetic:
        ``W J v`` (the local expansion the corner and grazing rules read; the
        path is :meth:`path`).
        """
        if self.thermo:
            return (self.x, self.y, self.vx, self.vy, *accel(self.ax, self.ay, self.vx, self.vy))
        if self.magnetic:
            return self.path().local()
        return self.x, self.y, self.vx, self.vy, self.ax, self.ay

    def path(self):
        """The thermostatted or magnetic path from the current state."""
        if self.magnetic:
            return magnetic.MagneticPath(self.ctx, self.x, self.y, self.vx, self.vy, self.W)
        return ThermoPath(self.ctx, self.x, self.y, self.vx, self.vy, self.ax, self.ay)

    def tol(self):
        """The length tolerance at the particle: ``10^(-floor(dps/2)) * max(scale, |x|, |y|)``."""
        return self.rel_tol * self.table.length(self.x, self.y)

    def record(self, copy, vx_in, vy_in, w_in, corner):
        """Append the collision just resolved on ``copy`` to the orbit."""
        x, y, vx, vy, w = self.x, self.y, self.vx, self.vy, self.w
        orbit, rec = self.orbit, self.orbit.records
        for k, val in zip(("t", "x", "y", "vx", "vy", "spin", "vx_in", "vy_in", "spin_in"),
                          (self.t, x, y, vx, vy, w, vx_in, vy_in, w_in)):
            rec[k].append(val)
        rec["s"].append(copy.arclength(x, y))
        potential = 0 if self.thermo else self.ax * x + self.ay * y  # the thermostat keeps the kinetic energy
        rec["energy"].append((vx * vx + vy * vy + w * w) / 2 - potential)
        orbit.element.append(copy.index)
        orbit.corner.append(corner)
        orbit.cells.append(self.table.cell(x, y))


def _run(scene, q, v, w, resume_element, max_collisions, max_time, level, dps):
    """The event loop at ``dps`` digits; ``resume_element`` is the element just hit, if any."""
    loop = _EventLoop(scene, q, v, w, max_collisions, max_time, level, dps)
    if resume_element is not None:
        loop.resume_on(resume_element)
    return loop.finish(loop.run())

"""High-precision reference orbits: the slow, obviously-correct twin of :func:`noslipsim.simulate`.

The same event-driven algorithm as the compiled engine, written again from
the definitions in mpmath at ``dps`` significant digits, on any
:class:`~noslipsim.scenes.Scene` (lines, segments, circles, arcs; with or
without force; no-slip or specular).  It shares no numerical code with
:mod:`noslipsim.core`; the float64 engine is judged against it.

Algorithm (one collision)
-------------------------
1. *Crossing polynomials.*  Along the flight ``q(t) = q + v t + a t^2/2`` each
   element has a polynomial that is positive on the table side:
   ``(q(t) - p) . n_in`` for lines and segments (degree <= 2) and
   ``sigma (|q(t) - c|^2 - r^2)`` for circles and arcs (degree <= 4,
   ``sigma = +1`` when the table lies outside the circle).  Exact zero leading
   coefficients are dropped; for the element just hit the exact root ``t = 0``
   is removed by dividing by ``t``.
2. *All real roots.*  Degree 1 and 2 in closed form (the cancellation-free
   quadratic formula), degree 3 and 4 by :func:`mpmath.polyroots`
   (Durand-Kerner on all complex roots, iterated at three times the working
   precision); the roots it returns as real (imaginary part below the working
   epsilon) are the real roots.  A polynomial whose coefficients show no sign
   change has no positive root (Descartes' rule) and is skipped.
3. *Exit roots.*  A root ``t > 0`` is a hit if the polynomial decreases there
   (the orbit leaves the table: ``p'(t) < 0`` beyond a noise floor
   ``10^(-2 dps / 5)`` relative to the size of the terms of ``p'``, so an exact
   tangency is not a hit) and the point lies in the element's extent
   (segment: ``0 <= u <= L``; arc: CCW angle past ``theta0`` within the span),
   ends inclusive within ``tol``.
4. *Earliest hit.*  The smallest hit time over all elements; times equal to a
   relative ``10^(-dps/2)`` go to the lower element index.
5. *Relocate and resolve.*  The particle is placed on the element
   (orthogonal projection onto a line, radial onto a circle) and the collision
   law is applied in the frame of DESIGN section 2: ``n`` the outward unit
   normal, ``t = J n = (-n_y, n_x)``,

   .. math::

       w^+ = -c w - s v_t, \\quad v_t^+ = -s w + c v_t, \\quad v_n^+ = -v_n,
       \\qquad c = \\frac{1-\\gamma^2}{1+\\gamma^2}, \\; s = \\frac{2\\gamma}{1+\\gamma^2}

   (no-slip); specular keeps ``v_t`` and ``w`` and reverses ``v_n``.
6. *Corner rule* (as documented in :mod:`noslipsim.core.loop`): every other
   element touched at the hit point (signed distance within ``tol``, in its
   extent within ``tol``: ends inclusive) whose supporting line or circle the
   new velocity leaves (distance rate ``< 0``, or ``= 0`` with a negative
   second coefficient) is hit at once, in index order, as a separate
   collision with ``corner = 1``; more than ``MAX_CORNER_BOUNCES`` in a row
   stop the orbit (``corner``).  If the element hit last would be left
   through at once the orbit stops (``grazing``).  The kernel's junction gate
   (corner pass only near points where two elements meet) is a shortcut that
   cannot change this rule's outcome, so it has no twin here.

``tol = 10^(-floor(dps/2)) * max(scene scale, |x|, |y|)`` is the only length
tolerance.  The stop rules follow :data:`noslipsim.core.layout.STOP_REASONS`:
crossing ``stop_below`` downwards (before or at the next hit), escape (no hit
ahead: the state of the last collision is final, whatever the time limit), the
time limit (the state advanced to it) and the collision budget.

Inputs are taken at the exact values of their Python floats (``mpf(float)``
is exact).  Element geometry is read from the element objects: segments from
their end points ``p0, p1`` (so adjacent polygon edges share their vertex
exactly), lines from ``point`` and the stored float unit ``normal`` (taken as
an exact direction and renormalised), circles and arcs from ``center``,
``radius``, ``theta0``, ``theta1``.  An arc ends at its float angles, so where
it meets a segment (a stadium's ``theta0 = -pi/2`` rounded) the two touch only
to about ``1e-16``; orbits aimed that close to such a junction are beyond what
either engine resolves.
"""
from __future__ import annotations

import inspect
import math
from dataclasses import dataclass, field

import mpmath
import numpy as np
import xarray as xr

from ._validate import finite_float, finite_vector
from ._version import __version__
from .core.layout import STOP_REASONS
from .core.tolerances import MAX_CORNER_BOUNCES
from .elements import Arc, Circle, Line, Segment
from .metadata import annotate
from .scenes import Scene
from .simulate import check_limits, check_start

#: Variables recorded per collision (all mpf), in the order of :func:`noslipsim.simulate`.
RECORDED = ("t", "x", "y", "vx", "vy", "spin", "vx_in", "vy_in", "spin_in", "s", "energy")
FINAL = ("t", "x", "y", "vx", "vy", "spin")

#: Smallest working precision accepted: the tolerances are ``10^(-dps/2)``.
MIN_DPS = 20


# ---------------------------------------------------------------------------- elements in mpmath
class _StraightMp:
    """A line or segment: ``p`` a point on it, ``n`` the unit normal INTO the table."""

    def __init__(self, ctx, index, px, py, nx, ny, u=None, length=None):
        self.ctx = ctx
        self.index = index
        self.px, self.py = px, py
        self.nx, self.ny = nx, ny
        self.u = u              # unit direction p0 -> p1 (segments only)
        self.length = length    # segment length (segments only)

    def crossing(self, x, y, vx, vy, ax, ay):
        """Ascending coefficients of ``(q(t) - p) . n_in``."""
        nx, ny = self.nx, self.ny
        return [(x - self.px) * nx + (y - self.py) * ny, vx * nx + vy * ny, (ax * nx + ay * ny) / 2]

    def distance(self, x, y):
        return (x - self.px) * self.nx + (y - self.py) * self.ny

    def rate(self, x, y, vx, vy):
        return vx * self.nx + vy * self.ny

    def extent(self, x, y, tol):
        """-1 outside, 0 interior, 1 at the start, 2 at the end (ends within ``tol``)."""
        if self.u is None:
            return 0
        u = (x - self.px) * self.u[0] + (y - self.py) * self.u[1]
        if u < -tol or u > self.length + tol:
            return -1
        if u <= tol:
            return 1
        if u >= self.length - tol:
            return 2
        return 0

    def place(self, x, y):
        """Orthogonal projection onto the line."""
        d = self.distance(x, y)
        return x - d * self.nx, y - d * self.ny

    def outward_normal(self, x, y):
        return -self.nx, -self.ny

    def arclength(self, x, y):
        if self.u is not None:  # distance from p0
            return (x - self.px) * self.u[0] + (y - self.py) * self.u[1]
        # signed distance from the point along t = J n_out = (n_in_y, -n_in_x)
        return (x - self.px) * self.ny - (y - self.py) * self.nx


class _RoundMp:
    """A circle or arc; ``sigma = +1`` when the table lies outside the circle."""

    def __init__(self, ctx, index, cx, cy, r, sigma, theta0=None, span=None):
        self.ctx = ctx
        self.index = index
        self.cx, self.cy, self.r, self.sigma = cx, cy, r, sigma
        self.theta0 = theta0    # arcs only
        self.span = span

    def crossing(self, x, y, vx, vy, ax, ay):
        """Ascending coefficients of ``sigma (|q(t) - c|^2 - r^2)``."""
        dx, dy, sg = x - self.cx, y - self.cy, self.sigma
        return [sg * (dx * dx + dy * dy - self.r * self.r),
                sg * 2 * (dx * vx + dy * vy),
                sg * (vx * vx + vy * vy + dx * ax + dy * ay),
                sg * (vx * ax + vy * ay),
                sg * (ax * ax + ay * ay) / 4]

    def distance(self, x, y):
        return self.sigma * (self.ctx.hypot(x - self.cx, y - self.cy) - self.r)

    def rate(self, x, y, vx, vy):
        dx, dy = x - self.cx, y - self.cy
        return self.sigma * (dx * vx + dy * vy) / self.ctx.hypot(dx, dy)

    def angle(self, x, y):
        """CCW angle of the point past ``theta0`` (arcs) or past 0 (circles), in ``[0, 2 pi)``."""
        ctx = self.ctx
        ang = ctx.atan2(y - self.cy, x - self.cx) - (self.theta0 if self.theta0 is not None else 0)
        return ang % (2 * ctx.pi)

    def extent(self, x, y, tol):
        if self.theta0 is None:
            return 0
        ang = self.angle(x, y)
        atol = tol / self.r
        two_pi = 2 * self.ctx.pi
        if ang <= atol or ang >= two_pi - atol:
            return 1
        if self.span - atol <= ang <= self.span + atol:
            return 2
        if ang < self.span:
            return 0
        return -1

    def place(self, x, y):
        """Radial projection onto the circle."""
        dx, dy = x - self.cx, y - self.cy
        rho = self.ctx.hypot(dx, dy)
        return self.cx + self.r * dx / rho, self.cy + self.r * dy / rho

    def outward_normal(self, x, y):
        dx, dy = x - self.cx, y - self.cy
        rho = self.ctx.hypot(dx, dy)
        return -self.sigma * dx / rho, -self.sigma * dy / rho

    def arclength(self, x, y):
        return self.r * self.angle(x, y)


def _mp_elements(ctx, scene):
    """The scene's elements in mpmath, from the exact values of their floats."""
    f = ctx.mpf
    out = []
    for i, e in enumerate(scene.elements):
        if isinstance(e, Line):
            nx, ny = f(e.normal[0]), f(e.normal[1])
            norm = ctx.hypot(nx, ny)
            out.append(_StraightMp(ctx, i, f(e.point[0]), f(e.point[1]), nx / norm, ny / norm))
        elif isinstance(e, Segment):
            x0, y0, x1, y1 = (f(v) for v in (*e.p0, *e.p1))
            length = ctx.hypot(x1 - x0, y1 - y0)
            ux, uy = (x1 - x0) / length, (y1 - y0) / length
            sgn = 1 if e.side == "left" else -1  # the table's normal is +-J u
            out.append(_StraightMp(ctx, i, x0, y0, -sgn * uy, sgn * ux, (ux, uy), length))
        elif isinstance(e, Circle):
            out.append(_RoundMp(ctx, i, f(e.center[0]), f(e.center[1]), f(e.radius), f(e.sigma)))
        elif isinstance(e, Arc):
            t0, t1 = f(e.theta0), f(e.theta1)
            out.append(_RoundMp(ctx, i, f(e.center[0]), f(e.center[1]), f(e.radius), f(e.sigma),
                                t0, t1 - t0))
        else:
            raise ValueError(f"scene.elements[{i}]: unknown element type {type(e).__name__}")
    return out


# ---------------------------------------------------------------------------- roots
def _polyval(coeffs, t):
    acc = 0
    for c in reversed(coeffs):
        acc = acc * t + c
    return acc


def _polyroots(ctx, coeffs, steps, extra):
    """All complex roots of ``sum(coeffs[k] t^k)`` (ascending coefficients).

    mpmath >= 1.4 takes ascending coefficients with ``asc=True`` and deprecates the
    descending order; older releases know only the descending order.
    """
    if "asc" in inspect.signature(ctx.polyroots).parameters:
        return ctx.polyroots(list(coeffs), maxsteps=steps, extraprec=extra, asc=True)
    return ctx.polyroots(list(reversed(coeffs)), maxsteps=steps, extraprec=extra)


def _real_roots(ctx, coeffs):
    """All real roots of the polynomial with ascending ``coeffs`` (exact zero leading terms dropped)."""
    coeffs = list(coeffs)
    while coeffs and coeffs[-1] == 0:
        coeffs.pop()
    deg = len(coeffs) - 1
    if deg <= 0:
        return []
    if deg == 1:
        return [-coeffs[0] / coeffs[1]]
    if deg == 2:
        c0, c1, c2 = coeffs
        disc = c1 * c1 - 4 * c2 * c0
        if disc < 0:
            return []
        q = -(c1 + ctx.sqrt(disc)) / 2 if c1 >= 0 else -(c1 - ctx.sqrt(disc)) / 2
        if q == 0:  # c1 = c0 = 0: a double root at 0
            return [ctx.zero]
        return sorted([q / c2, c0 / q])
    steps, extra = 400, 2 * ctx.prec
    for _ in range(3):
        try:
            roots = _polyroots(ctx, coeffs, steps, extra)
            break
        except ctx.NoConvergence:
            steps, extra = 4 * steps, 2 * extra
    else:  # pragma: no cover - Durand-Kerner converges for every quartic met so far
        raise ArithmeticError(f"mpmath.polyroots did not converge on {coeffs}")
    return sorted(r for r in roots if isinstance(r, ctx.mpf))


def _exit_roots(ctx, coeffs, deflate, floor):
    """Sorted roots ``t > 0`` where the polynomial changes from + to - (crossing out of the table)."""
    if deflate:  # p(t) = t h(t) with p(0) = 0 exactly: drop the root t = 0
        coeffs = [ctx.zero] + list(coeffs[1:])
    searched = coeffs[1:] if deflate else coeffs
    signs = [c > 0 for c in searched if c != 0]
    if all(sg == signs[0] for sg in signs):  # Descartes: no sign change, no positive root
        return []
    roots = _real_roots(ctx, searched)
    deriv = [k * c for k, c in enumerate(coeffs)][1:]
    out = []
    for t in roots:
        if t <= 0:
            continue
        slope = _polyval(deriv, t)
        size = sum(abs(d) * abs(t) ** k for k, d in enumerate(deriv))
        if slope < -floor * size:
            out.append(t)
    return out


def _flight(x, y, vx, vy, ax, ay, t):
    return x + vx * t + ax * t * t / 2, y + vy * t + ay * t * t / 2


# ---------------------------------------------------------------------------- result
@dataclass
class ReferenceOrbit:
    """A reference orbit at full working precision.

    Attributes
    ----------
    records : dict of str to list of mpf
        Per collision: ``t, x, y, vx, vy, spin`` (just after), ``vx_in, vy_in,
        spin_in`` (just before), ``s`` (arclength on the element) and ``energy``
        ``(|v|^2 + w^2)/2 - a.q``.
    element, corner : list of int
        Element index of each collision and 1 where the corner rule resolved it.
    final : dict of str to mpf
        ``t, x, y, vx, vy, spin`` where the orbit ended.
    stop_reason : str
        One of :data:`noslipsim.core.layout.STOP_REASONS`.
    n_corner : int
        Number of corner collisions.
    dps : int
        Working precision in decimal digits.
    """

    scene: Scene
    dps: int
    start: dict
    records: dict = field(default_factory=lambda: {k: [] for k in RECORDED})
    element: list = field(default_factory=list)
    corner: list = field(default_factory=list)
    final: dict = field(default_factory=dict)
    stop_reason: str = STOP_REASONS[0]
    n_corner: int = 0

    def __len__(self):
        return len(self.element)

    def to_dataset(self):
        """The orbit as an ``xarray.Dataset`` laid out like :func:`noslipsim.simulate` (float64 values)."""
        dim = ("collision",)
        n = len(self.element)
        data = {k: (dim, np.array([float(v) for v in self.records[k]], dtype=float).reshape(n))
                for k in RECORDED}
        data["element"] = (dim, np.array(self.element, dtype=np.int32).reshape(n))
        data["corner"] = (dim, np.array(self.corner, dtype=np.int8).reshape(n))
        for k in FINAL:
            data[f"{k}_final"] = ((), float(self.final[k]))
        data["n_collisions"] = ((), n)
        ds = xr.Dataset(data, coords={"collision": np.arange(n)})
        scene = self.scene
        ds.attrs.update(
            title="noslipsim reference orbit",
            source=f"noslipsim {__version__}",
            stop_reason=self.stop_reason,
            n_corner=int(self.n_corner),
            law=scene.law,
            gamma=scene.gamma,
            force=list(scene.force),
            scene=scene.to_json(),
            start=str(self.start),
            dps=int(self.dps),
        )
        return annotate(ds)


# ---------------------------------------------------------------------------- the event loop
def _validated_limits(scene, q, max_collisions, max_time, stop_below, dps):
    if isinstance(dps, bool) or not isinstance(dps, (int, np.integer)) or dps < MIN_DPS:
        raise ValueError(f"dps: expected an integer >= {MIN_DPS}, got {dps!r}")
    max_collisions, max_time = check_limits(max_collisions, max_time)
    level = None if stop_below is None else finite_float(stop_below, "stop_below")
    if level is not None and level >= q[1]:
        raise ValueError(f"stop_below: {level} must lie below the start height {q[1]}")
    return max_collisions, max_time, level, int(dps)


def _check_scene(scene):
    if not isinstance(scene, Scene):
        raise ValueError(f"scene: expected a noslipsim.Scene, got {type(scene).__name__}")
    if scene.lattice is not None:
        raise ValueError("scene.lattice: periodic scenes are not supported by this version")


def simulate_reference(scene: Scene, position, velocity, spin=0.0, max_collisions=1000,
                       max_time=math.inf, stop_below=None, dps=50, as_mpf=False):
    """Simulate one orbit in mpmath at ``dps`` digits (the reference for :func:`noslipsim.simulate`).

    Parameters
    ----------
    scene : Scene
        Table, law, gamma and force (nondimensional; lattices are not supported).
    position : (float, float)
        Start ``(x, y)``, strictly inside the table.
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
        to float64) and the attribute ``dps``.

    Raises
    ------
    ValueError
        On a bad scene, start, limit, level or precision (as :func:`noslipsim.simulate`).

    Notes
    -----
    The algorithm is described in the module docstring.  At 50 digits a
    collision costs about a tenth of a millisecond per line or segment and a
    few milliseconds per circle or arc under a force: use it for tens to
    hundreds of collisions.
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
    rounding of the input), then the corner rule and the next-hit search run
    exactly as after a hit inside :func:`simulate_reference`.  Times restart
    at 0.

    Parameters
    ----------
    scene : Scene
        Table, law, gamma and force.
    position, velocity : (float, float)
        Post-collision position (on ``element``) and velocity.
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
        On a bad scene, state, element index, limit, level or precision.
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


def _run(scene, q, v, w, resume_element, max_collisions, max_time, level, dps):
    """The event loop at ``dps`` digits; ``resume_element`` is the element just hit, if any."""
    ctx = mpmath.MPContext()
    ctx.dps = dps
    f = ctx.mpf
    elements = _mp_elements(ctx, scene)
    rel_tol = f(10) ** (-(dps // 2))
    slope_floor = f(10) ** (-((2 * dps) // 5))
    scale = f(scene.scale)
    ax, ay = f(scene.force[0]), f(scene.force[1])
    noslip = scene.law == "no-slip"
    g = f(scene.gamma)
    c_law, s_law = (1 - g * g) / (1 + g * g), 2 * g / (1 + g * g)
    t_max = ctx.inf if math.isinf(max_time) else f(max_time)
    level_mp = None if level is None else f(level)

    orbit = ReferenceOrbit(scene=scene, dps=dps,
                           start=dict(position=[float(c) for c in q], velocity=[float(c) for c in v],
                                      spin=float(w)))
    rec = orbit.records
    x, y, vx, vy, w = f(q[0]), f(q[1]), f(v[0]), f(v[1]), f(w)
    t = ctx.zero

    def collide(vx_, vy_, w_, nx, ny):
        tx, ty = -ny, nx  # t = J n, n outward
        vt = vx_ * tx + vy_ * ty
        vn = vx_ * nx + vy_ * ny
        if noslip:
            vt, w_ = -s_law * w_ + c_law * vt, -c_law * w_ - s_law * vt
        vn = -vn
        return vt * tx + vn * nx, vt * ty + vn * ny, w_

    def record(el, vx_in, vy_in, w_in, corner):
        for k, val in zip(("t", "x", "y", "vx", "vy", "spin", "vx_in", "vy_in", "spin_in"),
                          (t, x, y, vx, vy, w, vx_in, vy_in, w_in)):
            rec[k].append(val)
        rec["s"].append(el.arclength(x, y))
        rec["energy"].append((vx * vx + vy * vy + w * w) / 2 - (ax * x + ay * y))
        orbit.element.append(el.index)
        orbit.corner.append(corner)

    def hit_time(el, deflate, tol):
        coeffs = el.crossing(x, y, vx, vy, ax, ay)
        for root in _exit_roots(ctx, coeffs, deflate, slope_floor):
            hx, hy = _flight(x, y, vx, vy, ax, ay, root)
            if el.extent(hx, hy, tol) >= 0:
                return root
        return None

    def leaves_through(el, tol):
        """The particle touches ``el`` (ends inclusive) and leaves its supporting line or circle."""
        if abs(el.distance(x, y)) > tol:
            return False
        if el.extent(x, y, tol) < 0:
            return False
        rate = el.rate(x, y, vx, vy)
        if rate > 0:
            return False
        if rate == 0 and el.crossing(x, y, vx, vy, ax, ay)[2] >= 0:
            return False
        return True

    def slides_off(el):
        """On ``el``, the flight leaves through it at once (first nonzero derivative negative)."""
        for c in el.crossing(x, y, vx, vy, ax, ay)[1:]:
            if c != 0:
                return c < 0
        return False

    current = None
    if resume_element is not None:
        current = elements[resume_element]
        x, y = current.place(x, y)
    n = 0
    stop = "max_collisions"
    while True:
        if current is not None:  # just after a hit on `current`: corner rule, then the grazing check
            bounces = 0
            while n < max_collisions:
                tol = rel_tol * max(scale, abs(x), abs(y))
                other = next((el for el in elements
                              if el is not current and leaves_through(el, tol)), None)
                if other is None:
                    break
                bounces += 1
                if bounces > MAX_CORNER_BOUNCES:
                    stop = "corner"
                    break
                vx_in, vy_in, w_in = vx, vy, w
                vx, vy, w = collide(vx, vy, w, *other.outward_normal(x, y))
                record(other, vx_in, vy_in, w_in, 1)
                n += 1
                orbit.n_corner += 1
                current = other
            if stop == "corner":
                break
            if slides_off(current):
                stop = "grazing"
                break
        if n >= max_collisions:
            break
        # next hit: the earliest exit root over all elements, near-ties to the lower index
        tol = rel_tol * max(scale, abs(x), abs(y))
        best_t, best = None, None
        for el in elements:
            th = hit_time(el, el is current, tol)
            if th is not None and (best_t is None or th < best_t * (1 - rel_tol)):
                best_t, best = th, el
        t_level = None
        if level_mp is not None:
            roots = _exit_roots(ctx, [y - level_mp, vy, ay / 2], False, slope_floor)
            t_level = roots[0] if roots else None
        remaining = t_max - t
        if t_level is not None and (best_t is None or t_level <= best_t) and t_level <= remaining:
            x, y = _flight(x, y, vx, vy, ax, ay, t_level)
            y = level_mp
            vx, vy = vx + ax * t_level, vy + ay * t_level
            t += t_level
            stop = "stop_below"
            break
        if best is None:  # nothing ahead: the orbit leaves for good from its last collision
            stop = "escape"
            break
        if best_t > remaining:
            x, y = _flight(x, y, vx, vy, ax, ay, remaining)
            vx, vy = vx + ax * remaining, vy + ay * remaining
            t = t_max
            stop = "max_time"
            break
        # relocate onto the element, then resolve the collision
        hx, hy = _flight(x, y, vx, vy, ax, ay, best_t)
        vx_in, vy_in, w_in = vx + ax * best_t, vy + ay * best_t, w
        x, y = best.place(hx, hy)
        vx, vy, w = collide(vx_in, vy_in, w, *best.outward_normal(x, y))
        t += best_t
        record(best, vx_in, vy_in, w_in, 0)
        n += 1
        current = best

    orbit.stop_reason = stop
    orbit.final = dict(t=t, x=x, y=y, vx=vx, vy=vy, spin=w)
    return orbit

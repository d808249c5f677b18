"""High-precision reference orbits: the slow, obviously-correct twin of :func:`noslipsim.simulate`.

The same event-driven algorithm as the compiled engine, written again from
the definitions in mpmath at ``dps`` significant digits, on any
:class:`~noslipsim.scenes.Scene` (lines, segments, circles, arcs; with or
without force; no-slip or specular; plain or periodic).  It shares no
numerical code with :mod:`noslipsim.core`; the float64 engine is judged
against it.  The engine's algorithm is described in ``docs/algorithm.md``.

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
4. *Earliest hit.*  The smallest hit time over all elements (on a lattice:
   over the element copies met along the cell walk below); times equal to a
   relative ``10^(-dps/2)`` go to the element met first (lower index, then
   earlier cell).
5. *Relocate and resolve.*  The particle is placed on the element
   (orthogonal projection onto a line, radial onto a circle) and the collision
   law is applied in the frame of ``docs/algorithm.md`` (step 3): ``n`` the
   outward unit normal, ``t = J n = (-n_y, n_x)``,

   .. math::

       w^+ = -c w - s v_t, \\quad v_t^+ = -s w + c v_t, \\quad v_n^+ = -v_n,
       \\qquad c = \\frac{1-\\gamma^2}{1+\\gamma^2}, \\; s = \\frac{2\\gamma}{1+\\gamma^2}

   (no-slip); specular keeps ``v_t`` and ``w`` and reverses ``v_n``.
6. *Corner rule* (as documented in :mod:`noslipsim.core.loop`): every other
   element touched at the hit point (signed distance within ``tol``, in its
   extent within ``tol``: ends inclusive) whose supporting line or circle the
   new velocity leaves (distance rate ``< 0``, or ``= 0`` with a negative
   second coefficient) is hit at once, in index order, as a separate
   collision with ``corner = 1``, except across a reflex junction (one
   piece's end leads off to the other's wall side: the table is locally the
   union of their table sides, and the particle, having just entered one,
   is inside; ``docs/algorithm.md``, step 4); more than
   ``MAX_CORNER_BOUNCES`` in a row stop the orbit (``corner``).  If the element hit last would be left
   through at once the orbit stops (``grazing``).  The kernel's junction gate
   (corner pass only near points where two elements meet) is a shortcut that
   cannot change this rule's outcome, so it has no twin here.

``tol = 10^(-floor(dps/2)) * max(scene scale, |x|, |y|)`` is the only length
tolerance (on a lattice ``x, y`` are measured from the centre of the
particle's cell).  The stop rules follow
:data:`noslipsim.core.layout.STOP_REASONS`: crossing ``stop_below`` downwards
(before or at the next hit), escape (no hit ahead: the state of the last
collision is final, whatever the time limit), the time limit (the state
advanced to it) and the collision budget.

Periodic scenes
---------------
A scene with a ``lattice`` repeats its elements at every ``n1 a1 + n2 a2``.
Positions are kept unfolded (absolute) at full precision; cell ``(n1, n2)`` is
the closed parallelogram of lattice coordinates ``|alpha - n1|, |beta - n2| <= 1/2``
(``q = alpha a1 + beta a2``, by Cramer's rule), and a point's cell is its
nearest lattice site (``nint``, ties to even), as :func:`noslipsim.simulate`
reports ``cell_a1, cell_a2``.  A flight walks the cells it crosses:

* the exit time of a cell is the first time ``>= t_in`` (the entry time) at
  which a lattice coordinate, a polynomial of degree <= 2 in ``t``, crosses a
  face of its strip outwards (which root is the exit follows from the shape of
  the quadratic, never from the sign of a rounded slope, so the entry root is
  never an exit and a tangency is no crossing); a face reached by both
  coordinates at the same time (a lattice corner) steps both indices;
* in each cell the element copies that reach it
  (:func:`noslipsim.lattice.reaching_copies`, a conservative box test) are
  solved on the whole flight from the last collision (step 3; the first hit of
  a copy is remembered for the rest of the flight);
* the walk ends when the earliest hit found so far comes no later than the
  exit time of the current cell: a copy not yet met lies in a later cell, which
  the flight enters only after that exit.

A flight whose path is a straight line along a lattice vector
``P = p a1 + q a2`` (no force and ``v`` parallel to ``P``, or ``v`` parallel to
the force and the force to ``P``; tested in exact rational arithmetic,
``|p|, |q| <= PERIOD_MAX``) repeats its geometry after every ``P``: once it has
covered ``|P|`` (beyond its turning point, under a force) without meeting
anything it never will.  Such an endless flight, or a walk past
``MAX_CELLS_PER_FLIGHT`` cells, ends the orbit as the engine's does: escape,
unless ``stop_below`` or ``max_time`` comes first; an endless flight's time
limit counts as reached first when the engine's walk would reach it within
``MAX_CELLS_PER_FLIGHT`` cells (counted from the face crossings up to the limit).
The copy hit is reported by its element index, with ``s`` measured on that copy.

Inputs are taken at the exact values of their Python floats (``mpf(float)``
is exact).  Element geometry is read from the element objects: segments from
their end points ``p0, p1`` (so adjacent polygon edges share their vertex
exactly), lines from ``point`` and the stored float unit ``normal`` (taken as
an exact direction and renormalised), circles and arcs from ``center``,
``radius``, ``theta0``, ``theta1``; lattice vectors from the scene's floats.  An
arc ends at its float angles, so where it meets a segment (a stadium's
``theta0 = -pi/2`` rounded) the two touch only to about ``1e-16``; orbits aimed
that close to such a junction are beyond what either engine resolves.
"""
from __future__ import annotations

import inspect
import math
from dataclasses import dataclass, field
from fractions import Fraction

import mpmath
import numpy as np
import xarray as xr

from ._validate import finite_float, finite_vector
from ._version import __version__
from .core.layout import STOP_REASONS
from .core.tolerances import MAX_CELLS_PER_FLIGHT, MAX_CORNER_BOUNCES
from .elements import Arc, Circle, Line, Segment
from .lattice import reaching_copies
from .metadata import annotate
from .scenes import Scene
from .simulate import check_limits, check_start

#: Variables recorded per collision (all mpf), in the order of :func:`noslipsim.simulate`.
RECORDED = ("t", "x", "y", "vx", "vy", "spin", "vx_in", "vy_in", "spin_in", "s", "energy")
FINAL = ("t", "x", "y", "vx", "vy", "spin")

#: Smallest working precision accepted: the tolerances are ``10^(-dps/2)``.
MIN_DPS = 20

#: Largest ``|p|, |q|`` of a lattice vector ``P = p a1 + q a2`` along which a straight
#: flight is recognised as periodic (a period then walks about ``|p| + |q|`` cells).
PERIOD_MAX = 1000

#: How far (relative to the length scale) a resumed position may lie from its element.
RESUME_TOL = 1e-9


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

    def end_direction(self, x, y, tol):
        """Unit direction into the segment from the end at ``(x, y)`` (within ``tol``), or None."""
        at = self.extent(x, y, tol)
        if self.u is None or at not in (1, 2):
            return None
        return self.u if at == 1 else (-self.u[0], -self.u[1])

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

    def end_direction(self, x, y, tol):
        """Unit tangent into the arc from the end at ``(x, y)`` (within ``tol``), or None."""
        at = self.extent(x, y, tol)
        if self.theta0 is None or at not in (1, 2):
            return None
        dx, dy = (x - self.cx) / self.r, (y - self.cy) / self.r
        return (-dy, dx) if at == 1 else (dy, -dx)  # counter-clockwise from theta0, clockwise from theta1

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


# ---------------------------------------------------------------------------- copies and cells
class _Copy:
    """An element translated by ``(sx, sy) = o1 a1 + o2 a2`` (plain scenes: ``o1 = o2 = 0``, no shift).

    Each method takes the unfolded position and measures it in the element's own frame.
    """

    __slots__ = ("el", "index", "key", "sx", "sy")

    def __init__(self, el, o1, o2, sx, sy):
        self.el = el
        self.index = el.index
        self.key = (el.index, o1, o2)
        self.sx, self.sy = sx, sy

    def crossing(self, x, y, vx, vy, ax, ay):
        return self.el.crossing(x - self.sx, y - self.sy, vx, vy, ax, ay)

    def distance(self, x, y):
        return self.el.distance(x - self.sx, y - self.sy)

    def rate(self, x, y, vx, vy):
        return self.el.rate(x - self.sx, y - self.sy, vx, vy)

    def extent(self, x, y, tol):
        return self.el.extent(x - self.sx, y - self.sy, tol)

    def end_direction(self, x, y, tol):
        return self.el.end_direction(x - self.sx, y - self.sy, tol)

    def place(self, x, y):
        px, py = self.el.place(x - self.sx, y - self.sy)
        return px + self.sx, py + self.sy

    def outward_normal(self, x, y):
        return self.el.outward_normal(x - self.sx, y - self.sy)

    def arclength(self, x, y):
        return self.el.arclength(x - self.sx, y - self.sy)


def _exact(value):
    """The exact rational value of an mpf."""
    man, exp = value.man_exp
    return Fraction(man) * Fraction(2) ** exp


class _Table:
    """The scene's boundary in mpmath: one copy per element, or on a lattice the copies per cell.

    ``a = (a1x, a1y, a2x, a2y)`` are the lattice vectors; a point's lattice
    coordinates ``(alpha, beta)`` solve ``q = alpha a1 + beta a2`` (Cramer's
    rule), and its cell is the nearest lattice site.
    """

    def __init__(self, ctx, scene):
        self.ctx = ctx
        self.elements = _mp_elements(ctx, scene)
        self.periodic = scene.lattice is not None
        self.scale = ctx.mpf(scene.scale)
        self._copies = {}
        if self.periodic:
            lat = scene.lattice
            raw = (lat["a1"][0], lat["a1"][1], lat["a2"][0], lat["a2"][1])
            self.a = tuple(ctx.mpf(v) for v in raw)
            self.exact_a = tuple(Fraction(v) for v in raw)
            a1x, a1y, a2x, a2y = self.a
            self.det = a1x * a2y - a2x * a1y
            self.reach = [tuple(int(v) for v in row) for row in reaching_copies(scene.elements, lat)]
        else:
            self.reach = [(i, 0, 0) for i in range(len(self.elements))]

    def coordinates(self, x, y):
        """``(alpha, beta)`` with ``(x, y) = alpha a1 + beta a2`` (a point, a velocity or a force)."""
        a1x, a1y, a2x, a2y = self.a
        return (x * a2y - y * a2x) / self.det, (a1x * y - a1y * x) / self.det

    def shift(self, n1, n2):
        """``n1 a1 + n2 a2``."""
        a1x, a1y, a2x, a2y = self.a
        return n1 * a1x + n2 * a2x, n1 * a1y + n2 * a2y

    def cell(self, x, y):
        """Indices of the cell holding ``(x, y)``: the nearest lattice site ((0, 0) for plain scenes)."""
        if not self.periodic:
            return 0, 0
        alpha, beta = self.coordinates(x, y)
        return int(self.ctx.nint(alpha)), int(self.ctx.nint(beta))

    def length(self, x, y):
        """The length scale of tolerances at ``(x, y)``: ``max(scale, |x|, |y|)`` from the cell's centre."""
        if self.periodic:
            ox, oy = self.shift(*self.cell(x, y))
            x, y = x - ox, y - oy
        return max(self.scale, abs(x), abs(y))

    def copy(self, e, o1, o2):
        key = (e, o1, o2)
        c = self._copies.get(key)
        if c is None:
            sx, sy = self.shift(o1, o2) if self.periodic else (self.ctx.zero, self.ctx.zero)
            c = self._copies[key] = _Copy(self.elements[e], o1, o2, sx, sy)
        return c

    def copies_at(self, d1, d2):
        """The element copies that reach cell ``(d1, d2)``, in element order (plain scenes: every element)."""
        return [self.copy(e, o1 + d1, o2 + d2) for e, o1, o2 in self.reach]

    def period(self, vx, vy, ax, ay):
        """The length ``|P|`` of the lattice vector along which the flight's path is a straight line, or None.

        Exact: the path is straight when ``a = 0`` or ``v x a = 0``, and a
        lattice vector ``p a1 + q a2`` is parallel to its direction ``u`` when
        ``p (a1 x u) + q (a2 x u) = 0``, solved in rationals.
        """
        if not self.periodic:
            return None
        v = (_exact(vx), _exact(vy))
        a = (_exact(ax), _exact(ay))
        if a != (0, 0):
            if v[0] * a[1] - v[1] * a[0] != 0:
                return None
            u = a
        else:
            u = v
        a1x, a1y, a2x, a2y = self.exact_a
        ca = a1x * u[1] - a1y * u[0]
        cb = a2x * u[1] - a2y * u[0]
        if ca == 0:
            p, q = 1, 0
        elif cb == 0:
            p, q = 0, 1
        else:
            ratio = -cb / ca  # = p / q in lowest terms
            p, q = ratio.numerator, ratio.denominator
        if max(abs(p), abs(q)) > PERIOD_MAX:
            return None
        return self.ctx.hypot(*self.shift(p, q))


def _face_exit(ctx, coeffs, face, outward, t_in):
    """When a flight inside the strip at ``t_in`` leaves it through ``face`` (``inf``: never).

    ``alpha(t)`` has ascending ``coeffs`` (degree <= 2); ``outward = +1`` for the
    upper face, ``-1`` for the lower one.  With ``g = outward (alpha - face)``,
    the flight is on the strip's side of the face where ``g <= 0``: on an
    interval ``[lo, hi]`` between the roots of ``g`` (``g2 > 0``: it leaves at
    ``hi``), before ``lo`` or after ``hi`` (``g2 < 0``: it leaves at ``lo`` if it is
    in the first part, never if it entered at ``hi``), or before the root of a
    linear ``g`` that increases.  The walk asks only from inside, so which
    root is the exit follows from the shape of ``g``, never from the sign of a
    rounded slope (the root the flight entered through is never taken for an
    exit, a tangency is no crossing), and an exit computed a rounding before
    ``t_in`` is ``t_in``.
    """
    g0, g1, g2 = outward * (coeffs[0] - face), outward * coeffs[1], outward * coeffs[2]
    if g2 == 0:
        return max(-g0 / g1, t_in) if g1 > 0 else ctx.inf
    disc = g1 * g1 - 4 * g2 * g0
    if g2 < 0 and disc <= 0:  # g <= 0 at all times: never leaves through this face
        return ctx.inf
    if disc < 0:  # g > 0 at all times: the flight is not on this side (a rounding at a face): leave at once
        return t_in
    if disc == 0:  # inside only where g touches 0
        return max(-g1 / (2 * g2), t_in)
    qq = -(g1 + ctx.sqrt(disc)) / 2 if g1 >= 0 else -(g1 - ctx.sqrt(disc)) / 2
    lo, hi = sorted((qq / g2, g0 / qq))  # the roots, without cancellation
    if g2 > 0:
        return max(hi, t_in)
    return max(lo, t_in) if t_in < (lo + hi) / 2 else ctx.inf


def _strip_exit(ctx, coeffs, d, t_in):
    """Exit ``(t, step)`` of ``alpha(t)`` from the strip ``[d - 1/2, d + 1/2]`` after ``t_in``.

    ``step = +1`` through the upper face, ``-1`` through the lower one, 0 if it never leaves.
    """
    half = ctx.mpf(0.5)
    t_up = _face_exit(ctx, coeffs, d + half, 1, t_in)
    t_dn = _face_exit(ctx, coeffs, d - half, -1, t_in)
    if t_up <= t_dn and t_up < ctx.inf:
        return t_up, 1
    if t_dn < ctx.inf:
        return t_dn, -1
    return ctx.inf, 0


def _faces_crossed(ctx, coeffs, t_end):
    """Number of half-integers ``alpha(t)`` (degree <= 2) passes over ``(0, t_end)``."""
    c0, c1, c2 = coeffs
    cuts = [ctx.zero, t_end]
    if c2 != 0:
        t_turn = -c1 / (2 * c2)
        if 0 < t_turn < t_end:
            cuts.insert(1, t_turn)
    total = 0
    half = ctx.mpf(0.5)
    for t0, t1 in zip(cuts, cuts[1:]):
        u0 = c0 + t0 * (c1 + c2 * t0)
        u1 = c0 + t1 * (c1 + c2 * t1)
        total += abs(int(ctx.floor(u1 + half)) - int(ctx.floor(u0 + half)))
    return total


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
    cells : list of (int, int)
        Periodic scenes: the cell ``(cell_a1, cell_a2)`` holding each collision point.
    final : dict of str to mpf
        ``t, x, y, vx, vy, spin`` where the orbit ended.
    final_cell : (int, int)
        Periodic scenes: the cell holding the final position.
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
    cells: list = field(default_factory=list)
    final: dict = field(default_factory=dict)
    final_cell: tuple = (0, 0)
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
        if self.scene.lattice is not None:
            cells = np.array(self.cells, dtype=np.int64).reshape(n, 2)
            data["cell_a1"] = (dim, cells[:, 0])
            data["cell_a2"] = (dim, cells[:, 1])
            data["cell_a1_final"] = ((), np.int64(self.final_cell[0]))
            data["cell_a2_final"] = ((), np.int64(self.final_cell[1]))
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
    The algorithm is described in the module docstring.  At 50 digits a
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


def _run(scene, q, v, w, resume_element, max_collisions, max_time, level, dps):
    """The event loop at ``dps`` digits; ``resume_element`` is the element just hit, if any."""
    max_cells = MAX_CELLS_PER_FLIGHT  # read at each call, so a test may lower it
    ctx = mpmath.MPContext()
    ctx.dps = dps
    f = ctx.mpf
    table = _Table(ctx, scene)
    rel_tol = f(10) ** (-(dps // 2))
    slope_floor = f(10) ** (-((2 * dps) // 5))
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

    def record(copy, vx_in, vy_in, w_in, corner):
        for k, val in zip(("t", "x", "y", "vx", "vy", "spin", "vx_in", "vy_in", "spin_in"),
                          (t, x, y, vx, vy, w, vx_in, vy_in, w_in)):
            rec[k].append(val)
        rec["s"].append(copy.arclength(x, y))
        rec["energy"].append((vx * vx + vy * vy + w * w) / 2 - (ax * x + ay * y))
        orbit.element.append(copy.index)
        orbit.corner.append(corner)
        orbit.cells.append(table.cell(x, y))

    def first_hit(copy, deflate, tol):
        """The first exit root of the whole flight through ``copy`` within its extent, or None."""
        coeffs = copy.crossing(x, y, vx, vy, ax, ay)
        for root in _exit_roots(ctx, coeffs, deflate, slope_floor):
            hx, hy = _flight(x, y, vx, vy, ax, ay, root)
            if copy.extent(hx, hy, tol) >= 0:
                return root
        return None

    def leaves_through(copy, tol):
        """The particle touches ``copy`` (ends inclusive) and leaves its supporting line or circle."""
        if abs(copy.distance(x, y)) > tol:
            return False
        if copy.extent(x, y, tol) < 0:
            return False
        rate = copy.rate(x, y, vx, vy)
        if rate > 0:
            return False
        if rate == 0 and copy.crossing(x, y, vx, vy, ax, ay)[2] >= 0:
            return False
        return True

    def reflex(current, other, tol):
        """The two pieces meet here at a reflex junction of the table (its angle exceeds pi).

        Where one piece ends at the point, the table lies locally on the table
        side of either piece (the union of the half planes) when that end
        leads off to the other piece's wall side: having just reflected into
        the table side of ``current``, the particle is inside, whatever
        ``other``'s line says.  (A point inside both pieces, a full circle or a
        line has no end here: not reflex.)
        """
        for a, b in ((other, current), (current, other)):
            u = a.end_direction(x, y, tol)
            if u is not None:
                nx, ny = b.outward_normal(x, y)
                return u[0] * nx + u[1] * ny > 0  # a's end leads into b's wall side
        return False

    def slides_off(copy):
        """On ``copy``, the flight leaves through it at once (first nonzero derivative negative)."""
        for c in copy.crossing(x, y, vx, vy, ax, ay)[1:]:
            if c != 0:
                return c < 0
        return False

    def next_hit(current, t_limit):
        """``(t, copy, gave_up)``: the earliest hit ahead (or None), and whether the search gave up.

        Plain scenes: every element, over all times (``gave_up``: nothing ahead).
        Lattices: the cell walk of the module docstring; ``gave_up`` when the
        flight is endless or the walk passes ``max_cells`` cells (an escape
        unless a limit comes first).  The walk may stop at ``t_limit`` with no
        hit found (or one beyond the limit).
        """
        tol = rel_tol * table.length(x, y)
        met = {}
        best = [None, None]

        def test(copies):
            for c in copies:
                if c.key in met:
                    continue
                th = met[c.key] = first_hit(c, c is current, tol)
                if th is not None and (best[0] is None or th < best[0] * (1 - rel_tol)):
                    best[0], best[1] = th, c

        if not table.periodic:
            test(table.copies_at(0, 0))
            return best[0], best[1], best[1] is None
        # lattice coordinates along the flight, ascending coefficients in t
        (p0, r0), (p1, r1), (p2, r2) = (table.coordinates(x, y), table.coordinates(vx, vy),
                                        table.coordinates(ax, ay))
        alpha, beta = [p0, p1, p2 / 2], [r0, r1, r2 / 2]
        d1, d2 = table.cell(x, y)
        t_in = ctx.zero
        ta, sa = _strip_exit(ctx, alpha, d1, t_in)
        tb, sb = _strip_exit(ctx, beta, d2, t_in)
        period = table.period(vx, vy, ax, ay)
        if period is not None:
            # the path is straight and repeats after `period`; it is monotone after t_turn
            acc = ctx.hypot(ax, ay)
            t_turn = ctx.zero if acc == 0 else max(ctx.zero, -(vx * ax + vy * ay) / (acc * acc))
            x_turn, y_turn = _flight(x, y, vx, vy, ax, ay, t_turn)
        for _ in range(max_cells):
            t_out = min(ta, tb)
            test(table.copies_at(d1, d2))
            if best[0] is not None and best[0] <= t_out:
                return best[0], best[1], False
            if t_out >= t_limit:  # the limit comes first (or the flight never leaves this cell: nothing ahead)
                return best[0], best[1], best[0] is None and t_out == ctx.inf
            if best[0] is None and period is not None and t_out > t_turn:
                xo, yo = _flight(x, y, vx, vy, ax, ay, t_out)
                if ctx.hypot(xo - x_turn, yo - y_turn) > period + tol:  # a full period met nothing
                    if t_limit == ctx.inf:
                        return None, None, True
                    cells = 1 + _faces_crossed(ctx, alpha, t_limit) + _faces_crossed(ctx, beta, t_limit)
                    return None, None, cells > max_cells
            if ta == t_out:
                d1 += sa
                ta, sa = _strip_exit(ctx, alpha, d1, t_out)
            if tb == t_out:
                d2 += sb
                tb, sb = _strip_exit(ctx, beta, d2, t_out)
        return None, None, True

    current = None
    if resume_element is not None:
        current = _resumed_copy(table, resume_element, x, y)
        x, y = current.place(x, y)
    n = 0
    stop = "max_collisions"
    while True:
        if current is not None:  # just after a hit on `current`: corner rule, then the grazing check
            bounces = 0
            while n < max_collisions:
                tol = rel_tol * table.length(x, y)
                other = next((c for c in table.copies_at(*table.cell(x, y))
                              if c.key != current.key and leaves_through(c, tol)
                              and not reflex(current, c, tol)), None)
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
        t_level = None
        if level_mp is not None:
            roots = _exit_roots(ctx, [y - level_mp, vy, ay / 2], False, slope_floor)
            t_level = roots[0] if roots else None
        remaining = t_max - t
        t_limit = remaining if t_level is None else min(remaining, t_level)
        best_t, best, gave_up = next_hit(current, t_limit)
        if t_level is not None and (best_t is None or t_level <= best_t) and t_level <= remaining:
            x, y = _flight(x, y, vx, vy, ax, ay, t_level)
            y = level_mp
            vx, vy = vx + ax * t_level, vy + ay * t_level
            t += t_level
            stop = "stop_below"
            break
        if best is None and gave_up:  # nothing ahead: the orbit leaves for good from its last collision
            stop = "escape"
            break
        if best is None or best_t > remaining:
            x, y = _flight(x, y, vx, vy, ax, ay, remaining)
            vx, vy = vx + ax * remaining, vy + ay * remaining
            t = t_max
            stop = "max_time"
            break
        # relocate onto the element copy, then resolve the collision
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
    orbit.final_cell = table.cell(x, y)
    return orbit

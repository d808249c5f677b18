"""The scene's elements in mpmath: the exact twins of lines, segments, circles and arcs.

Each element answers the questions the algorithm of :mod:`noslipsim.reference`
asks about one piece of boundary: its crossing polynomial along a flight
(step 1), its signed distance, distance rate and extent (steps 3 and 6), the
projection onto it and its outward normal (step 5), and where an end leads
(the reflex-junction test of step 6).  :class:`_Copy` moves an element to a
lattice cell without rounding the particle's unfolded position.
"""
from __future__ import annotations

from ..elements import Arc, Circle, Line, Segment


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
        """Signed distance from the line, positive on the table side."""
        return (x - self.px) * self.nx + (y - self.py) * self.ny

    def rate(self, x, y, vx, vy):
        """Rate of change of :meth:`distance` at velocity ``(vx, vy)``."""
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
        """Unit normal out of the table (into the wall)."""
        return -self.nx, -self.ny

    def arclength(self, x, y):
        """The coordinate ``s`` of the point along the element, as :func:`noslipsim.simulate` reports it."""
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
        """Signed distance from the circle, positive on the table side."""
        return self.sigma * (self.ctx.hypot(x - self.cx, y - self.cy) - self.r)

    def rate(self, x, y, vx, vy):
        """Rate of change of :meth:`distance` at velocity ``(vx, vy)``."""
        dx, dy = x - self.cx, y - self.cy
        return self.sigma * (dx * vx + dy * vy) / self.ctx.hypot(dx, dy)

    def angle(self, x, y):
        """CCW angle of the point past ``theta0`` (arcs) or past 0 (circles), in ``[0, 2 pi)``."""
        ctx = self.ctx
        ang = ctx.atan2(y - self.cy, x - self.cx) - (self.theta0 if self.theta0 is not None else 0)
        return ang % (2 * ctx.pi)

    def extent(self, x, y, tol):
        """-1 outside, 0 interior, 1 at ``theta0``, 2 at ``theta1`` (ends within ``tol``; circles: 0)."""
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
        """Unit normal out of the table (into the wall), along the radius."""
        dx, dy = x - self.cx, y - self.cy
        rho = self.ctx.hypot(dx, dy)
        return -self.sigma * dx / rho, -self.sigma * dy / rho

    def arclength(self, x, y):
        """The coordinate ``s``: arclength counter-clockwise from ``theta0`` (circles: from angle 0)."""
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

    # each method forwards to the element, with the position moved into the element's frame

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


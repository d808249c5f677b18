r"""Thermostatted flights in mpmath: the closed-form path and a certified search for its crossings.

The twin of :mod:`noslipsim.core.thermostat` and :mod:`noslipsim.core.thermo_events`,
written again from the definitions and sharing no code with them.  Between
collisions ``dv/dt = F - alpha v``, ``alpha = F.v/|v|^2``: the speed ``c`` is
constant and ``u = tan(phi/2) = u0 exp(-k t)`` (``phi`` the heading from the
field, ``k = E/c``).  At ``dps`` digits the plain forms suffice:

.. math::

    x' = \frac{c}{k} \ln\frac{u_0 (1 + u^2)}{u (1 + u_0^2)}, \qquad
    y' = \frac{2c}{k} (\arctan u_0 - \arctan u)

in the field frame (``x'`` along ``F``, ``y' = J x'``), with the straight
flights along and against the field (``u0 = 0``, ``u0 = inf``) apart.
``tests/test_thermostat_reference.py`` checks these against mpmath's Taylor
integrator (:func:`mpmath.odefun`) of the equations of motion themselves.

Crossings.  A crossing function ``g(t)`` (positive on the table side: a line's
signed distance, ``sigma (|q - c|^2 - r^2)`` for a circle, a lattice strip's
distance to a face) has a bound ``M`` on ``|g''|`` over any window ``[a, b]``
(``|dv/dt| = E |sin phi| <= E``).  The window is cut in halves until on each
piece either (1) ``g`` keeps its sign (both ends beyond ``M h^2 / 8`` of zero,
the most a function with ``|g''| <= M`` can dip below its chord), or (2) ``g``
is monotone (``|g'(mid)| > M h / 2``), where a sign change is one root, an
exit if ``g`` falls, found by bisection to the working precision.  Pieces
narrower than the working precision that fit neither case are tangencies to
that precision (an exit only if ``g`` changes sign from + to - across it).
Pieces are taken from left to right, so the first exit found is the first.
An unbounded window is cut where the path certainly leaves for good: past a
bounded element along the field, moving along it (``cos phi >= 0`` then for
ever), or where a line's ``g'`` is at least 0 from then on.
"""
from __future__ import annotations


class ThermoPath:
    """The thermostatted path from ``(x, y)`` with velocity ``(vx, vy)`` in the field ``(ax, ay)`` (mpf, ``E > 0``)."""

    def __init__(self, ctx, x, y, vx, vy, ax, ay):
        self.ctx = ctx
        self.x, self.y, self.vx, self.vy, self.ax, self.ay = x, y, vx, vy, ax, ay
        self.E = ctx.hypot(ax, ay)
        self.fx, self.fy = ax / self.E, ay / self.E
        self.c = ctx.hypot(vx, vy)
        self.k = self.E / self.c
        vp = (vx * self.fx + vy * self.fy) / self.c       # cos phi0
        vq = (vy * self.fx - vx * self.fy) / self.c       # sin phi0
        self.phi0 = ctx.atan2(vq, vp)
        self.straight = vq == 0                             # along (phi0 = 0) or against (phi0 = pi) the field
        self.u0 = None if self.straight else ctx.tan(self.phi0 / 2)

    # ------------------------------------------------------------------ the path
    def heading(self, t):
        """``phi(t)``, the heading from the field."""
        if self.straight:
            return self.phi0
        return 2 * self.ctx.atan(self.u0 * self.ctx.exp(-self.k * t))

    def frame_move(self, t):
        """``(dx', dy')``: the move in the field frame after time ``t``."""
        ctx, c, k = self.ctx, self.c, self.k
        if self.straight:
            return c * t * ctx.cos(self.phi0), ctx.zero
        u0 = self.u0
        u = u0 * ctx.exp(-k * t)
        if t == 0:
            return ctx.zero, ctx.zero
        dx = (c / k) * ctx.log(u0 * (1 + u * u) / (u * (1 + u0 * u0)))
        dy = (2 * c / k) * (ctx.atan(u0) - ctx.atan(u))
        return dx, dy

    def position(self, t):
        """``(x, y)`` after time ``t``."""
        dx, dy = self.frame_move(t)
        return self.x + dx * self.fx - dy * self.fy, self.y + dx * self.fy + dy * self.fx

    def velocity(self, t):
        """``(vx, vy)`` after time ``t``."""
        phi = self.heading(t)
        cp, sp = self.c * self.ctx.cos(phi), self.c * self.ctx.sin(phi)
        return cp * self.fx - sp * self.fy, cp * self.fy + sp * self.fx

    def acceleration(self, t):
        """``F - alpha v`` after time ``t``."""
        return accel(self.ax, self.ay, *self.velocity(t))

    def along_field(self, t):
        """``cos phi(t) >= 0``: from ``t`` on the particle moves along the field for ever."""
        return self.ctx.cos(self.heading(t)) >= 0

    def field_coordinate(self, t):
        """``x'`` of the position at ``t`` (along the field)."""
        px, py = self.position(t)
        return px * self.fx + py * self.fy


def accel(ax, ay, vx, vy):
    """The thermostatted acceleration ``F - (F.v/|v|^2) v``."""
    alpha = (ax * vx + ay * vy) / (vx * vx + vy * vy)
    return ax - alpha * vx, ay - alpha * vy


# ---------------------------------------------------------------------- certified crossings
def first_exit(ctx, g, dg, bound, lo, hi, skip=None):
    """The first exit root in ``(lo, hi]`` (finite) of ``g``, certified by ``|g''| <= bound(a, b)`` on ``[a, b]``.

    ``g`` is positive on the table side; an exit is a root where ``g`` changes
    from + to -.  ``skip(t)`` may reject a root (an exit outside an element's
    extent); the search then goes on.  Returns the root or None.
    """
    eps = ctx.mpf(2) ** (-ctx.prec + 8)
    width = eps * max(abs(hi), ctx.one)
    stack = [(hi, g(hi), lo, g(lo))]  # right end first: pop() takes the leftmost piece
    while stack:
        b, gb, a, ga = stack.pop()
        h = b - a
        M = bound(a, b)
        dip = M * h * h / 8
        if (ga > dip and gb > dip) or (ga < -dip and gb < -dip):
            continue
        m = (a + b) / 2
        slope = dg(m)
        if abs(slope) > M * h / 2 or h <= width:  # monotone on [a, b], or a tangency to the working precision
            if ga > 0 and gb <= 0 and ((abs(slope) > M * h / 2 and slope < 0) or h <= width):
                root = b if gb == 0 else _bisect(ctx, g, a, b, width)
                if skip is None or not skip(root):
                    return root
            continue
        gm = g(m)
        stack.append((b, gb, m, gm))
        stack.append((m, gm, a, ga))
    return None


def _bisect(ctx, g, a, b, width):
    """Root of ``g`` in ``[a, b]`` with ``g(a) > 0 >= g(b)``, to ``width``; the end with ``g <= 0``."""
    while b - a > width / 4:
        m = (a + b) / 2
        if g(m) > 0:
            a = m
        else:
            b = m
    return b if g(b) == 0 else (a + b) / 2


def horizon(ctx, path, done, start=None):
    """A finite time ``T`` after which ``done(T)`` certifies that nothing happens any more (doubling from ``start``)."""
    T = start if start is not None else max(1 / path.k, ctx.one / path.c)
    for _ in range(4000):
        if done(T):
            return T
        T *= 2
    raise ArithmeticError("reference: no finite horizon found for a thermostatted flight")


def line_first_exit(ctx, path, nx, ny, f0, lo, hi=None, skip=None, bounded=None):
    """First exit in ``(lo, hi]`` of ``f(t) = f0 + n . (q(t) - q(0))`` (``hi`` None: for ever), or None.

    ``bounded``: the largest field coordinate ``x'`` of a bounded element
    (a segment), past which the search may stop; None for a line or strip,
    whose search stops where ``f`` keeps its sign for ever (``f'`` keeps the
    sign of both its value now and along the field, the ends of the arc of
    headings still to come).
    """
    q0 = (path.x, path.y)
    g = lambda t: f0 + nx * (path.position(t)[0] - q0[0]) + ny * (path.position(t)[1] - q0[1])  # noqa: E731
    dg = lambda t: nx * path.velocity(t)[0] + ny * path.velocity(t)[1]  # noqa: E731
    M = ctx.hypot(nx, ny) * path.E
    bound = lambda a, b: M  # noqa: E731
    if hi is not None:
        return first_exit(ctx, g, dg, bound, lo, hi, skip)
    along = nx * path.fx + ny * path.fy  # f' once the heading has turned to the field (over c)
    across = ny * path.fx - nx * path.fy  # n . J F
    # a flight across the field's direction (n . F = 0) tends to f0 + n . (J F) (c / k) phi0
    limit = None if along != 0 or path.straight else f0 + across * (path.c / path.k) * path.phi0

    def keeps_sign(gT, slope_now, slope_later):
        return (gT > 0 and slope_now >= 0 and slope_later >= 0) or (gT < 0 and slope_now <= 0 and slope_later <= 0)

    def done(T):
        if T <= lo:
            return False
        if bounded is not None:
            return path.along_field(T) and path.field_coordinate(T) > bounded
        gT, dT = g(T), dg(T)
        if path.straight:
            return keeps_sign(gT, dT, dT)
        if not path.along_field(T):  # the headings still to come may span more than a half turn
            return False
        if keeps_sign(gT, dT, along):
            return True
        # monotone towards its limit: a limit on the same side ends the search too
        return limit is not None and ((gT > 0 and limit > 0) or (gT < 0 and limit < 0))

    T = horizon(ctx, path, done, start=lo + max(1 / path.k, ctx.one / path.c))
    return first_exit(ctx, g, dg, bound, lo, T, skip)

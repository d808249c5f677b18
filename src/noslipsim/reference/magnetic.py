r"""Magnetic flights in mpmath: the cyclotron path and its crossings, written from the definitions.

The twin of :mod:`noslipsim.core.magnetic`, sharing no code with it.  Between
collisions ``dv/dt = W J v`` (``W = Scene.magnetic``, ``J (a, b) = (-b, a)``);
with ``theta = W t``, ``S = sin(theta)/W`` and ``Q = (1 - cos(theta))/W``

.. math::

    x(t) = x_0 + S v_0 + Q J v_0, \qquad v(t) = \cos\theta\, v_0 + \sin\theta\, J v_0 .

At ``dps`` digits the plain forms suffice (a field as weak as ``W t = 1e-12``
costs 24 of them in ``1 - cos``).  Along the path every crossing function the
event loop asks about (a line's or lattice face's signed distance, a circle's
``sigma (|x - p|^2 - r^2)``, a level's height) has the form
``g(t) = g_0 + a S + b Q``, so that ``W g = 0`` reads

.. math::

    A \cos\theta + B \sin\theta = C, \qquad A = b, \; B = -a, \; C = W g_0 + b,

with the roots ``theta = atan2(B, A) +- acos(C / hypot(A, B))`` when
``|C| <= hypot(A, B)``, taken into one period ``(0, 2 pi/|W|)``: the path is
closed, so a crossing not met in one period is never met.  A root is an exit
where ``g' = a cos(theta) + b sin(theta)`` is negative beyond the noise floor
of the event loop (a tangency, ``|C| = hypot(A, B)``, has ``g' = 0`` and is no
exit).  On the element just hit ``g_0 = 0`` and ``C = A`` exactly: its roots
are ``theta = 0`` (the collision itself, removed analytically) and
``theta = 2 atan2(B, A)``.  For a circle about ``p`` (``d = x_0 - p``):
``g_0 = sigma (|d|^2 - r^2)``, ``a = 2 sigma d . v_0``,
``b = 2 sigma (d . J v_0 + c^2 / W)`` (from ``|S v + Q J v|^2 = 2 Q c^2 / W``).
"""
from __future__ import annotations

from .elements import _StraightMp

#: Stop reason of a magnetic orbit whose cyclotron circle meets no element after its last event: it
#: circles for ever (the reference's own; the compiled engine has no magnetic flight yet).
PINNED = "pinned"


class MagneticPath:
    """The cyclotron path from ``(x, y)`` with velocity ``(vx, vy)`` at the frequency ``W != 0`` (mpf)."""

    def __init__(self, ctx, x, y, vx, vy, W):
        self.ctx = ctx
        self.x, self.y, self.vx, self.vy, self.W = x, y, vx, vy, W
        self.jx, self.jy = -vy, vx
        self.c2 = vx * vx + vy * vy
        self.T = 2 * ctx.pi / abs(W)

    def position(self, t):
        """``(x, y)`` after time ``t``."""
        th = self.W * t
        S = self.ctx.sin(th) / self.W
        Q = (1 - self.ctx.cos(th)) / self.W
        return self.x + S * self.vx + Q * self.jx, self.y + S * self.vy + Q * self.jy

    def velocity(self, t):
        """``(vx, vy)`` after time ``t``."""
        th = self.W * t
        cs, sn = self.ctx.cos(th), self.ctx.sin(th)
        return cs * self.vx + sn * self.jx, cs * self.vy + sn * self.jy

    def centre(self):
        """``(mx, my, radius)`` of the cyclotron circle: ``x_0 + J v_0 / W`` and ``c / |W|``."""
        return self.x + self.jx / self.W, self.y + self.jy / self.W, self.ctx.sqrt(self.c2) / abs(self.W)

    def local(self):
        """``(x, y, vx, vy, ax, ay)``: the flight's second-order expansion at ``t = 0`` (``a = W J v``).

        The corner and grazing rules read the first two derivatives of a crossing function there.
        """
        return self.x, self.y, self.vx, self.vy, self.W * self.jx, self.W * self.jy

    # ------------------------------------------------------------------ crossing functions
    def line_terms(self, g0, nx, ny):
        """``(g0, a, b)`` of ``g0 + n . (x(t) - x_0)`` (``n`` need not be a unit vector)."""
        return g0, nx * self.vx + ny * self.vy, nx * self.jx + ny * self.jy

    def circle_terms(self, cx, cy, r, sigma, deflate):
        """``(g0, a, b)`` of ``sigma (|x(t) - c|^2 - r^2)``."""
        dx, dy = self.x - cx, self.y - cy
        g0 = self.ctx.zero if deflate else sigma * (dx * dx + dy * dy - r * r)
        a = 2 * sigma * (dx * self.vx + dy * self.vy)
        b = 2 * sigma * (dx * self.jx + dy * self.jy + self.c2 / self.W)
        return g0, a, b

    def exits(self, g0, a, b, deflate, floor):
        """Sorted exit times in ``(0, T)`` of ``g0 + a S + b Q`` (``deflate``: ``g0 = 0``, the root 0 removed)."""
        ctx, W = self.ctx, self.W
        A, B = b, -a
        phi0 = ctx.atan2(B, A)
        if deflate:
            thetas = [2 * phi0]
        else:
            C = W * g0 + b
            rho = ctx.hypot(A, B)
            if rho == 0 or abs(C) > rho:
                return []
            alpha = ctx.acos(C / rho)
            thetas = [phi0 - alpha, phi0 + alpha]
        out = []
        for th in thetas:
            t = th / W
            t -= self.T * ctx.floor(t / self.T)  # into [0, T)
            if not 0 < t < self.T:
                continue
            sn, cs = ctx.sin(W * t), ctx.cos(W * t)
            if a * cs + b * sn < -floor * (abs(a) + abs(b)):
                out.append(t)
        return sorted(out)


def first_hit(ctx, path, copy, deflate, tol, floor):
    """The first exit time in ``(0, T)`` through ``copy`` within its extent, or None (never, on any turn)."""
    el = copy.el
    if isinstance(el, _StraightMp):  # a line or segment: its table-side normal
        g0 = ctx.zero if deflate else copy.distance(path.x, path.y)
        terms = path.line_terms(g0, el.nx, el.ny)
    else:
        terms = path.circle_terms(el.cx + copy.sx, el.cy + copy.sy, el.r, el.sigma, deflate)
    for t in path.exits(*terms, deflate, floor):
        if copy.extent(*path.position(t), tol) >= 0:
            return t
    return None


def level_exit(ctx, path, level, floor):
    """When the path first crosses the height ``level`` downwards in ``(0, T)``, or None."""
    roots = path.exits(*path.line_terms(path.y - level, ctx.zero, ctx.one), False, floor)
    return roots[0] if roots else None


def face_exit(ctx, path, g0, gx, gy, t_in, floor):
    """When the path, on the inner side of the face ``g0 + G . (x(t) - x_0) >= 0`` at ``t_in``, leaves it, or inf.

    Within one period after ``t_in``'s turn began: a face left before ``t_in``
    (and entered again) is left next only in the following period, which the
    walk never needs (it stops at ``T``).  On or past the face at ``t_in`` and
    moving out, it leaves at once.
    """
    px, py = path.position(t_in)
    vx, vy = path.velocity(t_in)
    if g0 + gx * (px - path.x) + gy * (py - path.y) <= 0 and gx * vx + gy * vy < 0:
        return t_in
    for t in path.exits(*path.line_terms(g0, gx, gy), False, floor):
        if t >= t_in:
            return t
    return ctx.inf

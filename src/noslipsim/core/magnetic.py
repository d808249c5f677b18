r"""Magnetic flights: the closed-form cyclotron path and its exits through lines and circles.

A constant field normal to the table turns the velocity at the cyclotron
angular frequency ``W`` (``Scene.magnetic``; not the spin ``w``):
``dv/dt = W J v`` with ``J (a, b) = (-b, a)``.  The speed ``c = |v|`` and the
spin are constant in flight; with ``theta = W t``

.. math::

    v(t) = \cos\theta\, v_0 + \sin\theta\, J v_0, \qquad
    x(t) = x_0 + \frac{\sin\theta}{W} v_0 + \frac{2 \sin^2(\theta/2)}{W} J v_0,

a circle of radius ``c/|W|`` about ``x_0 + J v_0 / W``, run counter-clockwise
for ``W > 0``.  The half-angle form, and the series below ``|theta| = 1e-8``,
keep ``W -> 0`` (the straight flight) free of cancellation and of a division
by a tiny ``W``.  A line's signed distance or a circle's
``sigma (|x - p|^2 - r^2)`` along the path is ``g = g_0 + a S + b Q``
(``S = sin(theta)/W``, ``Q = (1 - cos(theta))/W``); in the tangent half-angle
``zeta = 2 tan(theta/2) / W`` (``= t`` for ``W = 0``) it is the quadratic

.. math::

    (1 + \tan^2(\theta/2))\, g = c_0 + c_1 \zeta + c_2 \zeta^2, \qquad
    c_0 = g_0, \; c_1 = a, \; c_2 = W b / 2 + W^2 g_0 / 4,

so an element is met at most once per period, at the exit root (where the
quadratic falls), or never.  Its time, deflation and certified grazing
(:data:`GRAZE_ULPS`): docs/algorithm.md, "Magnetic flights".  Kernels take raw
floats (normals outward, out of the table, as the collision frame's ``n``);
the slow twin is :mod:`noslipsim.reference.magnetic`.
"""
import math

from .exact import fma
from .jit import jit

INF = math.inf
EPS = 2.220446049250313e-16
#: Below this ``|W t|`` the path uses its series (``sin(theta)/W = t (1 - theta^2/6)``): exact to
#: the last bit there, and no division by a ``W`` that may be subnormal.
SERIES_ANGLE = 1e-8
#: ``atan(v) = v (pi/4 + ATAN_SLOPE (1 - v))`` within ``ATAN_ERROR`` on ``[0, 1]`` (its error is at most 0.0038; the
#: rest covers rounding): bounds on an exit's half-angle without its ``atan2`` (:func:`exit_after`).
ATAN_SLOPE = 0.273
ATAN_ERROR = 0.005
#: A discriminant within ``GRAZE_ULPS`` roundings of its coefficients (first-order error bound)
#: is a tangency: the orbit touches the element's line or circle to rounding and does not cross it.
GRAZE_ULPS = 16.0


# ---------------------------------------------------------------------------- the path
@jit(inline="always")
def turn(W, t):
    """``(S, Q, cos(W t), sin(W t))`` with ``S = sin(W t)/W`` and ``Q = (1 - cos(W t))/W`` (``W = 0``: ``t, 0``).

    From the half angle's sine ``h`` and cosine ``k`` alone: ``sin = 2 h k``, ``cos = (k - h)(k + h)``,
    ``1 - cos = 2 h^2`` (two calls, not three: 2 to 7 % of a magnetic collision; benchmarks/RESULTS.md).
    """
    th = W * t
    if abs(th) < SERIES_ANGLE:
        return t * (1.0 - th * th / 6.0), 0.5 * t * th, 1.0 - 0.5 * th * th, th
    h = math.sin(0.5 * th)
    k = math.cos(0.5 * th)
    sn = 2.0 * h * k
    return sn / W, 2.0 * h * h / W, (k - h) * (k + h), sn


@jit(inline="always")
def advance(x, y, vx, vy, W, t):
    """``(x, y, vx, vy)`` after a flight of duration ``t`` from ``(x, y)`` with velocity ``(vx, vy)``."""
    S, Q, cs, sn = turn(W, t)
    jx, jy = -vy, vx
    return x + S * vx + Q * jx, y + S * vy + Q * jy, cs * vx + sn * jx, cs * vy + sn * jy


@jit
def advance_many(x, y, vx, vy, W, t, out):
    """:func:`advance` over arrays (``out`` (N, 4): ``x, y, vx, vy``)."""
    for i in range(x.size):
        out[i, 0], out[i, 1], out[i, 2], out[i, 3] = advance(x[i], y[i], vx[i], vy[i], W, t[i])


@jit(inline="always")
def period(W):
    """``2 pi / |W|``: the cyclotron period (``inf`` without a field)."""
    if W == 0.0:
        return INF
    return 2.0 * math.pi / abs(W)


@jit(inline="always")
def centre(x, y, vx, vy, W):
    """``(mx, my, rho)``: the cyclotron circle's centre ``x + J v / W`` and radius ``|v| / |W|`` (``W != 0``)."""
    return x - vy / W, y + vx / W, math.hypot(vx, vy) / abs(W)


# ---------------------------------------------------------------------------- the quadratic in zeta
@jit(inline="always")
def line_coefficients(x, y, vx, vy, W, px, py, nx, ny, deflate):
    """``(c0, c1, c2, m0, m1, m2)``: the quadratic in ``zeta`` of the line through ``p`` (outward normal ``n``).

    ``m0, m1, m2``: the size of the terms of each coefficient (its rounding is a few ``EPS m``).
    """
    c0 = 0.0 if deflate else -(nx * (x - px) + ny * (y - py))
    m0 = abs(nx) * (abs(x) + abs(px)) + abs(ny) * (abs(y) + abs(py))
    return functional_coefficients(c0, m0, -nx, -ny, vx, vy, W)


@jit(inline="always")
def functional_coefficients(c0, m0, nx, ny, vx, vy, W):
    """``(c0, c1, c2, m0, m1, m2)``: the quadratic in ``zeta`` of ``c0 + n . (q(t) - q(0))`` from velocity ``v``.

    ``n`` points to the side where the function is positive (a line's table side, a lattice face's
    inside; it need not be unit); ``m0``: the size of the terms ``c0`` was formed from.  A line's
    signed distance (:func:`line_coefficients`), a lattice face and the stop level are such functions.
    """
    a = nx * vx + ny * vy
    b = ny * vx - nx * vy  # n . J v
    m1 = abs(nx * vx) + abs(ny * vy)
    c2 = W * (0.5 * b + 0.25 * W * c0)
    m2 = abs(W) * (0.5 * (abs(ny * vx) + abs(nx * vy)) + 0.25 * abs(W) * m0)
    return c0, a, c2, m0, m1, m2


@jit(inline="always")
def circle_coefficients(x, y, vx, vy, W, cx, cy, r, sigma, deflate):
    """``(c0, c1, c2, m0, m1, m2)``: the quadratic in ``zeta`` of the circle (table outside it for ``sigma = +1``)."""
    return circle_coefficients_at(x, y, vx, vy, W, cx, cy, r, sigma, deflate, math.hypot(x - cx, y - cy),
                                  math.hypot(vx, vy))


@jit(inline="always")
def circle_coefficients_at(x, y, vx, vy, W, cx, cy, r, sigma, deflate, rho, c):
    """:func:`circle_coefficients` given the distance ``rho = |x - (cx, cy)|`` and the speed ``c = |v|`` (each a
    ``math.hypot``), for a caller that has formed them already."""
    dx, dy = x - cx, y - cy
    f0 = 0.0 if deflate else (rho - r) * (rho + r)
    m0 = (rho + r) * (abs(x) + abs(cx) + abs(y) + abs(cy))
    c1 = 2.0 * (dx * vx + dy * vy)
    m1 = 2.0 * c * (abs(x) + abs(cx) + abs(y) + abs(cy))
    cross = dy * vx - dx * vy  # d . J v
    c2 = c * c + W * cross + 0.25 * W * W * f0
    m2 = c * c + abs(W) * (rho * c + 0.25 * abs(W) * m0)
    return sigma * f0, sigma * c1, sigma * c2, m0, m1, m2


@jit(inline="always")
def discriminant(c0, c1, c2, m0, m1, m2):
    """``(D, bound)``: ``c1^2 - 4 c0 c2`` (one rounding) and the bound on its error from the coefficients'."""
    D = fma(c1, c1, -4.0 * c0 * c2)
    bound = GRAZE_ULPS * EPS * (2.0 * abs(c1) * m1 + 4.0 * (abs(c2) * m0 + abs(c0) * m2) + c1 * c1
                                + 4.0 * abs(c0 * c2))
    return D, bound


@jit(inline="always")
def zeta_time(num, den, W):
    """The time in ``(0, 2 pi/|W|)`` of ``zeta = num / den`` (``den >= 0``; ``inf`` for ``t = 0`` or none)."""
    if W == 0.0:
        if den == 0.0:
            return INF
        t = num / den
        return t if t > 0.0 else INF
    aw = abs(W)
    z = aw * num
    if abs(z) <= SERIES_ANGLE * 2.0 * den:  # atan(z) = z to the last bit: no loss for a tiny W
        t = num / den
    else:
        t = 2.0 * math.atan2(z, 2.0 * den) / aw
    if t < 0.0:
        t += 2.0 * math.pi / aw
    return t if t > 0.0 else INF


@jit(inline="always")
def angle_bounds(X, Y):
    """``(lo, hi)``: bounds on ``atan2(Y, X)`` in ``[0, pi/2]`` (``X, Y >= 0``), a quadratic in the smaller ratio."""
    if Y <= X:
        v = Y / X if X > 0.0 else 0.0  # X = Y = 0 (an underflowed root): the bounds stay finite
        a = v * (0.25 * math.pi + ATAN_SLOPE * (1.0 - v))
    else:  # atan(Y / X) = pi/2 - atan(X / Y)
        v = X / Y
        a = 0.5 * math.pi - v * (0.25 * math.pi + ATAN_SLOPE * (1.0 - v))
    return a - ATAN_ERROR, a + ATAN_ERROR


@jit(inline="always")
def exit_after(num, den, W, lo, hi):
    """True if the root ``zeta = num / den`` (``den >= 0``, ``W != 0``) certainly has ``lo + t > hi`` for its time
    ``t = zeta_time(num, den, W)`` (or none), from a lower bound on ``t`` without an ``atan2``.

    ``t = 2 psi / |W|`` with the half-angle ``psi`` in ``(0, pi)``: ``atan2(z, 2 den)`` for ``z = |W| num > 0``,
    ``pi - atan2(-z, 2 den)`` for ``z <= 0`` (past half a period; ``z = 0`` is ``t = 0``, no root).  The bound
    lies at least 0.001 below ``psi``, far more than the computed ``t`` can round below ``2 psi / |W|``, so
    rounding only ever keeps a root (``lo + t`` rounds monotonically): false for a root that may be in time.
    """
    aw = abs(W)
    z = aw * num
    if z > 0.0:
        psi = angle_bounds(2.0 * den, z)[0]
    else:
        psi = math.pi - angle_bounds(2.0 * den, -z)[1]
    return lo + 2.0 * psi / aw > hi


@jit(inline="always")
def exit_root(c0, c1, c2, m0, m1, m2, deflate):
    """``(found, num, den)``: the exit root ``zeta = num / den`` (``den >= 0``) of the quadratic in ``zeta``;
    ``found`` false for none or a certified graze."""
    if deflate:
        if not c1 > 0.0:  # on the element and not moving into the table: its exit is t = 0 itself
            return False, 0.0, 0.0
        num, den = -c1, c2
    else:
        D, bound = discriminant(c0, c1, c2, m0, m1, m2)
        if D <= bound:  # no crossing, or a tangency to rounding (certified grazing)
            return False, 0.0, 0.0
        sq = math.sqrt(D)
        if c1 >= 0.0:
            num, den = -0.5 * (c1 + sq), c2
        else:
            num, den = c0, 0.5 * (sq - c1)
    if den < 0.0:
        num, den = -num, -den
    return True, num, den


@jit(inline="always")
def exit_time(c0, c1, c2, m0, m1, m2, W, deflate):
    """The exit root's time in ``(0, 2 pi/|W|)`` of the quadratic in ``zeta`` (``inf``: none, or a certified graze)."""
    found, num, den = exit_root(c0, c1, c2, m0, m1, m2, deflate)
    if not found:
        return INF
    return zeta_time(num, den, W)


@jit(inline="always")
def root_position(x, y, vx, vy, W, num, den):
    """The position at the root ``zeta = num / den`` without a trigonometric function.

    With ``u = tan(theta/2) = W zeta / 2``: ``S = sin(theta)/W = zeta / (1 + u^2)`` and
    ``Q = (1 - cos(theta))/W = W zeta^2 / (2 (1 + u^2))``, i.e. ``S = 4 num den / k`` and
    ``Q = 2 W num^2 / k`` with ``k = 4 den^2 + W^2 num^2``: rational, finite at half a period
    (``den = 0``) and at ``W = 0``.  For extent tests (the event loop forms the hit itself with
    :func:`advance` at the root's time).
    """
    wn = W * num
    k = 4.0 * den * den + wn * wn
    S = 4.0 * num * den / k
    Q = 2.0 * wn * num / k
    return x + S * vx - Q * vy, y + S * vy + Q * vx


@jit(inline="always")
def can_meet(c0, c1, c2, m0, m1, m2):
    """The whole orbit (cyclotron circle; a straight flight's whole line) touches or crosses: ``D >= -bound``."""
    D, bound = discriminant(c0, c1, c2, m0, m1, m2)
    return D >= -bound


# ---------------------------------------------------------------------------- exits through elements
@jit
def line_exit(x, y, vx, vy, W, px, py, nx, ny, deflate):
    """Earliest time in ``(0, 2 pi/|W|)`` the flight leaves the table through the line ``n . (q - p) = 0``, or inf.

    ``n`` is the outward unit normal; ``deflate``: the flight starts on the line (its ``t = 0`` root removed).
    """
    c0, c1, c2, m0, m1, m2 = line_coefficients(x, y, vx, vy, W, px, py, nx, ny, deflate)
    return exit_time(c0, c1, c2, m0, m1, m2, W, deflate)


@jit
def circle_exit(x, y, vx, vy, W, cx, cy, r, sigma, deflate):
    """Earliest time in ``(0, 2 pi/|W|)`` the flight leaves the table through the circle, or inf.

    ``sigma = +1``: the table lies outside the circle (a scatterer), ``-1`` inside (a container).
    """
    c0, c1, c2, m0, m1, m2 = circle_coefficients(x, y, vx, vy, W, cx, cy, r, sigma, deflate)
    return exit_time(c0, c1, c2, m0, m1, m2, W, deflate)

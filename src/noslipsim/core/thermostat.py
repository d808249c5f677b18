r"""Thermostatted flights: the closed-form path of the Gaussian isokinetic thermostat.

Between collisions a particle under a constant field ``F`` (force per unit
mass, strength ``E = |F|``) with the Gaussian isokinetic thermostat moves as

.. math::

    \dot q = v, \qquad \dot v = F - \alpha v, \qquad \alpha = \frac{F \cdot v}{|v|^2},

so its speed ``c = |v|`` and its spin are constant in flight and only the
heading ``phi`` (counter-clockwise from ``F``) turns, towards the field:
``phi' = -k sin(phi)`` with ``k = E / c``, and ``lambda = ln|tan(phi / 2)|``
falls linearly, ``lambda(t) = lambda_0 - k t``.  In the field frame (``x'``
along ``F``, ``y'`` along ``J F``), with ``R = c^2 / E``,
``C^2 = cos^2(phi_0/2)``, ``S^2 = sin^2(phi_0/2)`` and ``e = exp(-k t)``:

.. math::

    \Delta x' = c t + R \ln(C^2 + S^2 e^2), \qquad
    \Delta y' = R (\phi_0 - \phi) = 2 R \arctan\frac{S C (1 - e)}{C^2 + S^2 e},

    \cos\phi = -\tanh\lambda, \qquad \sin\phi = \operatorname{sgn}(\sin\phi_0) / \cosh\lambda .

A flight is packed once, at its start (:func:`flight`), and evaluated from
there at each trial time of the event search (:mod:`thermo_events`), never by
steps, in forms where nothing cancels or overflows (docs/algorithm.md,
"Thermostatted flights").
"""
import math

from .exact import fma
from .jit import jit

INF = math.inf


@jit(inline="always")
def field(ax, ay):
    """``(E, fx, fy)``: the field's strength and unit direction (``E > 0``)."""
    E = math.hypot(ax, ay)
    return E, ax / E, ay / E


@jit(inline="always")
def _softplus(z):
    """``ln(1 + e^z)`` without overflow or loss for either sign of ``z``."""
    if z > 0.0:
        return z + math.log1p(math.exp(-z))
    return math.log1p(math.exp(z))


@jit(inline="always")
def cross(ax, ay, vx, vy):
    """``ax vy - ay vx`` to a few ulps of itself (Kahan's determinant; exactly 0 for parallel vectors)."""
    w = ay * vx
    return fma(ax, vy, -w) + fma(-ay, vx, w)


@jit(inline="always")
def flight(x, y, vx, vy, ax, ay):
    """The flight from ``(x, y)`` with velocity ``(vx, vy)`` (speed > 0) in the field ``(ax, ay)`` (``!= 0``), packed.

    Returns ``(x, y, vx, vy, c, k, R, C2, S2, SC, lam0, sgn, fx, fy)``: the start, the speed ``c``, ``k = E / c``,
    ``R = c^2 / E``, ``C2 = cos^2(phi_0/2)``, ``S2 = sin^2(phi_0/2)``, ``SC = sin(phi_0/2) cos(phi_0/2)`` (each
    without cancellation), ``lam0 = ln|tan(phi_0/2)|`` (``-inf`` along the field, ``+inf`` against it), the sign
    of ``sin phi_0`` and the field's unit direction.  ``c sin(phi_0) = (F x v) / E`` is formed to a few ulps of
    itself (:func:`cross`): a flight nearly against the field (whose small angle grows like ``exp(k t)``) keeps
    its angle's digits, and an exactly (anti)parallel one is straight.
    """
    E, fx, fy = field(ax, ay)
    c = math.hypot(vx, vy)
    vp = vx * fx + vy * fy          # c cos(phi_0)
    vq = cross(ax, ay, vx, vy) / E  # c sin(phi_0)
    if vp >= 0.0:
        C2 = (c + vp) / (2.0 * c)
        S2 = vq * vq / (2.0 * c * (c + vp))
    else:
        S2 = (c - vp) / (2.0 * c)
        C2 = vq * vq / (2.0 * c * (c - vp))
    SC = vq / (2.0 * c)
    if S2 == 0.0:
        lam0 = -INF
    elif C2 == 0.0:
        lam0 = INF
    else:
        lam0 = 0.5 * (math.log(S2) - math.log(C2))
    sgn = 1.0 if vq > 0.0 else (-1.0 if vq < 0.0 else 0.0)
    k = E / c
    return x, y, vx, vy, c, k, c / k, C2, S2, SC, lam0, sgn, fx, fy


@jit(inline="always")
def heading(lam, sgn):
    """``(cos phi, sin phi)`` of the heading with ``ln|tan(phi/2)| = lam`` and ``sgn = sign(sin phi)``."""
    a = abs(lam)
    w = math.exp(-a)                 # |tan(phi/2)| or its inverse, <= 1
    inv = 1.0 / (1.0 + w * w)
    cphi = -math.expm1(-2.0 * a) * inv
    if lam > 0.0:
        cphi = -cphi
    return cphi, sgn * 2.0 * w * inv


#: Below this ``k t`` a move is split into the straight step ``v0 t`` and the bend, ``O(E t^2)``, each to
#: a few ulps of itself (series below): a short hop off a wall keeps its relative precision.
SHORT = 0.0625


@jit(inline="always")
def _expm1_tail(x):
    """``x + expm1(-x) = x^2/2 - x^3/6 + ...`` for ``0 <= x <= 1/8``, to a few ulps of itself."""
    acc = 0.0
    for n in range(20, 2, -1):
        acc = (-x / n) * (1.0 + acc)
    return 0.5 * x * x * (1.0 + acc)


@jit(inline="always")
def _log1p_tail(m):
    """``log1p(-m) + m = -(m^2/2 + m^3/3 + ...)`` for ``0 <= m <= 1/8``, to a few ulps of itself."""
    acc = 0.0
    for n in range(26, 1, -1):
        acc = 1.0 / n + m * acc
    return -m * m * acc


@jit(inline="always")
def _atan_tail(z):
    """``atan(z) - z = -z^3/3 + z^5/5 - ...`` for ``|z| <= 1/16``, to a few ulps of itself."""
    z2 = z * z
    acc = 0.0
    for n in range(10, 0, -1):
        acc = (-1.0) ** n / (2 * n + 1) + z2 * acc
    return z * z2 * acc


@jit
def displacement(fl, t):
    """``(tl, dX, dY, cos phi, sin phi, lam)`` after time ``t >= 0``: the move and the heading.

    The move is ``v0 tl + dX F + dY (J F)`` (``F`` the field's unit direction): for ``k t <= SHORT`` the
    straight step ``v0 t`` and its bend (``tl = t``), each to a few ulps of itself, so a short flight's distance
    from a wall it grazes or just left has the precision of that distance, not of the step; otherwise the closed
    form in the field frame (``tl = 0``).  A flight along or exactly against the field is straight.
    """
    _x, _y, _vx, _vy, c, k, R, C2, S2, SC, lam0, sgn, _fx, _fy = fl
    if sgn == 0.0:  # straight along (or exactly against) the field
        cphi = 1.0 if S2 == 0.0 else -1.0
        return t, 0.0, 0.0, cphi, 0.0, lam0
    kt = k * t
    e = math.exp(-kt)
    em = -math.expm1(-kt)            # 1 - e, exact to rounding for small k t
    m = S2 * em * (1.0 + e)          # S^2 (1 - e^2)
    lam = lam0 - kt
    cphi, sphi = heading(lam, sgn)
    if kt <= SHORT:
        # dX - c t cos(phi0) = R S^2 g(2kt) + R (log1p(-m) + m), g(x) = x + expm1(-x);
        # dY - c t sin(phi0) = 2R (atan z - z) + 2R SC (kt S^2 (1 - e) - g(kt)) / (1 - S^2 (1 - e))
        D1 = 1.0 - S2 * em
        z = SC * em / D1
        dX = R * (S2 * _expm1_tail(2.0 * kt) + _log1p_tail(m))
        dY = 2.0 * R * (_atan_tail(z) + SC * (kt * S2 * em - _expm1_tail(kt)) / D1)
        return t, dX, dY, cphi, sphi, lam
    # L = ln((1 + u^2)/(1 + u0^2)), u = tan(phi/2) = exp(lam) (up to sign)
    if m <= 0.5:
        L = math.log1p(-m)
    elif lam > 0.0:  # still against the field: the large terms 2 lam and 2 lam0 cancel exactly
        L = -2.0 * kt + (math.log1p(math.exp(-2.0 * lam)) - math.log1p(math.exp(-2.0 * lam0)))
    else:  # no underflow of u, nothing left to cancel
        L = math.log1p(math.exp(2.0 * lam)) - _softplus(2.0 * lam0)
    dX = c * t + R * L
    dY = 2.0 * R * math.atan2(SC * em, C2 + S2 * e)
    return 0.0, dX, dY, cphi, sphi, lam


@jit
def state(fl, t):
    """``(x, y, vx, vy)`` of the flight after time ``t >= 0`` (``t = 0``: the start, exactly)."""
    x, y, vx, vy, c, _k, _R, _C2, _S2, _SC, _lam0, sgn, fx, fy = fl
    if t == 0.0:
        return x, y, vx, vy
    if sgn == 0.0:  # along or exactly against the field: a straight line at constant velocity
        return x + t * vx, y + t * vy, vx, vy
    tl, dX, dY, cphi, sphi, _lam = displacement(fl, t)
    return ((x + tl * vx) + (dX * fx - dY * fy), (y + tl * vy) + (dX * fy + dY * fx),
            c * (cphi * fx - sphi * fy), c * (cphi * fy + sphi * fx))


@jit(inline="always")
def advance(x, y, vx, vy, ax, ay, t):
    """State ``(x, y, vx, vy)`` after a thermostatted flight of time ``t >= 0`` from ``(x, y, vx, vy)``."""
    return state(flight(x, y, vx, vy, ax, ay), t)


@jit(inline="always")
def drag(vx, vy, ax, ay):
    """``F - alpha v``, the acceleration of the thermostatted flight at velocity ``v`` (``alpha = F.v/|v|^2``)."""
    alpha = (ax * vx + ay * vy) / (vx * vx + vy * vy)
    return ax - alpha * vx, ay - alpha * vy


@jit
def advance_many(x, y, vx, vy, ax, ay, tau, out):
    """:func:`advance` for arrays of starts and durations (one flight per entry); ``out[i] = (x, y, vx, vy)``.

    For plots and checks above the kernels (drawing a thermostatted orbit, sampling its flights).
    """
    for i in range(x.shape[0]):
        out[i, 0], out[i, 1], out[i, 2], out[i, 3] = advance(x[i], y[i], vx[i], vy[i], ax, ay, tau[i])

"""Exit roots of the crossing polynomial along a flight.

A flight crosses an element where its crossing polynomial
``p(t) = c0 + c1 t + c2 t^2 + c3 t^3 + c4 t^4`` (positive on the table side)
changes sign from + to -; only those *exit* roots in ``(0, hi]`` matter.
Degrees 1 and 2 use closed forms (the cancellation-free quadratic formula).  Cubics and quartics are
isolated exactly: the real roots of the derivative split ``[0, hi]`` into monotone pieces, each holding
at most one root, which safeguarded Newton (bisection fallback) polishes to full precision.  No
coefficient is compared against an epsilon: the caller fixes the degree from what the scene needs, and
only an exactly zero leading coefficient lowers it.  docs/algorithm.md, *1. Next hit*.
"""
import math

from .jit import jit
from .tolerances import ROOT_MAX_ITER

INF = math.inf
EPS = 2.220446049250313e-16


@jit
def horner(c0, c1, c2, c3, c4, t):
    """``c0 + c1 t + c2 t^2 + c3 t^3 + c4 t^4`` by Horner's rule."""
    return (((c4 * t + c3) * t + c2) * t + c1) * t + c0


@jit
def horner_prime(c1, c2, c3, c4, t):
    """The derivative ``c1 + 2 c2 t + 3 c3 t^2 + 4 c4 t^3`` by Horner's rule."""
    return ((4.0 * c4 * t + 3.0 * c3) * t + 2.0 * c2) * t + c1


@jit
def cauchy_bound(c0, c1, c2, c3, c4, deg):
    """Upper bound on the modulus of every root of a polynomial of degree ``deg``."""
    if deg == 4:
        lead = abs(c4)
        m = max(abs(c0), abs(c1), abs(c2), abs(c3))
    elif deg == 3:
        lead = abs(c3)
        m = max(abs(c0), abs(c1), abs(c2))
    elif deg == 2:
        lead = abs(c2)
        m = max(abs(c0), abs(c1))
    else:
        lead = abs(c1)
        m = abs(c0)
    return 1.0 + m / lead


@jit(inline="always")  # inlined: it starts every polish, and the operations must stay those of each caller
def secant_start(a, b, fa, fb):
    """The first iterate of :func:`bracket_step` in ``[a, b]`` from ``fa = f(a)``, ``fb = f(b)`` of opposite signs.

    The regula falsi point (exact for a straight piece), or the midpoint
    where rounding puts that point outside the open bracket.
    """
    t = a + (b - a) * (fa / (fa - fb))
    if not (a < t < b):
        t = 0.5 * (a + b)
    return t


@jit(inline="always")  # inlined: one call per Newton step of every root polished
def bracket_step(a, b, t, f, d, sa):
    """One safeguarded Newton step on the bracket ``[a, b]``: ``(a, b, t_next, done)``.

    ``f``, ``d``: the function and its derivative at ``t``; ``sa``: the sign
    (``f > 0``) at ``a``.  ``t`` replaces the bracket's end of its sign; the
    Newton iterate from ``t``, or the bisection point when it falls outside
    the bracket (or ``d = 0``), is ``t_next``.  ``done``: ``f(t) = 0``
    (``t_next = t``), or the step or the bracket is down to rounding.
    """
    if f == 0.0:
        return a, b, t, True
    if (f > 0.0) == sa:
        a = t
    else:
        b = t
    tn = t - f / d if d != 0.0 else 0.5 * (a + b)
    if not (a <= tn <= b):
        tn = 0.5 * (a + b)
    done = abs(tn - t) <= 2.0 * EPS * abs(tn) or b - a <= 2.0 * EPS * max(abs(a), abs(b))
    return a, b, tn, done


@jit
def polish(c0, c1, c2, c3, c4, a, b, fa):
    """Root of ``p`` in ``[a, b]`` where ``p`` is monotone and ``p(a)`` (= ``fa``), ``p(b)`` differ in sign."""
    sa = fa > 0.0
    t = secant_start(a, b, fa, horner(c0, c1, c2, c3, c4, b))
    for _ in range(ROOT_MAX_ITER):
        f = horner(c0, c1, c2, c3, c4, t)
        a, b, t, done = bracket_step(a, b, t, f, horner_prime(c1, c2, c3, c4, t), sa)
        if done:
            break
    return t


@jit
def quadratic_roots(c0, c1, c2):
    """Real roots of ``c0 + c1 t + c2 t^2`` as ``(n, r1, r2)``, sorted (a double root counts once)."""
    if c2 == 0.0:
        if c1 == 0.0:
            return 0, INF, INF
        return 1, -c0 / c1, INF
    disc = c1 * c1 - 4.0 * c2 * c0
    if disc < 0.0:
        return 0, INF, INF
    if disc == 0.0:
        return 1, -c1 / (2.0 * c2), INF
    sq = math.sqrt(disc)
    q = -0.5 * (c1 + sq) if c1 >= 0.0 else -0.5 * (c1 - sq)
    r1 = q / c2
    r2 = c0 / q if q != 0.0 else -r1
    if r1 > r2:
        r1, r2 = r2, r1
    return 2, r1, r2


@jit
def linear_exit(c0, c1, hi):
    """Exit root of ``c0 + c1 t`` in ``(0, hi]`` or inf."""
    if c1 < 0.0 and c0 > 0.0:
        t = -c0 / c1
        if t <= hi:
            return t
    return INF


@jit
def quadratic_exit(c0, c1, c2, hi):
    """Exit root of ``c0 + c1 t + c2 t^2`` in ``(0, hi]`` or inf (a quadratic has at most one)."""
    if c2 == 0.0:
        return linear_exit(c0, c1, hi)
    if c0 > 0.0 and c1 >= 0.0 and c2 > 0.0:  # both roots negative or complex: no square root needed
        return INF
    n, r1, r2 = quadratic_roots(c0, c1, c2)
    if n < 2:  # no root or a tangency: the flight never leaves
        return INF
    t = r1 if c2 > 0.0 else r2
    if 0.0 < t <= hi:
        return t
    return INF


@jit(inline="always")  # inlined: the lean straight flights test every circle copy in a cell with it
def straight_circle_exit(dx, dy, vx, vy, sig, r, deflate, hi):
    """Exit root in ``(0, hi]`` of a straight flight ``d + v t`` from the circle of radius ``r``, or inf.

    ``d = (dx, dy)``: the start relative to the centre; ``sig``: +1 outside
    the circle is the table side, -1 inside.  The crossing quadratic
    ``sig (|d + v t|^2 - r^2)``; ``deflate``: the circle was just hit at
    ``t = 0`` (its constant term is that root, divided out).
    """
    c1 = sig * 2.0 * (dx * vx + dy * vy)
    c2 = sig * (vx * vx + vy * vy)
    if deflate:
        return linear_exit(c1, c2, hi)
    return quadratic_exit(sig * ((dx * dx + dy * dy) - r * r), c1, c2, hi)


@jit(inline="always")
def _piece_end(i, k1, k2, k3, hi):
    """The right end of piece ``i`` of ``[0, hi]``: the break points ``k1, k2, k3``, then ``hi``."""
    if i == 0:
        return k1
    if i == 1:
        return k2
    if i == 2:
        return k3
    return hi


@jit(inline="always")
def _piece_exit(c0, c1, c2, c3, c4, a, fa, b, fb, before):
    """The exit root on the monotone piece ``[a, b]`` from ``p(a) = fa``, ``p(b) = fb``, or inf.

    ``before``: the last nonzero value at or before ``a``; ``+, 0, -`` is an
    exit at ``a`` (an osculating crossing).
    """
    if fa > 0.0 and fb < 0.0:
        return polish(c0, c1, c2, c3, c4, a, b, fa)
    if fa == 0.0 and a > 0.0 and before > 0.0 and fb < 0.0:
        return a
    return INF


@jit(inline="always")
def _add_exit(e1, e2, r):
    """``(e1, e2)`` with the exit ``r`` (inf: none) in the first free place."""
    if r != INF:
        if e1 == INF:
            e1 = r
        else:
            e2 = r
    return e1, e2


@jit(inline="always")
def _add_exit_at_end(c1, c2, c3, c4, a, fa, before, hi, e1, e2):
    """``(e1, e2)`` with an exit exactly at ``hi`` if ``p`` reaches 0 there from above, decreasing."""
    if fa == 0.0 and a == hi and a > 0.0 and before > 0.0 and horner_prime(c1, c2, c3, c4, a) <= 0.0:
        if e1 == INF:
            e1 = a
        elif e2 == INF and e1 != a:
            e2 = a
    return e1, e2


@jit
def _exits_on_pieces(c0, c1, c2, c3, c4, k1, k2, k3, hi):
    """Up to two exit roots of ``p`` in ``(0, hi]`` given its sorted critical points ``k1..k3`` (inf padded).

    ``p`` is monotone between break points; a piece with ``p(a) > 0 > p(b)`` holds one exit.  Where
    ``p`` rounds to exactly zero at a break point, the last nonzero value before it decides: ``+, 0, -``
    is an exit there (an osculating, triple-root crossing), ``+, 0, +`` a tangency.  An exit exactly at
    ``hi`` counts when ``p`` decreases there.
    """
    e1 = INF
    e2 = INF
    a = 0.0
    fa = c0
    before = c0  # last nonzero value at or before a
    for i in range(4):
        b = _piece_end(i, k1, k2, k3, hi)
        if b <= a:
            continue
        if b > hi:
            b = hi
        fb = horner(c0, c1, c2, c3, c4, b)
        e1, e2 = _add_exit(e1, e2, _piece_exit(c0, c1, c2, c3, c4, a, fa, b, fb, before))
        if fa != 0.0:
            before = fa
        a = b
        fa = fb
        if a >= hi:
            break
    return _add_exit_at_end(c1, c2, c3, c4, a, fa, before, hi, e1, e2)


@jit
def cubic_roots_in(c0, c1, c2, c3, lo, hi):
    """Real roots of a cubic in ``[lo, hi]`` (finite), sorted and inf padded: ``(r1, r2, r3)``."""
    if c3 == 0.0:
        n, q1, q2 = quadratic_roots(c0, c1, c2)
        r1 = q1 if (n >= 1 and lo <= q1 <= hi) else INF
        r2 = q2 if (n >= 2 and lo <= q2 <= hi) else INF
        if r1 == INF:
            r1, r2 = r2, INF
        return r1, r2, INF
    _, k1, k2 = quadratic_roots(c1, 2.0 * c2, 3.0 * c3)
    out1 = INF
    out2 = INF
    out3 = INF
    a = lo
    fa = horner(c0, c1, c2, c3, 0.0, a)
    for i in range(3):
        if i == 0:
            b = k1
        elif i == 1:
            b = k2
        else:
            b = hi
        if b <= a:
            continue
        if b > hi:
            b = hi
        fb = horner(c0, c1, c2, c3, 0.0, b)
        r = INF
        if fa == 0.0:
            r = a
        elif (fa > 0.0) != (fb > 0.0) and fb != 0.0:
            r = polish(c0, c1, c2, c3, 0.0, a, b, fa)
        elif fb == 0.0:
            r = b
        if r != INF and r != out1 and r != out2:
            if out1 == INF:
                out1 = r
            elif out2 == INF:
                out2 = r
            else:
                out3 = r
        a = b
        fa = fb
        if a >= hi:
            break
    return out1, out2, out3


@jit
def surely_positive(c0, c1, c2, c3, c4, hi):
    """True if ``p`` (degree <= 4) is certainly positive on ``[0, hi]`` (finite ``hi``).

    ``p`` is a convex combination of its Bernstein coefficients on ``[0, hi]``
    (``b_k = sum_j C(k, j)/C(4, j) c_j hi^j``), so ``min b_k > 0`` excludes a root.  The margin,
    ``32 eps sum_j |c_j| hi^j``, exceeds the rounding of the ``b_k`` and of Horner's rule: the test
    only saves work, it never changes a result.
    """
    d1 = c1 * hi
    d2 = c2 * hi * hi
    d3 = c3 * hi * hi * hi
    d4 = c4 * hi * hi * hi * hi
    margin = 32.0 * EPS * (abs(c0) + abs(d1) + abs(d2) + abs(d3) + abs(d4))
    if c0 <= margin:
        return False
    if c0 + 0.25 * d1 <= margin:
        return False
    if c0 + 0.5 * d1 + d2 / 6.0 <= margin:
        return False
    if c0 + 0.75 * d1 + 0.5 * d2 + 0.25 * d3 <= margin:
        return False
    return c0 + d1 + d2 + d3 + d4 > margin


@jit
def cubic_exits(c0, c1, c2, c3, hi):
    """Exit roots ``(e1, e2)`` of a cubic in ``(0, hi]`` (inf padded)."""
    if c3 == 0.0:
        return quadratic_exit(c0, c1, c2, hi), INF
    if hi < INF and surely_positive(c0, c1, c2, c3, 0.0, hi):
        return INF, INF
    if hi == INF:
        hi = cauchy_bound(c0, c1, c2, c3, 0.0, 3)
    n, k1, k2 = quadratic_roots(c1, 2.0 * c2, 3.0 * c3)
    if n < 2:
        k1 = INF
        k2 = INF
    return _exits_on_pieces(c0, c1, c2, c3, 0.0, k1, k2, INF, hi)


@jit
def surely_convex(c2, c3, c4, hi):
    """True if ``p'' = 2 c2 + 6 c3 t + 12 c4 t^2`` is certainly positive on ``[0, hi]`` (finite ``hi``, ``c4 >= 0``)."""
    margin = 16.0 * EPS * (abs(2.0 * c2) + abs(6.0 * c3 * hi) + 12.0 * c4 * hi * hi)
    if 2.0 * c2 <= margin or 2.0 * c2 + hi * (6.0 * c3 + 12.0 * c4 * hi) <= margin:
        return False
    if c4 > 0.0:
        tv = -c3 / (4.0 * c4)
        if 0.0 < tv < hi and 2.0 * c2 - 0.75 * c3 * c3 / c4 <= margin:
            return False
    return True


#: Newton steps ``convex_first_exit`` takes before it hands over to the full
#: isolation: a simple root converges quadratically in far fewer, a
#: (near-)double root only linearly.
CONVEX_NEWTON_STEPS = 16


@jit
def convex_first_exit(c0, c1, c2, c3, c4, hi):
    """Exit root in ``(0, hi]`` of ``p`` convex on ``[0, hi]`` with ``p(0) = c0 > 0``; inf if none.

    A convex ``p`` has at most one exit; Newton's iterates from ``t = 0`` increase monotonically and
    never pass it, so an iterate beyond ``hi``, or one where ``p`` stops decreasing, proves there is
    none.  Returns ``-1`` when the iterates converge only linearly (a tangency to rounding): the caller
    decides by the full isolation, as for every tangency.
    """
    t = 0.0
    f = c0
    for _ in range(CONVEX_NEWTON_STEPS):
        d = horner_prime(c1, c2, c3, c4, t)
        if d >= 0.0:  # the minimum is behind: p > 0 from here on
            return INF
        tn = t - f / d
        if tn > hi:
            return INF
        f = horner(c0, c1, c2, c3, c4, tn)
        if f <= 0.0 or tn - t <= 2.0 * EPS * tn:
            return tn
        t = tn
    return -1.0


@jit
def quartic_exits(c0, c1, c2, c3, c4, hi):
    """Exit roots ``(e1, e2)`` of a quartic in ``(0, hi]`` (inf padded)."""
    if c4 == 0.0:
        return cubic_exits(c0, c1, c2, c3, hi)
    if hi < INF and surely_positive(c0, c1, c2, c3, c4, hi):
        return INF, INF
    if hi < INF and c0 > 0.0 and c4 > 0.0 and surely_convex(c2, c3, c4, hi):
        t = convex_first_exit(c0, c1, c2, c3, c4, hi)
        if t >= 0.0:
            return t, INF
    if hi == INF:
        hi = cauchy_bound(c0, c1, c2, c3, c4, 4)
    k1, k2, k3 = cubic_roots_in(c1, 2.0 * c2, 3.0 * c3, 4.0 * c4, 0.0, hi)
    return _exits_on_pieces(c0, c1, c2, c3, c4, k1, k2, k3, hi)

r"""Event times of thermostatted flights: certified brackets, then safeguarded Newton on the closed form.

A thermostatted path (:mod:`thermostat`) is transcendental; two facts make its crossings as certain
as the parabolic ones (docs/algorithm.md, "Thermostatted flights", *Events*):

* **Lines are unimodal.**  ``f(t) = f0 + n . (q(t) - q(0))`` has ``f' = c (n1 cos phi + n2 sin phi)``
  (``n1, n2`` the field-frame parts of ``n``), zero only where ``sinh lambda = sgn n2 / n1``: one
  critical time, in closed form, so at most one exit root, isolated between ``0``, that time and the
  window's end, then polished (:func:`line_exit`).  Lattice strips and the stop level are such functions.
* **Circles are bracketed by the curvature bound.**  On a step window ``[a, a + W]``,
  ``G(t) = sigma (|d(t)|^2 - r^2)`` lies between the quadratics
  ``G_a + G'_a tau + (sigma c^2 -+ Q) tau^2``, ``Q = (|d_a| + c W) E S``: the lower one's first root is
  a step that cannot pass a root; once the upper one's is in the window too, the bracket holds exactly
  one exit (:func:`round_hit`).  A tangency to rounding is decided by the exact ``G''``.

The brackets are proofs in exact arithmetic; the polish only narrows them.
"""
import math

from .geometry import extent_position
from .jit import jit
from .layout import ARC, LINE, SEGMENT
from .roots import bracket_step, secant_start, straight_circle_exit
from .search import GAVE_UP, SEARCH_FAILED  # noqa: F401  (re-exported: the give-up codes of the search)
from .thermostat import displacement, drag, state
from .tolerances import ROOT_MAX_ITER

INF = math.inf
EPS = 2.220446049250313e-16

#: Conservative steps one circle search may take before it gives up (not reached in the tests and benchmarks:
#: a step below the time's resolution is lengthened to a rounding step).  Giving up is not "no hit": the search
#: returns :data:`GAVE_UP`, the cell search :data:`SEARCH_FAILED`, the cell walk status 3, and the event loop
#: stops the orbit with ``layout.STOP_SEARCH_LIMIT`` ("search_limit") where it stands.
MAX_STEPS = 100_000
#: Bracket doublings for the last, unbounded piece of a line (each doubles the time window).
MAX_DOUBLINGS = 2100


# ---------------------------------------------------------------------------- lines
@jit(inline="always")
def _field_parts(fl, nx, ny):
    """``(n1, n2)``: ``n`` along the field and along ``J F``."""
    fx = fl[12]
    fy = fl[13]
    return nx * fx + ny * fy, ny * fx - nx * fy


@jit
def _line_value(fl, n1, n2, nv, t):
    """``(n . (q(t) - q(0)), n . v(t))`` for the field-frame parts ``n1, n2`` of ``n`` and ``nv = n . v(0)``."""
    tl, dX, dY, cphi, sphi, _lam = displacement(fl, t)
    return nv * tl + (n1 * dX + n2 * dY), fl[4] * (n1 * cphi + n2 * sphi)


@jit
def _line_root(fl, f0, n1, n2, nv, a, b, fa, fb):
    """Root of the monotone ``f = f0 + n . (q(t) - q(0))`` in ``[a, b]`` with ``fa > 0 >= fb``: safeguarded Newton."""
    if fb == 0.0:
        return b
    t = secant_start(a, b, fa, fb)
    for _ in range(ROOT_MAX_ITER):
        val, der = _line_value(fl, n1, n2, nv, t)
        a, b, t, done = bracket_step(a, b, t, f0 + val, der, True)
        if done:
            break
    return t


@jit
def _critical_time(fl, n1, n2):
    """The one time ``> 0`` at which ``n . v(t)`` changes sign, or inf (straight flights and ``n1 = 0``: none)."""
    sgn = fl[11]
    if n1 == 0.0 or sgn == 0.0:
        return INF
    tc = (fl[10] - math.asinh(sgn * n2 / n1)) / fl[5]
    return tc if tc > 0.0 else INF


@jit
def _decreasing_at_infinity(fl, f0, n1, n2):
    """On the last piece (after any critical time): does ``f`` fall below 0 for good?"""
    if fl[11] == 0.0:  # straight: f' = n . v0 for ever
        fx = fl[12]
        fy = fl[13]
        return n1 * (fl[2] * fx + fl[3] * fy) + n2 * (fl[3] * fx - fl[2] * fy) < 0.0
    if n1 < 0.0:
        return True
    if n1 > 0.0:
        return False
    # along J F: f tends to f0 + n2 dY(inf), dY(inf) = 2 R atan2(SC, C2)
    return f0 + n2 * 2.0 * fl[6] * math.atan2(fl[9], fl[7]) < 0.0


@jit
def _exit_from(fl, f0, n1, n2, nv, a, fa, pos, hi, tc):
    """First exit root in ``(a, hi]`` from ``f(a) = fa`` (``pos``: ``f > 0`` just after ``a``), critical time ``tc``."""
    c = fl[4]
    speed_n = c * math.hypot(n1, n2)      # |f'| <= c |n|
    for piece in range(2):
        b = tc if piece == 0 else INF
        if b <= a:
            continue
        bb = min(b, hi)
        if bb < INF:
            val, der = _line_value(fl, n1, n2, nv, bb)
            fb = f0 + val
            if pos and (fb < 0.0 or (fb == 0.0 and bb == hi)):
                if fa <= 0.0:  # deflated start: the root t = 0 is not an exit, f > 0 just after it
                    fa = 0.0
                    return _line_root_from_zero(fl, f0, n1, n2, nv, a, bb, fb, der)
                return _line_root(fl, f0, n1, n2, nv, a, bb, fa, fb)
            if bb >= hi:
                return INF
            a = bb
            fa = fb
            pos = fb > 0.0
            continue
        # the unbounded last piece: monotone; an exit only if it falls below 0 for good
        if not pos or not _decreasing_at_infinity(fl, f0, n1, n2):
            return INF
        h = fa / speed_n if fa > 0.0 else 0.0
        if fl[11] != 0.0 or not h > 0.0:  # a turning flight bends over the time 1 / k
            h = max(h, 1.0 / fl[5])
        for _ in range(MAX_DOUBLINGS):
            val, der = _line_value(fl, n1, n2, nv, a + h)
            fb = f0 + val
            if fb <= 0.0:
                if fa <= 0.0:
                    return _line_root_from_zero(fl, f0, n1, n2, nv, a, a + h, fb, der)
                return _line_root(fl, f0, n1, n2, nv, a, a + h, fa, fb)
            h *= 2.0
        return INF
    return INF


@jit
def _line_root_from_zero(fl, f0, n1, n2, nv, a, b, fb, derb):
    """The root in ``(a, b]`` of a deflated ``f`` (``f(a) = 0``, positive just after ``a``), bracketed off ``a``."""
    # f > 0 on (a, a + h) for small h: halve from b until a positive value is found
    h = b - a
    for _ in range(1100):
        h *= 0.5
        val, _der = _line_value(fl, n1, n2, nv, a + h)
        f = f0 + val
        if f > 0.0:
            return _line_root(fl, f0, n1, n2, nv, a + h, b, f, fb)
        if f < 0.0:
            b = a + h
            fb = f
        if h == 0.0:
            break
    return b


@jit
def line_exit(fl, f0, nx, ny, lo, hi, deflate):
    """First exit root in ``(lo, hi]`` of ``f(t) = f0 + n . (q(t) - q(0))`` along a thermostatted flight, or inf.

    ``f`` is positive on the table side (``n`` need not be unit).  ``deflate`` (with ``lo = 0``): ``f0 = 0`` is the root
    ``t = 0`` of the element just hit, removed; the sign just after it is that of ``f'(0)`` (or ``f''(0)``).
    """
    n1, n2 = _field_parts(fl, nx, ny)
    nv = nx * fl[2] + ny * fl[3]
    tc = _critical_time(fl, n1, n2)
    if lo == 0.0:
        fa = f0
        if deflate:
            fa = 0.0
            der = nx * fl[2] + ny * fl[3]
            if der == 0.0:  # a contact along the line: the curvature decides
                aex, aey = drag(fl[2], fl[3], fl[12], fl[13])
                der = nx * aex + ny * aey
            pos = der > 0.0
        else:
            pos = fa > 0.0
    else:
        val, der = _line_value(fl, n1, n2, nv, lo)
        fa = f0 + val
        pos = fa > 0.0
    if pos and fa > 0.0 and hi < INF and fa > c_bound(fl, n1, n2) * (hi - lo):
        return INF  # |f'| <= c |n|: f cannot reach 0 in the window
    return _exit_from(fl, f0, n1, n2, nv, lo, fa, pos, hi, tc)


@jit(inline="always")
def c_bound(fl, n1, n2):
    """``c |n|``, a bound on ``|f'|``."""
    return fl[4] * math.hypot(n1, n2)


@jit
def face_exit(fl, f0, nx, ny, t_in):
    """First time ``>= t_in`` at which ``f = f0 + n . (q(t) - q(0))`` (a strip's face, positive inside) leaves.

    On or past the face at ``t_in`` and moving out: ``t_in`` (leave at once).
    """
    n1, n2 = _field_parts(fl, nx, ny)
    nv = nx * fl[2] + ny * fl[3]
    tc = _critical_time(fl, n1, n2)
    if t_in == 0.0:
        fa = f0
        der = nv
        vx = fl[2]
        vy = fl[3]
    else:
        val, der = _line_value(fl, n1, n2, nv, t_in)
        fa = f0 + val
        vx, vy = state(fl, t_in)[2:]
    if fa <= 0.0:
        if der == 0.0:  # along the face: the path's curvature decides
            aex, aey = drag(vx, vy, fl[12], fl[13])
            der = nx * aex + ny * aey
        if der < 0.0:
            return t_in
    return _exit_from(fl, f0, n1, n2, nv, t_in, fa, fa > 0.0, INF, tc)


# ---------------------------------------------------------------------------- circles and arcs
@jit(inline="always")
def _first_root(g, g1, m):
    """Smallest ``tau > 0`` with ``g + g1 tau + m tau^2 = 0`` for ``g >= 0`` (inf if none), without cancellation."""
    if m == 0.0:
        return -g / g1 if g1 < 0.0 else INF
    if m > 0.0:
        if g1 >= 0.0:
            return INF
        disc = g1 * g1 - 4.0 * m * g
        if disc < 0.0:
            return INF
        return 2.0 * g / (-g1 + math.sqrt(disc))
    disc = g1 * g1 - 4.0 * m * g
    sq = math.sqrt(disc)
    if g1 >= 0.0:
        return (g1 + sq) / (-2.0 * m)
    return 2.0 * g / (sq - g1)


@jit(inline="always")
def _round_at(fl, cx, cy, sig, r, t):
    """``(dx, dy, vx, vy, lam, G, G')`` at time ``t`` for the circle of centre ``(cx, cy)``."""
    x0, y0, vx0, vy0, c, _k, _R, _C2, _S2, _SC, lam0, _sgn, fx, fy = fl
    if t == 0.0:
        dx = x0 - cx
        dy = y0 - cy
        vx = vx0
        vy = vy0
        lam = lam0
    else:
        tl, dX, dY, cphi, sphi, lam = displacement(fl, t)
        dx = ((x0 - cx) + tl * vx0) + (dX * fx - dY * fy)
        dy = ((y0 - cy) + tl * vy0) + (dX * fy + dY * fx)
        vx = c * (cphi * fx - sphi * fy)
        vy = c * (cphi * fy + sphi * fx)
    G = sig * ((dx * dx + dy * dy) - r * r)
    G1 = sig * 2.0 * (dx * vx + dy * vy)
    return dx, dy, vx, vy, lam, G, G1


@jit
def _round_root(fl, cx, cy, sig, r, a, b):
    """Root in ``[a, b]`` of ``G`` with ``G(a) >= 0 >= G(b)`` certified: safeguarded Newton on the closed form."""
    Ga = _round_at(fl, cx, cy, sig, r, a)[5]
    if Ga <= 0.0:
        return a
    Gb = _round_at(fl, cx, cy, sig, r, b)[5]
    if Gb >= 0.0:
        return b
    t = secant_start(a, b, Ga, Gb)
    for _ in range(ROOT_MAX_ITER):
        G, G1 = _round_at(fl, cx, cy, sig, r, t)[5:]
        a, b, t, done = bracket_step(a, b, t, G, G1, True)
        if done:
            break
    return t


@jit(inline="always")
def _in_extent(kind, p, fl, sx, sy, t, extent_tol):
    """True if the flight's point at time ``t``, shifted back by ``(sx, sy)``, lies in the element's extent."""
    hx, hy = state(fl, t)[:2]
    return extent_position(kind, p, hx - sx, hy - sy, extent_tol) >= 0


@jit
def _straight_round_hit(kind, p, fl, sx, sy, cx, cy, sig, r, lo, hi, deflate, extent_tol):
    """A straight flight (along or against the field): the quadratic's exit root if in ``(lo, hi]`` and the extent."""
    t = straight_circle_exit(fl[0] - cx, fl[1] - cy, fl[2], fl[3], sig, r, deflate, hi)
    if not t > lo:
        return INF
    if t < INF and kind == ARC and not _in_extent(kind, p, fl, sx, sy, t, extent_tol):
        return INF
    return t


@jit(inline="always")
def _receding(fl, r, hi, lam, dx, dy):
    """True if, with no end to the window, the flight is beyond the circle along the field and moves on along it."""
    return hi == INF and lam <= 0.0 and dx * fl[12] + dy * fl[13] > r


@jit(inline="always")
def _step_bounds(fl, r, E, dn, lam, a, hi, d0):
    """``(span, Q, noise)`` of the step from ``a``: the window, the curvature term and the rounding of ``G``."""
    c = fl[4]
    S = 1.0 if lam >= 0.0 else 1.0 / math.cosh(lam)
    W = (dn + r) / c
    Q = (2.0 * dn + r) * E * S
    span = min(W, hi - a)
    noise = 32.0 * EPS * (dn + r) * (dn + r + d0 + c * a)
    return span, Q, noise


@jit
def _tangency(fl, E, sig, dx, dy, vx, vy, G, G1, a, tlo, span, noise):
    """``G`` zero to rounding and no sure crossing: ``(root, tlo)``, decided by ``G''``.

    At the circle and curving out: it leaves here.  A dip deeper than the rounding: the first crossing.  Otherwise a
    tangency (no collision): the step ``tlo`` is lengthened past the minimum of ``G``.
    """
    root = INF
    aex, aey = drag(vx, vy, E * fl[12], E * fl[13])
    G2 = sig * 2.0 * ((vx * vx + vy * vy) + (dx * aex + dy * aey))
    if G2 <= 0.0 and G1 <= 0.0:
        root = a + _first_root(max(G, 0.0), G1, 0.5 * G2)
    elif G1 < 0.0 and G2 > 0.0:
        tm = -G1 / G2
        if G - 0.5 * G1 * G1 / G2 < -noise:
            root = a + 2.0 * G / (-G1 + math.sqrt(G1 * G1 - 2.0 * G2 * G))
        else:
            tlo = min(max(tlo, 2.0 * tm), span)
    return root, tlo


@jit(inline="always")
def _table_side_step(fl, E, cx, cy, sig, r, dx, dy, vx, vy, lam, G, G1, a, hi, span, Q, noise):
    """On the table side at ``a``: ``(step, root)``, a crossing ``root`` (inf if none) or else a safe ``step``.

    The lower quadratic's first root is a step that cannot pass a crossing; once the upper one's is in the window too,
    the bracket holds the exit.  ``step`` inf: the flight recedes for good, no exit.
    """
    c = fl[4]
    tlo = _first_root(G, G1, sig * c * c - Q)
    if tlo < span:
        tup = _first_root(G, G1, sig * c * c + Q)
        if tup <= span:
            return tlo, _round_root(fl, cx, cy, sig, r, a + tlo, a + tup)
        if G <= noise:
            root, tlo = _tangency(fl, E, sig, dx, dy, vx, vy, G, G1, a, tlo, span, noise)
            return tlo, root
        return tlo, INF
    if _receding(fl, r, hi, lam, dx, dy):
        return INF, INF
    return span, INF


@jit(inline="always")
def _off_side_step(fl, sig, r, dx, dy, lam, G, G1, hi, span, Q):
    """Off the table side at ``a`` (``G <= 0``): the step until ``G`` may be positive again (inf: never)."""
    c = fl[4]
    tin = _first_root(max(-G, 0.0), -G1, -(sig * c * c + Q))
    if tin < span:
        return tin
    if _receding(fl, r, hi, lam, dx, dy):
        return INF
    return span


#: What a crossing found by :func:`round_hit` is: the hit, past the window (no hit), or outside an
#: arc's extent (the search goes on from it).
HIT = 1
MISS = 2
PASS = 0


@jit(inline="always")
def _crossing_verdict(kind, p, fl, sx, sy, lo, hi, extent_tol, root):
    """:data:`HIT`, :data:`MISS` or :data:`PASS` for a crossing of the circle at time ``root``."""
    if root > lo and root <= hi:
        if kind != ARC or _in_extent(kind, p, fl, sx, sy, root, extent_tol):
            return HIT
        return PASS
    if root > hi:
        return MISS
    return PASS


@jit
def round_hit(kind, p, fl, sx, sy, lo, hi, deflate, extent_tol, E):
    """First exit root in ``(lo, hi]`` of a circle or arc copy (shifted by ``(sx, sy)``) within its extent, or inf.

    Conservative steps between the quadratic bounds of the module docstring; ``deflate`` (with ``lo = 0``): the copy was
    just hit at ``t = 0``.  After :data:`MAX_STEPS` steps without a decision: :data:`GAVE_UP` (negative).
    """
    cx = p[0] + sx
    cy = p[1] + sy
    r = p[2]
    sig = p[3]
    if fl[11] == 0.0:  # a straight flight: one quadratic exit at most
        return _straight_round_hit(kind, p, fl, sx, sy, cx, cy, sig, r, lo, hi, deflate, extent_tol)
    d0 = math.hypot(fl[0] - cx, fl[1] - cy)
    a = lo
    dx, dy, vx, vy, lam, G, G1 = _round_at(fl, cx, cy, sig, r, a)
    if deflate and a == 0.0:
        G = 0.0
    out = False  # just crossed out of the table side (an exit outside an arc's extent)
    for _ in range(MAX_STEPS):
        if a >= hi:
            return INF
        dn = math.hypot(dx, dy)
        span, Q, noise = _step_bounds(fl, r, E, dn, lam, a, hi, d0)
        if not out and (G > 0.0 or (G == 0.0 and G1 > 0.0)):
            step, root = _table_side_step(fl, E, cx, cy, sig, r, dx, dy, vx, vy, lam, G, G1, a, hi, span, Q, noise)
            if root < INF:
                verdict = _crossing_verdict(kind, p, fl, sx, sy, lo, hi, extent_tol, root)
                if verdict != PASS:
                    return root if verdict == HIT else INF
                a = max(root, a)
                out = True
                dx, dy, vx, vy, lam, G, G1 = _round_at(fl, cx, cy, sig, r, a)
                continue
        else:
            step = _off_side_step(fl, sig, r, dx, dy, lam, G, G1, hi, span, Q)
            out = False
        if step == INF:
            return INF
        if not a + step > a:  # no progress: the bound's step is zero or below the resolution of a (a flight
            # re-entering the table side with G zero to rounding stepped by 4e-16 at a = 5 and stalled for
            # MAX_STEPS steps); move on by a rounding step
            step = max(4.0 * EPS * a, EPS * dn / fl[4])
        a += step
        dx, dy, vx, vy, lam, G, G1 = _round_at(fl, cx, cy, sig, r, a)
    return GAVE_UP  # undecided: the caller must not read this as "no hit"


# ---------------------------------------------------------------------------- elements, cells, lattices
@jit
def element_hit(kind, p, fl, sx, sy, deflate, lo, hi, extent_tol, E):
    """First time in ``(lo, hi]`` at which the thermostatted flight leaves the table through this copy, or inf.

    :data:`GAVE_UP` (negative) when a circle search ran out of steps (:func:`round_hit`).
    """
    if kind == LINE or kind == SEGMENT:
        nx = p[2]
        ny = p[3]
        f0 = 0.0 if deflate else ((fl[0] - sx) - p[0]) * nx + ((fl[1] - sy) - p[1]) * ny
        t = line_exit(fl, f0, nx, ny, lo, hi, deflate)
        if t < INF and kind == SEGMENT and not _in_extent(kind, p, fl, sx, sy, t, extent_tol):
            return INF
        return t
    return round_hit(kind, p, fl, sx, sy, lo, hi, deflate, extent_tol, E)

"""Slow, obviously correct twins of the event-time kernels (stumpy's habit).

Everything here works from the *exact* values of the float inputs: every
float is a dyadic rational, so coefficients of the crossing polynomials are
built as :class:`fractions.Fraction` with no rounding at all.  Real roots are
isolated with a Sturm sequence of the square-free part (exact integer
arithmetic) and bisected to ~1e-42 relative; positions and angles at a root
are then evaluated with mpmath at 50 digits.

Nothing here shares code with ``noslipsim.core``: the twins are built from the
definitions (docs/algorithm.md):

* the crossing polynomial of an element is its signed distance along the
  flight, positive on the table side (a positive multiple of it for segments
  and circles: only its sign matters);
* an *exit* is a real root in ``(0, hi]`` where the polynomial changes sign
  from + to - (tangencies and other even-multiplicity roots are not exits);
* the hit on a segment or arc is the first exit whose point lies in the
  element's extent, ends inclusive within an absolute length ``tol``;
* deflation (the element just hit) drops the constant term exactly and divides
  by ``t``: ``h(t) = (p(t) - p(0)) / t``.
"""
from __future__ import annotations

import math
from fractions import Fraction
from math import gcd

import mpmath

DPS = 50
#: Roots are bisected until their bracket is below ``2**-REL_BITS`` relative.
REL_BITS = 140


def mp(x):
    """A Fraction (or float/int) as an mpmath number at ``DPS`` digits."""
    with mpmath.workdps(DPS):
        if isinstance(x, Fraction):
            return mpmath.mpf(x.numerator) / x.denominator
        return mpmath.mpf(x)


# --------------------------------------------------------------------------- exact polynomials
# A polynomial is a list of Fractions, lowest degree first.

def _trim(c):
    c = list(c)
    while c and c[-1] == 0:
        c.pop()
    return c


def _exact(coeffs):
    out = []
    for v in coeffs:
        if isinstance(v, Fraction):
            out.append(v)
        else:
            v = float(v)
            if not math.isfinite(v):
                raise ValueError(f"non-finite coefficient {v!r}")
            out.append(Fraction(v))
    return _trim(out)


def poly_value(c, x):
    """Exact value of the polynomial ``c`` at the rational ``x``."""
    acc = Fraction(0)
    for ci in reversed(c):
        acc = acc * x + ci
    return acc


def poly_derivative(c):
    return _trim([i * c[i] for i in range(1, len(c))])


def _divmod(a, b):
    a = list(a)
    q = [Fraction(0)] * max(len(a) - len(b) + 1, 1)
    while len(a) >= len(b) and a:
        k = len(a) - len(b)
        f = a[-1] / b[-1]
        q[k] = f
        for i, bi in enumerate(b):
            a[i + k] -= f * bi
        a.pop()  # the leading term cancelled exactly
        a = _trim(a)
    return _trim(q), a


def _gcd(a, b):
    while b:
        a, b = b, _divmod(a, b)[1]
    return [ci / a[-1] for ci in a]


def _squarefree(c):
    g = _gcd(c, poly_derivative(c))
    return _divmod(c, g)[0] if len(g) > 1 else c


def _integer(c):
    """Positive multiple of ``c`` with coprime integer coefficients (same signs everywhere)."""
    den = 1
    for ci in c:
        den = den * ci.denominator // gcd(den, ci.denominator)
    ints = [int(ci * den) for ci in c]
    g = 0
    for v in ints:
        g = gcd(g, v)
    return [v // g for v in ints] if g > 1 else ints


def _sign_at(ci, n, k):
    """Sign of the integer polynomial ``ci`` at the dyadic rational ``n / 2^k`` (exact)."""
    acc = ci[-1]
    shift = 0
    for v in reversed(ci[:-1]):
        shift += k
        acc = acc * n + (v << shift)
    return (acc > 0) - (acc < 0)


def _dyadic(x):
    """``(n, k)`` with ``x = n / 2^k`` for a Fraction whose denominator is a power of two."""
    d = x.denominator
    k = d.bit_length() - 1
    assert d == 1 << k, x
    return x.numerator, k


def _sturm(q):
    chain = [q, poly_derivative(q)]
    while len(chain[-1]) > 1:
        r = _divmod(chain[-2], chain[-1])[1]
        if not r:
            break
        chain.append([-v for v in r])
    return [_integer(c) for c in chain if c]


def _variations(chain, n, k):
    """Sign changes of the Sturm chain at ``n / 2^k`` (zeros skipped)."""
    prev = 0
    count = 0
    for c in chain:
        s = _sign_at(c, n, k)
        if s:
            if prev and s != prev:
                count += 1
            prev = s
    return count


def _pow2_above(x):
    """A power of two >= x > 0 (a Fraction)."""
    k = 0
    p = Fraction(1)
    while p < x:
        p *= 2
        k += 1
    return p


def _classify(c, a, b):
    """Kind of the one root of ``c`` in ``(a, b]`` (``a`` is not a root): 'exit', 'entry' or 'touch'."""
    pb = poly_value(c, b)
    pa = poly_value(c, a)
    if pb != 0:
        if pa > 0 > pb:
            return "exit"
        if pa < 0 < pb:
            return "entry"
        return "touch"
    # exact rational root at b: the first nonzero derivative decides
    d = c
    m = 0
    while True:
        d = poly_derivative(d)
        m += 1
        v = poly_value(d, b)
        if v != 0:
            break
    if m % 2 == 0:
        return "touch"
    return "exit" if v < 0 else "entry"


def naive_real_roots(coeffs, hi=math.inf):
    """Every distinct real root of the polynomial in ``(0, hi]`` with its kind.

    Returns a sorted list of ``(root, kind, bracket)``: ``root`` an mpmath
    number (50 digits), ``kind`` in {'exit', 'entry', 'touch'} and ``bracket``
    the exact rational ``(a, b]`` holding it (relative width < 2^-140).
    """
    c = _exact(coeffs)
    if len(c) <= 1:
        return []
    if hi <= 0:
        return []
    cauchy = 1 + max(abs(ci) for ci in c[:-1]) / abs(c[-1])
    top = _pow2_above(cauchy)
    if hi != math.inf:
        top = min(top, Fraction(float(hi)))
    q = _squarefree(c)
    chain = _sturm(q)
    qi = chain[0]
    # brackets (A, B] / 2^k: every endpoint is dyadic (floats and powers of two are)
    B, k = _dyadic(top)
    out = []
    stack = [(0, B, k, _variations(chain, 0, k), _variations(chain, B, k))]
    while stack:
        A, B, k, va, vb = stack.pop()
        n = va - vb
        if n == 0:
            continue
        M, A, B, k = A + B, 2 * A, 2 * B, k + 1
        if n > 1:
            vm = _variations(chain, M, k)
            stack.append((A, M, k, va, vm))
            stack.append((M, B, k, vm, vb))
            continue
        # exactly one root in (A, B]: bisect until A > 0 and (B - A) < 2^-REL_BITS A.  While A is a
        # root itself (t = 0, excluded) the chain decides; then the sign of q does.
        sa = _sign_at(qi, A, k)
        while True:
            if A > 0 and (B - A) << REL_BITS <= A:
                break
            if sa == 0:
                vm = _variations(chain, M, k)
                if va - vm == 1:
                    B = M
                else:
                    A, va = M, vm
                    sa = _sign_at(qi, A, k)
            else:
                sm = _sign_at(qi, M, k)
                if sm == sa:
                    A = M
                else:
                    B = M          # a sign change, or q(M) == 0: the root is in (A, M]
            M, A, B, k = A + B, 2 * A, 2 * B, k + 1
        a, b = Fraction(A, 1 << k), Fraction(B, 1 << k)
        kind = _classify(c, a, b)
        root = b if poly_value(q, b) == 0 else (a + b) / 2
        out.append((mp(root), kind, (a, b)))
    out.sort(key=lambda r: r[0])
    return out


def naive_exit_roots(coeffs, hi=math.inf):
    """Sorted exit roots (``+`` to ``-`` sign changes) in ``(0, hi]`` of ``c0 + c1 t + ...``, 50 digits."""
    return [r for r, kind, _ in naive_real_roots(coeffs, hi) if kind == "exit"]


# --------------------------------------------------------------------------- flights and elements

def _flight(q, v, a):
    """Exact coordinate polynomials ``x(t), y(t)`` of ``q + v t + a t^2 / 2``."""
    (qx, qy), (vx, vy), (ax, ay) = ([Fraction(float(u)) for u in w] for w in (q, v, a))
    return [qx, vx, ax / 2], [qy, vy, ay / 2]


def _padd(a, b):
    n = max(len(a), len(b))
    return [(a[i] if i < len(a) else 0) + (b[i] if i < len(b) else 0) for i in range(n)]


def _pscale(a, s):
    return [s * v for v in a]


def _pmul(a, b):
    out = [Fraction(0)] * (len(a) + len(b) - 1)
    for i, x in enumerate(a):
        for j, y in enumerate(b):
            out[i + j] += x * y
    return out


def _type(element):
    return type(element).__name__


def naive_crossing_poly(element, q, v, a):
    """Exact coefficients (Fractions, low degree first, length 5) of a positive multiple of the
    element's signed distance along the flight, and the factor ``k`` (a float) it is multiplied
    by: the signed distance to the supporting line or circle is ``p(t) / k`` to first order.

    Line: ``(q(t) - point) . normal``; segment: ``s * cross(p1 - p0, q(t) - p0)`` with ``s = +1``
    for a table on the left (``k = |p1 - p0|``); circle and arc: ``sigma (|q(t) - c|^2 - r^2)``
    with ``sigma = +1`` outside (``k = 2 r``).
    """
    X, Y = _flight(q, v, a)
    name = _type(element)
    if name == "Line":
        px, py = (Fraction(u) for u in element.point)
        nx, ny = (Fraction(u) for u in element.normal)
        p = _padd(_pscale(_padd(X, [-px]), nx), _pscale(_padd(Y, [-py]), ny))
        k = math.hypot(*element.normal)
    elif name == "Segment":
        x0, y0 = (Fraction(u) for u in element.p0)
        x1, y1 = (Fraction(u) for u in element.p1)
        dx, dy = x1 - x0, y1 - y0
        s = 1 if element.side == "left" else -1
        p = _pscale(_padd(_pscale(_padd(Y, [-y0]), dx), _pscale(_padd(X, [-x0]), -dy)), s)
        k = math.hypot(float(dx), float(dy))
    elif name in ("Circle", "Arc"):
        cx, cy = (Fraction(u) for u in element.center)
        r = Fraction(element.radius)
        sig = 1 if element.side == "outside" else -1
        DX, DY = _padd(X, [-cx]), _padd(Y, [-cy])
        p = _pscale(_padd(_padd(_pmul(DX, DX), _pmul(DY, DY)), [-r * r]), sig)
        k = 2.0 * element.radius
    else:  # pragma: no cover
        raise TypeError(f"unknown element {element!r}")
    p = list(p) + [Fraction(0)] * (5 - len(p))
    return p, k


def _extent_excess(element, x, y):
    """How far (a length, mpmath) the point lies outside the element's extent; <= 0 inside."""
    name = _type(element)
    with mpmath.workdps(DPS):
        if name == "Segment":
            x0, y0 = (mp(u) for u in element.p0)
            x1, y1 = (mp(u) for u in element.p1)
            L = mpmath.hypot(x1 - x0, y1 - y0)
            u = ((x - x0) * (x1 - x0) + (y - y0) * (y1 - y0)) / L
            if u < 0:
                return -u
            if u > L:
                return u - L
            return -min(u, L - u)
        if name == "Arc":
            cx, cy = (mp(u) for u in element.center)
            r = mp(element.radius)
            two_pi = 2 * mpmath.pi
            rel = mpmath.atan2(y - cy, x - cx) - mp(element.theta0)
            rel -= two_pi * mpmath.floor(rel / two_pi)
            span = mp(element.theta1) - mp(element.theta0)
            if rel <= span:
                return -r * min(rel, span - rel)
            return r * min(rel - span, two_pi - rel)
    return mpmath.mpf(-1)  # lines and circles have no ends


def naive_flight_exits(element, q, v, a, deflate=False, hi=math.inf):
    """All exits of the flight through the element's supporting curve in ``(0, hi]``.

    Returns a list of dicts ``{t, excess, kind}`` sorted by ``t`` (``kind`` 'exit'), where
    ``excess`` is the distance of the exit point outside the extent (<= 0 inside), and also
    the non-exit roots (``kind`` 'entry'/'touch') for conditioning checks.
    """
    p, _ = naive_crossing_poly(element, q, v, a)
    if deflate:
        p = [*p[1:], Fraction(0)]
    X, Y = _flight(q, v, a)
    out = []
    for t, kind, br in naive_real_roots(p, hi):
        with mpmath.workdps(DPS):
            x = sum(mp(ci) * t ** i for i, ci in enumerate(X))
            y = sum(mp(ci) * t ** i for i, ci in enumerate(Y))
            out.append({"t": t, "kind": kind, "excess": _extent_excess(element, x, y), "bracket": br})
    return out


def naive_element_hit_time(element, q, v, a, deflate=False, hi=math.inf, tol=0.0):
    """First exit time in ``(0, hi]`` through ``element`` whose point is in its extent (ends
    inclusive within the absolute length ``tol``), as a 50-digit mpmath number, or ``mpmath.inf``.
    """
    for e in naive_flight_exits(element, q, v, a, deflate, hi):
        if e["kind"] == "exit" and e["excess"] <= tol:
            return e["t"]
    return mpmath.inf


def naive_roots_between(coeffs, lo, hi):
    """Every distinct real root in the closed interval ``[lo, hi]`` (finite), sorted, 50 digits.

    Substitutes ``t = lo + s`` exactly (Taylor shift) and searches ``s`` in ``(0, hi - lo]``.
    """
    c = _exact(coeffs)
    lo, hi = Fraction(float(lo)), Fraction(float(hi))
    if not c or hi < lo:
        return []
    # shifted polynomial: coefficients of p(lo + s) in s
    shifted = [Fraction(0)] * len(c)
    for n, cn in enumerate(c):  # add cn (lo + s)^n
        for k in range(n + 1):
            shifted[k] += cn * math.comb(n, k) * lo ** (n - k)
    out = [mp(lo)] if poly_value(c, lo) == 0 else []
    if hi > lo:
        with mpmath.workdps(DPS):
            out += [mp(lo) + r for r, _, _ in naive_real_roots(shifted, hi - lo)]
    return out


# --------------------------------------------------------------------------- conditioning

EPS = 2.0 ** -52


def predicted_root_error(coeffs, root, mags, k_eval):
    """The error a backward-stable float method can make on ``root`` (mpmath, absolute).

    The float method sees a polynomial perturbed by ``delta(t) = k_eval eps sum mags_i |t|^i``
    (``mags_i >= |c_i|``: the size of the terms each coefficient was computed from).  Near a root
    where the first ``k - 1`` derivatives are small the root moves by about
    ``(k! delta / |p^(k)(r)|)^(1/k)``: the minimum over ``k`` is the prediction (``k = 1`` for a
    simple root, ``k = 2`` gives the ``sqrt(eps)`` scale of a near-double root).
    """
    c = _exact(coeffs)
    with mpmath.workdps(DPS):
        r = abs(mpmath.mpf(root))
        delta = k_eval * EPS * sum(mpmath.mpf(float(m)) * r ** i for i, m in enumerate(mags))
        best = mpmath.inf
        d = c
        fact = 1
        for k in range(1, len(c)):
            d = poly_derivative(d)
            fact *= k
            v = abs(sum(mp(di) * mpmath.mpf(root) ** i for i, di in enumerate(d)))
            if v > 0:
                best = min(best, (fact * delta / v) ** (mpmath.mpf(1) / k))
        return best


def backward_residual(coeffs, t, mags):
    """``|p(t)| / (eps sum mags_i |t|^i)``: how many units of rounding ``t`` is from being a root."""
    c = _exact(coeffs)
    tf = Fraction(float(t))
    with mpmath.workdps(DPS):
        val = abs(mp(poly_value(c, tf)))
        scale = EPS * sum(mpmath.mpf(float(m)) * abs(mp(tf)) ** i for i, m in enumerate(mags))
        return val / scale if scale > 0 else (mpmath.inf if val else mpmath.mpf(0))


def naive_all_real_roots(coeffs):
    """Every distinct real root on the whole line, sorted, 50 digits (``p(-t)`` gives the negative ones)."""
    c = _exact(coeffs)
    if len(c) <= 1:
        return []
    neg = [-r for r, _, _ in naive_real_roots([ci if i % 2 == 0 else -ci for i, ci in enumerate(c)])]
    zero = [mp(0)] if c[0] == 0 else []
    pos = [r for r, _, _ in naive_real_roots(c)]
    return sorted(neg) + zero + pos


def crossing_magnitudes(element, q, v, a):
    """Sizes ``m_i >= |c_i|`` of the terms the float crossing coefficients are computed from,
    in the normalisation of :func:`naive_crossing_poly` (for :func:`predicted_root_error`).

    A float kernel computing ``c_i`` makes an error of a few ``eps m_i``.  The first operation on
    the inputs, a difference like ``x - c_x``, is correctly rounded (its error is relative to the
    difference), so sizes are built from the differences: for a circle ``c0 = |q - c|^2 - r^2``
    is computed from terms of size ``|q - c|^2 + r^2``.
    """
    (vx, vy), (ax, ay) = ([abs(float(u)) for u in w] for w in (v, a))
    x, y = (float(u) for u in q)
    name = _type(element)
    if name in ("Line", "Segment"):
        if name == "Line":
            (px, py), (nx, ny) = element.point, element.normal
        else:
            (px, py), (x1, y1) = element.p0, element.p1
            nx, ny = y1 - py, x1 - px          # |normal| * L, components up to sign and order
        nx, ny = abs(nx), abs(ny)
        dx, dy = abs(x - px), abs(y - py)
        return [dx * nx + dy * ny, vx * nx + vy * ny, 0.5 * (ax * nx + ay * ny), 0.0, 0.0]
    r = element.radius
    DX, DY = abs(x - element.center[0]), abs(y - element.center[1])
    return [DX * DX + DY * DY + r * r, 2.0 * (DX * vx + DY * vy),
            vx * vx + vy * vy + DX * ax + DY * ay, vx * ax + vy * ay, 0.25 * (ax * ax + ay * ay)]


def root_clusters(coeffs, roots, mags, k_eval, c_pred, well, rel_tol, sep):
    """Group real roots (from :func:`naive_real_roots`) that a float method cannot tell apart.

    Each root gets an allowed error ``c_pred * predicted_root_error + 4 eps t`` (capped at
    ``rel_tol * t`` when the prediction is below ``well * t``: then it is "well conditioned").
    Neighbours closer than ``max(sep * t, 2 (allowed + allowed'))`` share a cluster.  A cluster
    has a window ``[lo, hi]`` (its roots +- their allowed errors) and the sign of the polynomial
    just before (``left``) and after (``right``) it: ``left > 0 > right`` means the flight
    certainly leaves there, however the roots inside are resolved.
    """
    c = _exact(coeffs)
    info = []
    for r, kind, (a, _) in roots:
        pred = predicted_root_error(c, r, mags, k_eval)
        with mpmath.workdps(DPS):
            allowed = c_pred * pred + 4 * EPS * r
            is_well = pred <= well * r
            if is_well:
                allowed = min(allowed, rel_tol * r)
        pa = poly_value(c, a)
        left = {"exit": 1, "entry": -1}.get(kind, (pa > 0) - (pa < 0))
        right = {"exit": -1, "entry": 1}.get(kind, left)
        info.append({"t": r, "kind": kind, "allowed": allowed, "well": is_well,
                     "left": left, "right": right})
    clusters = []
    with mpmath.workdps(DPS):
        for x in info:
            if clusters:
                y = clusters[-1][-1]
                if x["t"] - y["t"] <= max(sep * x["t"], 2 * (x["allowed"] + y["allowed"])):
                    clusters[-1].append(x)
                    continue
            clusters.append([x])
        return [{"roots": cl, "lo": min(x["t"] - x["allowed"] for x in cl),
                 "hi": max(x["t"] + x["allowed"] for x in cl),
                 "left": cl[0]["left"], "right": cl[-1]["right"]} for cl in clusters]

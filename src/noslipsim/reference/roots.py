"""Roots of the crossing polynomials: steps 2 and 3 of :mod:`noslipsim.reference`.

Polynomials are lists of ascending coefficients in the flight time ``t``
(mpf, at the caller's context).  :func:`_real_roots` finds all real roots
(closed forms up to degree 2, :func:`mpmath.polyroots` beyond);
:func:`_exit_roots` keeps those ``t > 0`` where the polynomial leaves the
table side.  :func:`_flight` is the free flight ``q(t)`` they are measured on.
"""
from __future__ import annotations

import inspect


def _polyval(coeffs, t):
    """``sum(coeffs[k] t^k)`` by Horner's rule."""
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
        coeffs = [ctx.zero, *list(coeffs[1:])]
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
    """The position ``q + v t + a t^2 / 2`` after a free flight of duration ``t``."""
    return x + vx * t + ax * t * t / 2, y + vy * t + ay * t * t / 2

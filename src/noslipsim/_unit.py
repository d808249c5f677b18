"""Float pairs on the unit circle to the last bit.

The collision law applies ``(n, t)`` frames and the rotation ``(c, s)`` once
per collision.  If ``x^2 + y^2`` of a stored pair is off 1 by ``delta``, the
kinetic energy is scaled by ``1 + delta`` at every collision: a drift that
grows linearly with the number of collisions.  Choosing, among the floats a
few ulps around the rounded pair, the one with ``x^2 + y^2`` closest to 1 in
exact rational arithmetic leaves only unbiased rounding (a random walk).
"""
import math
from fractions import Fraction
from functools import lru_cache

_ULPS = 6


@lru_cache(maxsize=4096)
def unit_pair(x: float, y: float):
    """The float pair nearest the direction of ``(x, y)`` with ``x^2 + y^2`` closest to 1."""
    x, y = float(x), float(y)
    r = math.hypot(x, y)
    x0, y0 = x / r, y / r
    best, best_err = (x0, y0), None
    xs = _neighbours(x0)
    ys = _neighbours(y0)
    for xc in xs:
        fx = Fraction(xc) ** 2
        for yc in ys:
            err = abs(fx + Fraction(yc) ** 2 - 1)
            if best_err is None or err < best_err:
                best, best_err = (xc, yc), err
    return best


def _neighbours(v):
    out = [v]
    up = down = v
    for _ in range(_ULPS):
        up = math.nextafter(up, math.inf)
        down = math.nextafter(down, -math.inf)
        out += [up, down]
    return out

"""Error-free transformations: sums and products carried to twice the working precision.

A long flight forms small quantities (its offset from a far disk's centre across the flight, a hit
point relative to an element) as differences of large ones, each rounded to ``eps`` times the
flight's length.  These primitives keep the rounding error of each step as a second float, so such a
difference comes out to ``eps`` times its own size: :func:`two_sum` (Knuth), :func:`two_prod` (one
fused multiply-add; Ogita, Rump & Oishi 2005), and from them :func:`lattice_shift_dd`,
:func:`cross_dd` and :func:`shifted_dot`.

Python 3.11 has no ``math.fma``; :func:`fma` is LLVM's ``llvm.fma.f64`` (one instruction on an FMA
machine, a correctly rounded library call on any other), so the transformations are exact
everywhere; kernels never use fastmath (:mod:`jit`), so the compiler neither reassociates the sums
nor contracts products into fused ones.

References: Knuth, TAOCP vol. 2, 4.2.2; Ogita, Rump & Oishi, "Accurate sum
and dot product", SIAM J. Sci. Comput. 26 (2005).
"""
import math
from fractions import Fraction

from numba import config, types
from numba.extending import intrinsic

from .jit import jit


@intrinsic
def _fma(typingctx, a, b, c):
    """``a b + c`` rounded once (``llvm.fma.f64``)."""
    if not all(isinstance(x, types.Float) for x in (a, b, c)):
        return None
    sig = types.float64(types.float64, types.float64, types.float64)

    def codegen(context, builder, signature, args):
        x, y, z = (context.cast(builder, v, t, types.float64) for v, t in zip(args, signature.args, strict=True))
        return builder.fma(x, y, z)

    return sig, codegen


# A name that is the same in every process, as core/jit.py gives every kernel: numba pickles
# a kernel's globals into the cache key of kernels built around it, and an intrinsic's
# default name is a random UUID (the batch loops would miss the on-disk cache).
_fma._set_uuid("noslipsim-core-exact-fma")


@jit(inline="always")
def fma(a, b, c):
    """``a b + c`` with a single rounding."""
    return _fma(a, b, c)


if config.DISABLE_JIT:  # plain Python has no llvm.fma before 3.13: round the exact rational once
    def fma(a, b, c):
        """``a b + c`` with a single rounding (exact rationals: the kernels run as Python)."""
        if not (math.isfinite(a) and math.isfinite(b) and math.isfinite(c)):
            return a * b + c
        return float(Fraction(a) * Fraction(b) + Fraction(c))


@jit(inline="always")
def two_sum(a, b):
    """``(s, e)`` with ``s = fl(a + b)`` and ``s + e = a + b`` exactly (no condition on ``|a|, |b|``)."""
    s = a + b
    bb = s - a
    e = (a - (s - bb)) + (b - bb)
    return s, e


@jit(inline="always")
def two_prod(a, b):
    """``(p, e)`` with ``p = fl(a b)`` and ``p + e = a b`` exactly (barring underflow)."""
    p = a * b
    return p, fma(a, b, -p)


@jit(inline="always")
def lattice_shift_dd(A, n1, n2):
    """``n1 a1 + n2 a2`` (columns of ``A``) as ``(xh, xl, yh, yl)``, ``x = xh + xl`` to ``eps^2 |x|``.

    The products of the integer indices with the lattice vectors are exact (:func:`two_prod`), so the translation is
    that of the float lattice the scene defines, not one rounded to ``eps`` times its length.
    """
    f1 = float(n1)
    f2 = float(n2)
    p1, e1 = two_prod(f1, A[0, 0])
    p2, e2 = two_prod(f2, A[0, 1])
    xh, e3 = two_sum(p1, p2)
    q1, g1 = two_prod(f1, A[1, 0])
    q2, g2 = two_prod(f2, A[1, 1])
    yh, g3 = two_sum(q1, q2)
    return xh, (e1 + e2) + e3, yh, (g1 + g2) + g3


@jit(inline="always")
def offset_dd(x, sh, sl):
    """``x - (sh + sl)`` as ``(h, l)``: a point ``x`` of the current cell seen from a far translation."""
    h, e = two_sum(x, -sh)
    return h, e - sl


@jit(inline="always")
def cross_dd(dxh, dxl, dyh, dyl, vx, vy):
    """``dx vy - dy vx`` for ``dx = dxh + dxl``, ``dy = dyh + dyl``, with an error of a few ulps of the result.

    The two large products are formed exactly and subtracted with :func:`two_sum`; the remaining terms are small
    (rounding errors and the low parts), so their own rounding is ``eps^2`` times the products.
    """
    a, ea = two_prod(dxh, vy)
    b, eb = two_prod(dyh, vx)
    c, ec = two_sum(a, -b)
    return c + (((ec + ea) - eb) + (dxl * vy - dyl * vx))


@jit(inline="always")
def shifted_dot(x, y, px, py, nx, ny):
    """``(x - px) nx + (y - py) ny`` with an error of a few ulps of the result (plus ``eps^2`` of its terms),
    however far ``(x, y)`` lies from ``(px, py)`` (a point on a long wall seen from the wall's start)."""
    dx, ex = two_sum(x, -px)
    dy, ey = two_sum(y, -py)
    a, ea = two_prod(dx, nx)
    b, eb = two_prod(dy, ny)
    c, ec = two_sum(a, b)
    return c + (((ec + ea) + eb) + (ex * nx + ey * ny))

"""The fused multiply-add ``a * b + c`` rounded once, for kernels (the ``llvm.fma`` intrinsic).

One instruction on x86-64 with FMA3 (numba compiles for the host CPU), a
correctly rounded library call elsewhere.  The lean loop uses it so that a
correction far below an ulp enters a result *before* its only rounding: added
to an already rounded value it would be rounded away the same way every time,
which is a bias (docs/algorithm.md section 0).
"""
import hashlib

from llvmlite import ir
from numba import types
from numba.extending import intrinsic


@intrinsic
def fma(typingctx, a, b, c):
    """``a * b + c`` rounded once (float64)."""
    sig = types.float64(types.float64, types.float64, types.float64)

    def codegen(context, builder, signature, args):
        d = ir.DoubleType()
        fn = builder.module.declare_intrinsic("llvm.fma", [d], ir.FunctionType(d, [d, d, d]))
        return builder.call(fn, args)

    return sig, codegen


# The intrinsic pickles with a UUID drawn once per process; a kernel that calls it would then have
# a new cache key in every process (as core/jit.py explains for dispatchers): name it for good.
fma._set_uuid("noslipsim-" + hashlib.sha256(f"{__name__}.fma".encode()).hexdigest())

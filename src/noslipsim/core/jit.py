"""The one place that decides how every kernel is compiled.

All kernels are compiled with ``cache=True`` (compile once per machine),
``nogil=True`` (so dask threads run kernels in parallel) and *without*
fastmath: the event solver relies on IEEE semantics (signed zeros, exact
comparisons, no reassociation of the quadratic formula).

The kernels run without numba's reference-counting runtime (``_nrt=False``):
they allocate nothing and return no arrays, so an array view (``params[e]``)
needs no owner, and every view would otherwise cost an atomic increment and
decrement.  Measured on the event loop: 2 to 5 times faster on plain scenes
(benchmarks/RESULTS.md).  A kernel that allocates fails to compile rather than
running unsafely.  ``NOSLIPSIM_NUMBA_NRT=1`` compiles with the runtime, uncached
(so the on-disk cache never mixes the two), for ``benchmarks/bench_runtime.py``.
"""
import os

from numba import njit, prange  # noqa: F401  (prange re-exported for kernels)

_OPTIONS = dict(cache=True, nogil=True, fastmath=False, error_model="numpy", _nrt=False)
if os.environ.get("NOSLIPSIM_NUMBA_NRT") == "1":
    _OPTIONS.update(cache=False, _nrt=True)


def jit(func=None, **overrides):
    """Compile ``func`` with the project's options (decorator, with or without arguments)."""
    options = dict(_OPTIONS, **overrides)
    if func is None:
        return lambda f: njit(**options)(f)
    return njit(**options)(func)

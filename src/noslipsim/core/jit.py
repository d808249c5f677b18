"""The one place that decides how every kernel is compiled.

All kernels are compiled with ``cache=True`` (compile once per machine),
``nogil=True`` (so dask threads run kernels in parallel) and *without*
fastmath: the event solver relies on IEEE semantics (signed zeros, exact
comparisons, no reassociation of the quadratic formula).
"""
from numba import njit, prange  # noqa: F401  (prange re-exported for kernels)

_OPTIONS = dict(cache=True, nogil=True, fastmath=False, error_model="numpy")


def jit(func=None, **overrides):
    """Compile ``func`` with the project's options (decorator, with or without arguments)."""
    options = dict(_OPTIONS, **overrides)
    if func is None:
        return lambda f: njit(**options)(f)
    return njit(**options)(func)

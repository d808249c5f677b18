"""The one call of the compiled event loop, and the check that the code that ran is the code asked for.

Every orbit the package computes (``simulate``, ``simulate_many``, boundary
sections, the tests and benchmarks) goes through :func:`run_orbits`: a kernel
table (:mod:`.table`), starts, limits and record buffers in; the per-orbit
summary out.  The kernel reports the variant it was compiled for
(:func:`noslipsim.core.variant.report`) in every summary row, and a result
from any other variant raises :class:`KernelMismatch` instead of returning.
"""
from __future__ import annotations

import math
import threading

import numpy as np

from ..core import layout
from ..core.batch import F_VARIANT, N_FINAL, batch_kernel
from ..core.loop import orbit_kernel
from ..core.variant import describe, normalise, report


class KernelMismatch(RuntimeError):
    """The compiled code that ran is not the variant that was asked for (a wrong compile-cache entry)."""


def run_orbits(table, starts, *, max_collisions, max_time=math.inf, levels=None, start_elements=None,
               mode=layout.RECORD_NONE, rec=None, mask=None, flags=None, ceilings=None):
    """Run orbits of one kernel table; returns their summaries.

    Parameters
    ----------
    table : KernelTable
        The scene as the kernels take it (:func:`.table.kernel_table`).
    starts : array_like (N, 5)
        ``(x, y, vx, vy, w)`` per orbit, positions relative to the start cell.
    max_collisions : int
        Collision budget per orbit.
    max_time : float
        Time limit per orbit (``inf`` for none).
    levels : array_like (N,), optional
        Stop heights relative to each start cell (``-inf``: none, the default).
    start_elements : array_like (N,) of int, optional
        ``-1`` (default) for an interior start, or the element the orbit starts
        on (its ``t = 0`` root deflated).
    mode : int
        ``layout.RECORD_NONE``, ``RECORD_LOG`` or ``RECORD_PORTRAIT``.
    rec : float ndarray (N, rows, columns), optional
        Record buffer, written in place (``N_LOG`` or ``N_PORTRAIT`` columns).
    mask : bool ndarray (n_elements,), optional
        Elements a portrait records (default: none).
    flags : Variant or tuple, optional
        The kernel variant (:class:`noslipsim.core.variant.Variant`, its slots in
        order); default ``table.variant(mode)``, the fastest exact one for the
        table.  Tests and benchmarks pass others (``core.variant.GENERAL``: every
        slot at run time).
    ceilings : array_like (N,), optional
        The top of a bounded lattice (``table.top``) relative to each start
        cell; required when ``table.top`` is finite, ``inf`` otherwise (the default).

    Returns
    -------
    ndarray (N, N_FINAL)
        Per orbit, the columns ``core.batch.F_*``: collisions, stop code, corner
        collisions, records written, final time, position (unfolded), velocity,
        spin, cell indices, reported variant.

    Raises
    ------
    ValueError
        ``flags`` is no variant (:func:`noslipsim.core.variant.normalise`).
    KernelMismatch
        The kernel that ran reports another variant than ``flags``.
    """
    starts = np.ascontiguousarray(starts, dtype=np.float64).reshape(-1, 5)
    n = len(starts)
    levels = np.full(n, -math.inf) if levels is None else np.ascontiguousarray(levels, dtype=np.float64)
    start_elements = (np.full(n, -1, dtype=np.int64) if start_elements is None
                      else np.ascontiguousarray(start_elements, dtype=np.int64))
    rec = np.zeros((n, 0, 0)) if rec is None else rec
    mask = np.zeros(len(table.kinds), dtype=np.bool_) if mask is None else mask
    if ceilings is None:
        if table.top < math.inf:
            raise ValueError("ceilings: a bounded lattice (table.top finite) needs the top relative to each start "
                             "cell")
        ceilings = np.full(n, math.inf)
    else:
        ceilings = np.ascontiguousarray(ceilings, dtype=np.float64)
        if ceilings.shape != (n,) or np.isnan(ceilings).any():
            raise ValueError(f"ceilings: expected {n} heights (or inf), got shape {ceilings.shape}")
    flags = table.variant(mode) if flags is None else normalise(*flags)  # a slot out of place raises here
    final = np.zeros((n, N_FINAL))
    args = (*table.arrays(), table.law, table.c, table.s, table.ax, table.ay, table.thermostat)
    if n:
        _load_orbit_kernel_first(flags, args, starts, max_time, levels, table.scale, mode, rec, mask, start_elements,
                                 ceilings, table.magnetic)
    _kernel(flags)(*args, starts, start_elements, max_collisions, max_time, levels, table.scale, mode, rec, mask,
                   final, ceilings, table.magnetic)
    check_variant(final[:, F_VARIANT], flags)
    return final


_BUILDING = threading.Lock()
_LOADED = set()


def _load_orbit_kernel_first(flags, args, starts, max_time, levels, scale, mode, rec, mask, start_elements, ceilings,
                             W):
    """Compile or load the orbit kernel for this call's types before the batch kernel that calls it.

    A process that compiles the batch kernel compiles the orbit kernel first, and the batch's
    machine code then calls the orbit kernel's own (numba links every callee into its caller, as a
    weak definition, and the dynamic linker keeps the definition loaded first).  A process that
    loads the batch kernel from the cache loads nothing else first, so the batch runs its own copy
    of the orbit loop: the same source optimised a second time inside the batch's module, which
    LLVM may compile differently.  On the specular Galton board that copy ran at 0.63 of the fresh
    rate (benchmarks/RESULTS.md, "A kernel loaded from the cache"; docs/algorithm.md, "The compile
    cache").  Loading the orbit kernel first, with zero collisions, makes a cached run execute the
    code a fresh one does.
    """
    key = (flags, rec.ndim, rec.dtype.str, mode)
    if key in _LOADED:
        return
    with _BUILDING:
        orbit = orbit_kernel(*flags)
        x, y, vx, vy, w = (float(value) for value in starts[0])
        orbit(*args, x, y, vx, vy, w, 0, max_time, levels[0], scale, mode, np.zeros_like(rec[0]), mask,
              start_elements[0], ceilings[0], W)
        _LOADED.add(key)


def _kernel(flags):
    """The batch kernel of ``flags``, built once even when threads ask for it at the same time."""
    with _BUILDING:
        return batch_kernel(flags)


def check_variant(reported, flags):
    """Raise :class:`KernelMismatch` unless every reported number is the one of ``flags``."""
    expected = report(flags)
    bad = np.flatnonzero(np.asarray(reported) != float(expected))
    if bad.size:
        got = np.asarray(reported)[bad[0]]
        said = describe(int(got)) if np.isfinite(got) and got >= 0 else f"nothing readable ({got})"
        raise KernelMismatch(
            f"the compiled event loop that ran is not the one asked for: asked for {describe(expected)}, "
            f"the code that ran reports {said}. A wrong entry in numba's compile cache "
            f"({_cache_location()}) is the likely cause: delete it and run again, and report the case")


def _cache_location():
    import numba

    return numba.config.CACHE_DIR or "the __pycache__ folder of noslipsim/core"

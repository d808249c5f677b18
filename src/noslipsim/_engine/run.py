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
from ..core.variant import describe, report


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
    flags : tuple, optional
        The kernel variant (:func:`noslipsim.core.loop.orbit_kernel`); default
        ``table.variant(mode)``, the fastest exact one for the table.  Tests and
        benchmarks pass others (``core.variant.GENERAL``: every flag at run time).
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
    flags = table.variant(mode) if flags is None else tuple(flags)
    final = np.zeros((n, N_FINAL))
    _kernel(flags)(*table.arrays(), table.law, table.c, table.s, table.ax, table.ay, table.thermostat, starts,
                   start_elements, max_collisions, max_time, levels, table.scale, mode, rec, mask, final, ceilings)
    check_variant(final[:, F_VARIANT], flags)
    return final


_BUILDING = threading.Lock()


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

"""Many orbits at once: validation, chunks scheduled by dask, one compiled call per chunk.

Dask lives here and only here.  Locally the chunks run on dask's threaded
scheduler (the kernels release the GIL); pass a ``dask.distributed`` Client or
scheduler address to run them on a cluster.  Orbits are independent and
deterministic, so the dataset is identical whatever the chunk size, the
scheduler or the number of workers.
"""
from __future__ import annotations

import json
import math
import os
import sys
from collections.abc import Sequence
from typing import Any

import numpy as np
import xarray as xr
from numpy.typing import ArrayLike

from ._validate import finite_float
from ._version import __version__
from .core import layout
from .core.batch import F_CELL1, F_CELL2, F_CORNER, F_N, F_NREC, F_STOP, F_T, F_VX, F_VY, F_W, F_X, F_Y, N_FINAL
from ._engine.canonical import canonical_form
from ._engine.lattice import cell_of, cell_origin
from ._engine.run import run_orbits
from ._engine.table import kernel_table
from ._metadata import annotate
from .scenes import Scene
from .simulate import START_MARGIN, check_limits

RECORDS = ("final", "count", "portrait", "log")
STOP_FLAGS = {"flag_values": list(range(len(layout.STOP_REASONS))),
              "flag_meanings": " ".join(layout.STOP_REASONS)}


# ---------------------------------------------------------------------------- validation
def _array(value, shape_tail, n, field):
    try:
        arr = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{field}: expected numbers") from None
    if arr.ndim != 1 + len(shape_tail) or arr.shape[1:] != shape_tail or (n is not None and len(arr) != n):
        want = f"({n if n is not None else 'N'}{''.join(', ' + str(k) for k in shape_tail)})"
        raise ValueError(f"{field}: expected shape {want}, got {arr.shape}")
    bad = ~np.isfinite(arr).reshape(len(arr), -1).all(axis=1)
    if bad.any():
        raise ValueError(f"{field}: non-finite value for orbit {int(np.argmax(bad))}")
    return np.ascontiguousarray(arr)


def _indices(value, field):
    """Integer indices (an int64 array), or ValueError naming ``field``: no silent truncation of 0.5 to 0."""
    try:
        arr = np.asarray(value)
        ok = arr.dtype.kind in "iu" or (arr.dtype.kind == "f" and bool(np.all(np.isfinite(arr)))
                                        and bool(np.all(arr == np.round(arr))))
    except (TypeError, ValueError):
        ok = False
    if not ok:
        raise ValueError(f"{field}: expected integer element indices (-1 for an interior start), got {value!r}")
    return arr.astype(np.int64)


def check_starts(scene: Scene, positions, velocities, spins, start_elements=None):
    """Validate N initial states; returns ``(q, v, w, on)`` arrays.

    Interior starts (``on[i] = -1``) must lie strictly inside the table;
    boundary starts (``on[i] = k``) must lie on element ``k`` (of cell 0's
    copies in a periodic scene) with a velocity entering the table.
    """
    q = _array(positions, (2,), None, "positions")
    n = len(q)
    v = _array(velocities, (2,), n, "velocities")
    w = np.zeros(n) if spins is None else _array(spins, (), n, "spins")
    on = np.full(n, -1, dtype=np.int64) if start_elements is None else _indices(start_elements, "start_elements")
    if on.shape != (n,):
        raise ValueError(f"start_elements: expected shape ({n},), got {on.shape}")
    if ((on < -1) | (on >= len(scene.elements))).any():
        raise ValueError(f"start_elements: indices must be -1 or in [0, {len(scene.elements)})")
    if scene.force == (0.0, 0.0):
        still = (v == 0.0).all(axis=1)
        if still.any():
            raise ValueError(f"velocities: orbit {int(np.argmax(still))} has zero speed with zero force")
    if scene.thermostat is not None:
        still = (v == 0.0).all(axis=1)
        if still.any():
            raise ValueError(f"velocities: orbit {int(np.argmax(still))} has zero speed; the isokinetic "
                             "thermostat keeps the speed, so it needs a nonzero one")
    inside = on < 0
    if inside.any():
        rel = q[inside] - (cell_origin(cell_of(q[inside], scene.lattice, "positions"), scene.lattice)
                           if scene.lattice is not None else 0.0)
        margin = START_MARGIN * np.maximum(scene.scale, np.abs(rel).max(axis=1))
        depth = scene.depth(q[inside])
        bad = ~(depth > margin)
        if bad.any():
            i = int(np.flatnonzero(inside)[np.argmax(bad)])
            raise ValueError(f"positions: orbit {i} starts at {q[i].tolist()}, not strictly inside the table")
    tol = 1e-9 * max(scene.scale, 1.0)
    for k in np.unique(on[~inside]):
        idx = np.flatnonzero(on == k)
        e = scene.elements[k]
        dist = np.abs(e.side_distance(q[idx]))
        off = np.maximum(dist, e.distance(q[idx]) if e.finite else dist)
        if (off > tol).any():
            raise ValueError(f"positions: orbit {int(idx[np.argmax(off > tol)])} is not on start element {k}")
        speed = np.maximum(np.hypot(v[idx, 0], v[idx, 1]), 1e-300)
        ahead = q[idx] + 1e-6 * max(scene.scale, 1.0) * v[idx] / speed[:, None]
        enters = e.side_distance(ahead) > 0
        if not enters.all():
            raise ValueError(f"velocities: orbit {int(idx[np.argmin(enters)])} does not enter the table "
                             f"from start element {k}")
    return q, v, w, on


# ---------------------------------------------------------------------------- one chunk
def _run_chunk(table, starts, on, levels, max_collisions, max_time, mode, n_rec, n_cols, mask):
    """One compiled call over a block of orbits: their records and summaries."""
    rec = np.full((len(starts), n_rec, n_cols), np.nan)
    final = run_orbits(table, starts, max_collisions=max_collisions, max_time=max_time, levels=levels,
                       start_elements=on, mode=mode, rec=rec, mask=mask)
    return rec, final


def _run_threads(table, starts, on, levels, tail, threads):
    """The orbits in blocks run by a pool of threads (the kernels release the GIL); no dask.

    Four blocks per thread, so that a thread whose orbits end early takes another block."""
    from concurrent.futures import ThreadPoolExecutor

    n = len(starts)
    threads = max(1, min(threads, n))
    size = math.ceil(n / (4 * threads)) if n else 1
    blocks = [slice(i, i + size) for i in range(0, n, size)] or [slice(0, 0)]
    with ThreadPoolExecutor(threads) as pool:
        parts = list(pool.map(lambda b: _run_chunk(table, starts[b], on[b], levels[b], *tail), blocks))
    return np.concatenate([p[0] for p in parts]), np.concatenate([p[1] for p in parts])


def _compute(tasks, scheduler, progress, num_workers=None):
    """Compute dask tasks on the chosen scheduler; a Client made here from an address is closed here."""
    import dask

    show = sys.stderr.isatty() if progress is None else bool(progress)
    if scheduler is None or scheduler in ("threads", "sync", "synchronous"):
        # num_workers sizes the local thread pool (None: one thread per core)
        kw = {"num_workers": num_workers} if num_workers is not None and scheduler in (None, "threads") else {}
        if show:
            from dask.diagnostics import ProgressBar
            with ProgressBar(out=sys.stderr):
                return dask.compute(*tasks, scheduler=scheduler or "threads", **kw)
        return dask.compute(*tasks, scheduler=scheduler or "threads", **kw)
    from distributed import Client, progress as dprogress

    if isinstance(scheduler, str):
        with Client(scheduler, set_as_default=False) as client:
            return _on_client(client, tasks, show, dprogress)
    if isinstance(scheduler, Client):
        return _on_client(scheduler, tasks, show, dprogress)
    raise ValueError(f"scheduler: expected None, 'threads', 'sync', 'numba', a distributed Client "
                     f"or a scheduler address, got {scheduler!r}")


def _on_client(client, tasks, show, dprogress):
    futures = client.compute(list(tasks))
    if show:
        dprogress(futures)
    return client.gather(futures)


# ---------------------------------------------------------------------------- public API
def simulate_many(scene: Scene, positions: ArrayLike, velocities: ArrayLike, spins: ArrayLike | None = None, *,
                  max_collisions: int = 1000, max_time: float = math.inf, stop_below: float | None = None,
                  record: str = "final", elements: Sequence[int] | None = None,
                  start_elements: ArrayLike | None = None, chunk_size: int | None = None,
                  scheduler: Any = None, progress: bool | None = None,
                  num_workers: int | None = None) -> xr.Dataset:
    """Simulate many orbits of one scene.

    Parameters
    ----------
    scene : Scene
        Table, law, gamma and force (plain or periodic).
    positions, velocities : array_like (N, 2)
        Starts ``(x, y)`` and velocities ``(v_x, v_y)``.
    spins : array_like (N,), optional
        Scaled spins ``w = gamma R omega`` (CCW positive); zeros by default.
    max_collisions : int
        Collision budget per orbit.
    max_time : float
        Time limit per orbit (the final state is advanced to it).
    stop_below : float, optional
        End an orbit when it crosses this height downwards (exact crossing).
    record : {'final', 'count', 'portrait', 'log'}
        ``final``: final state, ``n_collisions``, ``stop_reason``, corner count;
        ``count``: ``n_collisions`` and ``stop_reason`` only; ``portrait``: on
        the chosen ``elements``, ``element``, ``s`` and the post-collision unit
        vector ``(w, v_t, v_n)`` per collision (dim ``point``); ``log``: the
        full collision log (dim ``collision``).  Records are NaN-padded past
        each orbit's end.
    elements : sequence of int, optional
        Elements recorded by ``portrait`` (default: all).
    start_elements : array_like (N,) of int, optional
        ``-1`` for interior starts, or the element each orbit starts on
        (boundary initial conditions, see :mod:`noslipsim.initial`).
    chunk_size : int, optional
        Orbits per dask task (default: about four tasks per core).
    scheduler : None, str or distributed.Client
        ``None``/'threads' (local threads), 'sync', 'numba' (one compiled call
        per thread, ``num_workers`` threads, no dask), a ``dask.distributed``
        Client or its address.
    progress : bool, optional
        Show a progress bar (default: only when stderr is a terminal).
    num_workers : int, optional
        Threads of the local threaded scheduler and of ``'numba'`` (default:
        one per core); a workflow job passes the threads it was given.  Ignored
        by the other schedulers.  The results do not depend on it.

    Returns
    -------
    xarray.Dataset
        Dim ``orbit`` (and ``point`` or ``collision``); every variable has
        ``long_name`` and ``units``.  ``stop_reason`` is an integer flag with CF
        ``flag_values``/``flag_meanings``.
    """
    if not isinstance(scene, Scene):
        raise ValueError(f"scene: expected a noslipsim.Scene, got {type(scene).__name__}")
    if record not in RECORDS:
        raise ValueError(f"record: must be one of {RECORDS}, got {record!r}")
    if chunk_size is not None and (isinstance(chunk_size, bool) or not isinstance(chunk_size, (int, np.integer))
                                   or chunk_size < 1):
        raise ValueError(f"chunk_size: must be a positive integer, got {chunk_size!r}")
    if num_workers is not None and (isinstance(num_workers, bool) or not isinstance(num_workers, (int, np.integer))
                                    or num_workers < 1):
        raise ValueError(f"num_workers: must be a positive integer, got {num_workers!r}")
    q, v, w, on = check_starts(scene, positions, velocities, spins, start_elements)
    n = len(q)
    max_collisions, max_time = check_limits(max_collisions, max_time)
    level = -math.inf if stop_below is None else finite_float(stop_below, "stop_below")
    if stop_below is not None and (q[:, 1] <= level).any():
        raise ValueError(f"stop_below: orbit {int(np.argmax(q[:, 1] <= level))} starts at or below {level}")
    mask = np.zeros(len(scene.elements), dtype=np.bool_)
    if record == "portrait":
        chosen = range(len(scene.elements)) if elements is None else list(elements)
        for e in chosen:
            if not 0 <= int(e) < len(scene.elements):
                raise ValueError(f"elements: no element {e} in a scene of {len(scene.elements)}")
            mask[int(e)] = True
    mode, n_rec, n_cols = {
        "final": (layout.RECORD_NONE, 0, 0), "count": (layout.RECORD_NONE, 0, 0),
        "portrait": (layout.RECORD_PORTRAIT, max_collisions, layout.N_PORTRAIT),
        "log": (layout.RECORD_LOG, max_collisions, layout.N_LOG),
    }[record]

    # the kernels run the canonical form; starts relative to their (canonical) cells
    form = canonical_form(scene)
    cells, origins, rel = form.kernel_starts(q)
    starts = np.ascontiguousarray(np.c_[rel, v, w])
    levels = np.full(n, form.user_level(level)) - origins[:, 1]
    table = kernel_table(form.scene)
    tail = (max_collisions, max_time, mode, n_rec, n_cols, mask)

    if scheduler == "numba" or n == 0:
        rec, final = _run_threads(table, starts, on, levels, tail, num_workers or os.cpu_count() or 1)
    else:
        import dask

        size = max(1, math.ceil(n / (4 * (os.cpu_count() or 1)))) if chunk_size is None else chunk_size
        run = dask.delayed(_run_chunk, pure=True)
        tasks = [run(table, starts[i:i + size], on[i:i + size], levels[i:i + size], *tail)
                 for i in range(0, n, size)]
        parts = _compute(tasks, scheduler, progress, num_workers)
        rec = np.concatenate([p[0] for p in parts]) if parts else np.zeros((0, n_rec, n_cols))
        final = np.concatenate([p[1] for p in parts]) if parts else np.zeros((0, N_FINAL))
    _to_user(form, record, rec, final, origins, cells, level)
    return _ensemble_dataset(scene, record, rec, final, dict(
        max_collisions=max_collisions, max_time=max_time, stop_below=stop_below))


def _to_user(form, record, rec, final, origins, cells, level):
    """Kernel outputs (relative to each orbit's canonical start cell) to the user's coordinates, in place."""
    x, y = final[:, F_X] + origins[:, 0], final[:, F_Y] + origins[:, 1]
    if form.scene.lattice is not None:
        final[:, F_CELL1], final[:, F_CELL2] = form.user_cells(final[:, F_CELL1] + cells[:, 0],
                                                               final[:, F_CELL2] + cells[:, 1], x, y)
    final[:, F_X], final[:, F_Y] = form.user_positions(x, y)
    final[final[:, F_STOP] == layout.STOP_LEVEL, F_Y] = level  # the exact crossing of the user's level
    if record == "log":
        x = rec[:, :, layout.LOG_X] + origins[:, :1]
        y = rec[:, :, layout.LOG_Y] + origins[:, 1:]
        if form.scene.lattice is not None:
            rec[:, :, layout.LOG_CELL_A1], rec[:, :, layout.LOG_CELL_A2] = form.user_cells(
                rec[:, :, layout.LOG_CELL_A1] + cells[:, :1], rec[:, :, layout.LOG_CELL_A2] + cells[:, 1:], x, y)
        rec[:, :, layout.LOG_X], rec[:, :, layout.LOG_Y] = form.user_positions(x, y)


def _ensemble_dataset(scene, record, rec, final, limits):
    o = ("orbit",)
    n_coll = final[:, F_N].astype(np.int64)
    data = {
        "n_collisions": (o, n_coll),
        "stop_reason": (o, final[:, F_STOP].astype(np.int8), dict(STOP_FLAGS)),
    }
    if record in ("final", "log"):
        data.update({
            "t_final": (o, final[:, F_T]),
            "x_final": (o, final[:, F_X]),
            "y_final": (o, final[:, F_Y]),
            "vx_final": (o, final[:, F_VX]),
            "vy_final": (o, final[:, F_VY]),
            "spin_final": (o, final[:, F_W]),
            "n_corner": (o, final[:, F_CORNER].astype(np.int64)),
        })
        if scene.lattice is not None:
            data["cell_a1_final"] = (o, final[:, F_CELL1].astype(np.int64))
            data["cell_a2_final"] = (o, final[:, F_CELL2].astype(np.int64))
    if record == "portrait":
        p = ("orbit", "point")
        data.update({
            "element": (p, rec[:, :, layout.POR_ELEMENT]),
            "s": (p, rec[:, :, layout.POR_S]),
            "w_unit": (p, rec[:, :, layout.POR_W]),
            "vt_unit": (p, rec[:, :, layout.POR_VT]),
            "vn_unit": (p, rec[:, :, layout.POR_VN]),
            "n_points": (o, final[:, F_NREC].astype(np.int64)),
        })
    if record == "log":
        cdim = ("orbit", "collision")
        cols = {"t": layout.LOG_T, "x": layout.LOG_X, "y": layout.LOG_Y, "vx": layout.LOG_VX,
                "vy": layout.LOG_VY, "spin": layout.LOG_W, "vx_in": layout.LOG_VX_IN,
                "vy_in": layout.LOG_VY_IN, "spin_in": layout.LOG_W_IN, "element": layout.LOG_ELEMENT,
                "s": layout.LOG_S, "corner": layout.LOG_CORNER}
        for name, col in cols.items():
            data[name] = (cdim, rec[:, :, col])
        if scene.lattice is not None:
            data["cell_a1"] = (cdim, rec[:, :, layout.LOG_CELL_A1])
            data["cell_a2"] = (cdim, rec[:, :, layout.LOG_CELL_A2])
    ds = xr.Dataset(data, coords={"orbit": np.arange(len(final))})
    ds.attrs.update(
        title=f"noslipsim ensemble ({record})",
        source=f"noslipsim {__version__}",
        record=record,
        law=scene.law,
        gamma=scene.gamma,
        force=list(scene.force),
        scene=scene.to_json(),
        limits=json.dumps({k: (None if v is None else float(v)) for k, v in limits.items()}),
    )
    return annotate(ds)

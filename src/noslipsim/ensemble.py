"""Many orbits at once: validation, chunks run as they complete, one compiled call per chunk.

Locally the chunks run on a thread pool (the kernels release the GIL); pass a
``dask.distributed`` Client or scheduler address to run them on a cluster
(:mod:`noslipsim._scheduler`, where dask lives).  With ``out`` the chunks go to
disk as they complete (:mod:`noslipsim._chunkstore`) and a killed run resumes.
Orbits are independent and deterministic, so the dataset is identical whatever
the chunk size, the scheduler, the number of workers, and whether it went
through disk.
"""
from __future__ import annotations

import json
import math
import os
from collections.abc import Sequence
from typing import Any

import numpy as np
import xarray as xr
from numpy.typing import ArrayLike

from ._chunkstore import chunk_path, digest, is_done, open_chunks, open_folder, write_chunk
from ._engine.canonical import canonical_form
from ._engine.lattice import cell_of, cell_origin
from ._engine.run import run_orbits
from ._engine.table import kernel_table
from ._metadata import annotate
from ._scheduler import check_scheduler, run_tasks
from ._version import __version__
from .core import layout
from .core.batch import F_CELL1, F_CELL2, F_CORNER, F_N, F_NREC, F_STOP, F_T, F_VX, F_VY, F_W, F_X, F_Y
from .scenes import Scene
from .simulate import START_MARGIN, check_level, check_limits, check_magnitudes

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
    bad = ~np.isfinite(arr).all(axis=tuple(range(1, arr.ndim)))
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
    if n == 0:
        raise ValueError("positions: no starts given; an ensemble needs at least one orbit")
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
    # positions relative to their cells' origins (plain scenes: as given)
    rel = q - (cell_origin(cell_of(q, scene.lattice, "positions"), scene.lattice)
               if scene.lattice is not None else 0.0)
    check_magnitudes(scene, rel, v, w, ("positions", "velocities", "spins"), lambda i: f"orbit {i}: ")
    inside = on < 0
    if inside.any():
        margin = START_MARGIN * np.maximum(scene.scale, np.abs(rel[inside]).max(axis=1))
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
        off = np.maximum(dist, e.distance(q[idx]))
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
def _run_chunk(table, starts, on, levels, ceilings, max_collisions, max_time, mode, n_rec, n_cols, mask):
    """One compiled call over a block of orbits: their records and summaries."""
    rec = np.full((len(starts), n_rec, n_cols), np.nan)
    final = run_orbits(table, starts, max_collisions=max_collisions, max_time=max_time, levels=levels,
                       start_elements=on, mode=mode, rec=rec, mask=mask, ceilings=ceilings)
    return rec, final


def _run_threads(table, starts, on, levels, ceilings, tail, threads):
    """The orbits in blocks run by a pool of threads (the kernels release the GIL); no dask.

    Four blocks per thread, so that a thread whose orbits end early takes another block."""
    from concurrent.futures import ThreadPoolExecutor

    n = len(starts)
    threads = max(1, min(threads, n))
    size = math.ceil(n / (4 * threads)) if n else 1
    blocks = [slice(i, i + size) for i in range(0, n, size)] or [slice(0, 0)]
    with ThreadPoolExecutor(threads) as pool:
        parts = list(pool.map(lambda b: _run_chunk(table, starts[b], on[b], levels[b], ceilings[b], *tail),
                              blocks))
    return np.concatenate([p[0] for p in parts]), np.concatenate([p[1] for p in parts])


def _chunk_to_file(run, starts, on, levels, ceilings, cells, origins, folder, start, stop, inputs):
    """One chunk computed, turned into its dataset (orbits ``start..stop-1``) and written to ``folder``.

    Runs on a worker: ``folder`` must be reachable there (a shared file system on a cluster)."""
    rec, final = _run_chunk(run["table"], starts, on, levels, ceilings, *run["tail"])
    _to_user(run["form"], run["record"], rec, final, origins, cells, run["level"])
    ds = _ensemble_dataset(run["scene"], run["record"], rec, final, run["limits"], first=start)
    write_chunk(ds, folder, start, stop, inputs)
    return stop - start


# ---------------------------------------------------------------------------- public API
#: Default chunk of the on-disk path (``out=``): at most this many orbits ...
CHUNK_ORBITS = 10_000
#: ... and at most this many bytes of records (portraits, logs), so memory per chunk is bounded.
CHUNK_BYTES = 64 * 2**20


def simulate_many(scene: Scene, positions: ArrayLike, velocities: ArrayLike, spins: ArrayLike | None = None, *,
                  max_collisions: int = 1000, max_time: float = math.inf, stop_below: float | None = None,
                  record: str = "final", elements: Sequence[int] | None = None,
                  start_elements: ArrayLike | None = None, chunk_size: int | None = None,
                  scheduler: Any = None, progress: bool | None = None,
                  num_workers: int | None = None, out: str | os.PathLike | None = None) -> xr.Dataset:
    """Simulate many orbits of one scene.

    Parameters
    ----------
    scene : Scene
        Table, law, gamma and force (plain or periodic).
    positions, velocities : array_like (N, 2)
        Starts ``(x, y)`` and velocities ``(v_x, v_y)``.  With ``out``, any
        array that slices into blocks (numpy, memmap, dask, zarr; see
        :class:`noslipsim.initial.UnitVelocities`): only the blocks in flight
        are in memory.
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
        (boundary initial conditions, see :mod:`noslipsim.initial`); on a
        lattice, a point of the element's copy in cell 0 (the element as
        written), wherever the disk reaches.
    chunk_size : int, optional
        Orbits per task (default: about four tasks per core; with ``out``,
        at most :data:`CHUNK_ORBITS` orbits and :data:`CHUNK_BYTES` of records,
        whatever the machine, so that a resumed run finds the same chunks).
    scheduler : None, str or distributed.Client
        ``None``/'threads' (local threads), 'sync', 'numba' (one compiled call
        per thread, ``num_workers`` threads, no dask), a ``dask.distributed``
        Client or its address.
    progress : bool, optional
        Progress lines on stderr: chunks done and an ETA (default: only when
        stderr is a terminal).
    num_workers : int, optional
        Threads of the local threaded scheduler and of ``'numba'`` (default:
        one per core); a workflow job passes the threads it was given.  Ignored
        by the other schedulers.  The results do not depend on it.
    out : str or path-like, optional
        A folder: each chunk is written there as a netCDF file as soon as it
        completes (by the worker that computed it: on a cluster, a folder all
        workers reach), so memory stays bounded whatever N.  Run again with the
        same arguments, it computes only the chunks missing (a run killed at
        any point resumes; the dataset is the same to the bit).  A folder that
        holds another run's chunks is refused.  The returned dataset reads the
        chunk files lazily (dask arrays; ``.load()`` reads them all).

    Returns
    -------
    xarray.Dataset
        Dim ``orbit`` (and ``point`` or ``collision``); every variable has
        ``long_name`` and ``units``.  ``stop_reason`` is an integer flag with CF
        ``flag_values``/``flag_meanings``.  The same dataset whatever the
        chunking, the scheduler, the workers, and whether ``out`` is given.
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
    check_scheduler(scheduler)
    max_collisions, max_time = check_limits(max_collisions, max_time)
    level = check_level(stop_below)
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
    run = dict(table=kernel_table(form.scene), tail=(max_collisions, max_time, mode, n_rec, n_cols, mask),
               form=form, scene=scene, record=record, level=level,
               limits=dict(max_collisions=max_collisions, max_time=max_time, stop_below=stop_below))
    if out is not None:
        return _simulate_to_folder(run, positions, velocities, spins, start_elements, out, chunk_size,
                                   dict(scheduler=scheduler, progress=progress, num_workers=num_workers))

    q, v, w, on = check_starts(scene, positions, velocities, spins, start_elements)
    _check_level(q, level, stop_below)
    n = len(q)
    cells, origins, starts, levels, ceilings = _kernel_inputs(form, q, v, w, level, on)
    table, tail = run["table"], run["tail"]
    if scheduler == "numba" or n == 0:
        rec, final = _run_threads(table, starts, on, levels, ceilings, tail, num_workers or os.cpu_count() or 1)
    else:
        size = max(1, math.ceil(n / (4 * (os.cpu_count() or 1)))) if chunk_size is None else chunk_size
        bounds = [(i, min(i + size, n)) for i in range(0, n, size)]
        parts = {}
        run_tasks(_run_chunk, (((i, j), (table, starts[i:j], on[i:j], levels[i:j], ceilings[i:j], *tail))
                                for i, j in bounds),
                  parts.__setitem__, scheduler=scheduler, num_workers=num_workers, progress=progress,
                  total=len(bounds))
        rec = np.concatenate([parts[b][0] for b in bounds])
        final = np.concatenate([parts[b][1] for b in bounds])
    _to_user(form, record, rec, final, origins, cells, level)
    return _ensemble_dataset(scene, record, rec, final, run["limits"])


def _check_level(q, level, stop_below, first=0):
    if stop_below is not None and (q[:, 1] <= level).any():
        raise ValueError(f"stop_below: orbit {first + int(np.argmax(q[:, 1] <= level))} starts at or below {level}")


def _kernel_inputs(form, q, v, w, level, on):
    """Cells, origins, kernel starts ``(x, y, vx, vy, w)`` relative to the canonical cells, levels and ceilings.

    ``on``: the start elements (a boundary start's cell is its element's).  ``ceilings``: a bounded
    lattice's top (``Scene.top``) relative to each start cell (``inf`` for none)."""
    cells, origins, rel = form.kernel_starts(q, on)
    starts = np.ascontiguousarray(np.c_[rel, v, w])
    levels = np.full(len(q), form.user_level(level)) - origins[:, 1]
    top = form.scene.top
    ceilings = np.full(len(q), math.inf) if top is None else top - origins[:, 1]
    return cells, origins, starts, levels, ceilings


def _blocks(value, n, field, tail=()):
    """``value`` as an array that slices into blocks, with ``n`` rows (a list becomes a numpy array)."""
    if value is None:
        return None
    if not (hasattr(value, "shape") and hasattr(value, "__getitem__")):
        value = np.asarray(value)
    if tuple(value.shape) != (n, *tail):
        want = f"({n}{''.join(', ' + str(k) for k in tail)})"
        raise ValueError(f"{field}: expected shape {want}, got {tuple(value.shape)}")
    return value


def _simulate_to_folder(run, positions, velocities, spins, start_elements, out, chunk_size, how):
    """:func:`simulate_many` with ``out``: chunks validated, computed and written one by one, resumable."""
    if not (hasattr(positions, "shape") and hasattr(positions, "__getitem__")):
        positions = np.asarray(positions, dtype=float)
    if len(positions.shape) != 2 or positions.shape[1] != 2:
        raise ValueError(f"positions: expected shape (N, 2), got {tuple(positions.shape)}")
    n = int(positions.shape[0])
    velocities = _blocks(velocities, n, "velocities", (2,))
    spins = _blocks(spins, n, "spins")
    start_elements = _blocks(start_elements, n, "start_elements")
    if n == 0:
        raise ValueError("positions: no starts given; an ensemble needs at least one orbit")
    tail = run["tail"]
    row_bytes = 8 * max(1, tail[3] * tail[4])
    size = chunk_size or max(1, min(CHUNK_ORBITS, CHUNK_BYTES // row_bytes))
    bounds = [(i, min(i + size, n)) for i in range(0, n, size)]
    folder = os.path.abspath(os.fspath(out))
    open_folder(folder, {
        "source": f"noslipsim {__version__}", "scene": run["scene"].to_json(), "record": run["record"],
        "limits": {k: (None if x is None else float(x)) for k, x in run["limits"].items()},
        "elements": np.flatnonzero(tail[5]).tolist(), "orbits": n, "chunk_size": size})
    present = sum(os.path.exists(chunk_path(folder, i, j)) for i, j in bounds)

    def jobs():
        for i, j in bounds:
            try:
                q, v, w, on = check_starts(run["scene"], positions[i:j], velocities[i:j],
                                           None if spins is None else spins[i:j],
                                           None if start_elements is None else start_elements[i:j])
            except ValueError as err:
                raise ValueError(f"orbits {i}-{j - 1}: {err}") from None
            _check_level(q, run["level"], run["limits"]["stop_below"], first=i)
            cells, origins, starts, levels, ceilings = _kernel_inputs(run["form"], q, v, w, run["level"], on)
            inputs = digest(starts, on, levels) if run["form"].scene.top is None else digest(starts, on, levels,
                                                                                            ceilings)
            if not is_done(folder, i, j, inputs):
                yield (i, j), (run, starts, on, levels, ceilings, cells, origins, folder, i, j, inputs)

    run_tasks(_chunk_to_file, jobs(), lambda key, result: None, total=len(bounds), done=present, **how)
    return open_chunks(folder, bounds, "orbit")


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


def _ensemble_dataset(scene, record, rec, final, limits, first=0):
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
    ds = xr.Dataset(data, coords={"orbit": np.arange(first, first + len(final))})
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

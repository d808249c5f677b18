"""A folder of netCDF chunk files that together make one dataset, filled as chunks complete and resumable.

Layout of a folder::

    run.json                               what the run is (scene, limits, record, sizes): a resume must match it
    chunk-000000000000-000000010000.nc     orbits [0, 10000): written atomically (temporary name, then rename)
    ...

Each chunk file carries ``chunk_inputs`` (a digest of its orbits' initial states) so that a
resumed run recomputes exactly the chunks that are missing and refuses a folder whose chunks
came from other starts.  A chunk file is complete or absent: a run killed at any point (even
while a file is written) leaves at most a ``.tmp-*`` file, removed at the next start.
"""
from __future__ import annotations

import glob
import hashlib
import json
import os
import threading
import uuid

import numpy as np
import xarray as xr

from ._netcdf import write_netcdf_atomically

#: Name of the run description in a chunk folder.
MANIFEST = "run.json"
#: Global attributes that belong to one chunk file, not to the dataset they make together.
CHUNK_ATTRS = ("chunk_inputs", "chunk_orbits")
#: netCDF/HDF5 is not thread-safe: chunk files written by the threads of one process take turns.
_WRITE_LOCK = threading.Lock()


def digest(*arrays):
    """sha256 of arrays' dtypes, shapes and bytes (the identity of a chunk's inputs)."""
    h = hashlib.sha256()
    for a in arrays:
        a = np.ascontiguousarray(a)
        h.update(f"{a.dtype.str}{a.shape}".encode())
        h.update(a.tobytes())
    return h.hexdigest()


def chunk_path(folder, start, stop):
    return os.path.join(os.fspath(folder), f"chunk-{start:012d}-{stop:012d}.nc")


def open_folder(folder, run):
    """Create ``folder`` for ``run`` (a JSON-able dict), or check that the one there describes the same run.

    Removes temporary files left by a killed run.  Raises ValueError naming the first difference."""
    folder = os.fspath(folder)
    os.makedirs(folder, exist_ok=True)
    path = os.path.join(folder, MANIFEST)
    text = json.dumps(run, sort_keys=True, indent=1)
    if os.path.exists(path):
        with open(path, encoding="utf-8") as f:
            old = json.load(f)
        new = json.loads(text)
        if old != new:
            key = next((k for k in sorted(set(old) | set(new)) if old.get(k) != new.get(k)), "?")
            raise ValueError(f"out: {folder} holds chunks of another run ({key!r} differs); "
                             f"use another folder, or empty this one to start again")
    else:
        _atomic_text(path, text)
    for tmp in glob.glob(os.path.join(folder, ".tmp-*")):
        os.remove(tmp)


def is_done(folder, start, stop, inputs):
    """Whether the chunk ``[start, stop)`` is on disk; ValueError if it is, from other inputs."""
    path = chunk_path(folder, start, stop)
    if not os.path.exists(path):
        return False
    with _WRITE_LOCK, xr.open_dataset(path, engine="netcdf4") as ds:
        found = ds.attrs.get("chunk_inputs")
    if found != inputs:
        raise ValueError(f"out: {path} was computed from other initial states; use another folder, "
                         f"or empty this one to start again")
    return True


def write_chunk(ds, folder, start, stop, inputs):
    """Write the dataset of orbits ``[start, stop)`` atomically; returns its path."""
    path = chunk_path(folder, start, stop)
    ds = ds.copy()
    ds.attrs.update(chunk_inputs=inputs, chunk_orbits=[start, stop])
    write_netcdf_atomically(ds, path, _WRITE_LOCK)
    return path


def open_chunks(folder, bounds, dim):
    """The chunks ``[(start, stop), ...]`` of ``folder`` as one lazy dataset along ``dim`` (dask arrays).

    No file stays open: each chunk file is opened, read whole and closed by the task that needs
    it (an open netCDF4/HDF5 file costs about a megabyte, and a dataset over thousands of chunk
    files kept open would grow with them).  So reading the dataset costs memory for the chunks
    being read, plus the index coordinate ``dim`` (8 bytes per entry), whatever the number of
    chunks; it also loads on a distributed cluster whose workers see the folder."""
    import dask
    import dask.array as da

    paths = [chunk_path(folder, a, b) for a, b in bounds]
    with xr.open_dataset(paths[0], engine="netcdf4") as first:
        meta = {name: (var.dims, var.dtype, dict(var.attrs), var.shape) for name, var in first.variables.items()}
        attrs = {k: v for k, v in first.attrs.items() if k not in CHUNK_ATTRS}
    reads = [dask.delayed(_read_chunk, pure=True)(path) for path in paths]
    data, coords = {}, {dim: np.arange(bounds[0][0], bounds[-1][1])}
    for name, (dims, dtype, var_attrs, shape) in meta.items():
        if name == dim:
            continue
        axis = dims.index(dim)
        parts = [da.from_delayed(read[name], shape=(*shape[:axis], b - a, *shape[axis + 1:]), dtype=dtype)
                 for read, (a, b) in zip(reads, bounds, strict=True)]
        (coords if name in first.coords else data)[name] = xr.Variable(dims, da.concatenate(parts, axis=axis),
                                                                       var_attrs)
    coords[dim] = xr.Variable(dim, coords[dim], meta[dim][2])
    return xr.Dataset(data, coords=coords, attrs=attrs)


def _read_chunk(path):
    """Every variable of one chunk file as numpy arrays; the file is closed on return.

    netCDF/HDF5 is not thread-safe and dask reads chunks from several threads: the read holds
    xarray's own HDF5 lock (the one its netCDF writes take), so it never overlaps another HDF5
    call of this process, and goes through netCDF4 directly (xarray would take that lock again).
    The chunk files hold plain numbers (floats with NaN as fill value, integers), which need no
    decoding."""
    import netCDF4
    from xarray.backends.locks import HDF5_LOCK

    with HDF5_LOCK, netCDF4.Dataset(path) as nc:
        nc.set_auto_mask(False)
        return {name: var[...] for name, var in nc.variables.items()}


def _atomic_text(path, text):
    tmp = os.path.join(os.path.dirname(path), f".tmp-{uuid.uuid4().hex}")
    with open(tmp, "w", encoding="utf-8") as f:
        f.write(text)
    os.replace(tmp, path)

"""Self-describing netCDF datasets (docs/datasets.md), written atomically."""
from __future__ import annotations

import datetime as _dt
import json
import os
import sys
import tempfile

import numpy as np
import xarray as xr

from ._version import __version__
from .metadata import annotate

REFERENCES = ("J. Ahmed, T. Chumley, S. Cook, C. Cox, H. Grant, N. Petela, B. Rothrock, R. Xhafaj: "
              "Dynamics of the no-slip Galton board.")


def _attr(value):
    """A netCDF-safe attribute: no dicts, None or bools (configs become JSON)."""
    if isinstance(value, (bool, np.bool_)):
        return int(value)
    if value is None:
        return ""
    if isinstance(value, dict):
        return json.dumps(value, sort_keys=True, default=float)
    if isinstance(value, (list, tuple)):
        arr = np.asarray(value)
        return arr if arr.dtype.kind in "iuf" else json.dumps(list(value), default=str)
    return value


def describe(ds: xr.Dataset, *, title=None, config=None, history=None) -> xr.Dataset:
    """Add the global attributes every noslipsim dataset carries; returns a new dataset."""
    ds = annotate(ds.copy())
    stamp = _dt.datetime.now(_dt.timezone.utc).strftime("%Y-%m-%d %H:%M:%S UTC")
    call = history or " ".join(os.path.basename(a) if i == 0 else a for i, a in enumerate(sys.argv))
    attrs = dict(ds.attrs)
    attrs.update(
        title=title or attrs.get("title", "noslipsim dataset"),
        source=f"noslipsim {__version__}",
        history=(attrs.get("history", "") + "\n" if attrs.get("history") else "")
        + f"[{stamp}] {call} - noslipsim {__version__}",
        references=REFERENCES,
        Conventions="CF-1.8",
    )
    if config is not None:
        attrs["config"] = json.dumps(config, sort_keys=True, default=float)
    ds.attrs = {k: _attr(v) for k, v in attrs.items()}
    for var in ds.variables.values():
        var.attrs = {k: _attr(v) for k, v in var.attrs.items()}
    return ds


def _umask():
    mask = os.umask(0)
    os.umask(mask)
    return mask


#: Permissions of a written dataset: those of a file created with ``open`` under the umask.
_CREATE_MODE = 0o666 & ~_umask()


def write_dataset(ds: xr.Dataset, path, *, title=None, config=None, history=None) -> xr.Dataset:
    """Write ``ds`` to netCDF at ``path`` atomically (temporary file, then rename).

    Returns the dataset as written (with its global attributes).
    """
    ds = describe(ds, title=title, config=config, history=history)
    path = os.fspath(path)
    folder = os.path.dirname(os.path.abspath(path))
    os.makedirs(folder, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=".tmp-", suffix=".nc", dir=folder)
    os.close(fd)
    try:
        ds.to_netcdf(tmp, engine="netcdf4")
        os.chmod(tmp, _CREATE_MODE)  # mkstemp makes the file private; a dataset is as readable as any new file
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.remove(tmp)
        raise
    return ds


def open_dataset(path) -> xr.Dataset:
    """Read a noslipsim dataset fully into memory (the file is closed on return)."""
    with xr.open_dataset(path, engine="netcdf4") as ds:
        return ds.load()

"""Writing a netCDF file so that no reader ever sees half of it (datasets and ensemble chunk files)."""
from __future__ import annotations

import contextlib
import os
import tempfile
from typing import Any

import xarray as xr


def _umask():
    mask = os.umask(0)
    os.umask(mask)
    return mask


#: Permissions of a written dataset: those of a file created with ``open`` under the umask.
_CREATE_MODE = 0o666 & ~_umask()


def write_netcdf_atomically(ds: xr.Dataset, path: str | os.PathLike, lock: Any = None) -> None:
    """Write ``ds`` to a temporary file beside ``path``, then rename it to ``path``: a reader never sees
    half a file and a killed writer leaves none.  ``lock`` (a context manager) is held while netCDF
    writes: the library is not thread-safe."""
    path = os.fspath(path)
    if os.path.isdir(path):
        raise IsADirectoryError(21, "is a folder, not a file name", path)
    folder = os.path.dirname(os.path.abspath(path))
    os.makedirs(folder, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=".tmp-", suffix=".nc", dir=folder)
    os.close(fd)
    try:
        with lock or contextlib.nullcontext():
            ds.to_netcdf(tmp, engine="netcdf4")
        os.chmod(tmp, _CREATE_MODE)  # mkstemp makes the file private; a dataset is as readable as any new file
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.remove(tmp)
        raise


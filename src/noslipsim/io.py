"""Self-describing netCDF datasets (docs/datasets.md), written atomically."""
from __future__ import annotations

import datetime as _dt
import functools
import json
import os
import platform
import subprocess
import sys
from collections.abc import Mapping
from importlib import metadata
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from ._metadata import annotate
from ._netcdf import write_netcdf_atomically
from ._version import __version__

REFERENCES = ("J. Ahmed, T. Chumley, S. Cook, C. Cox, H. Grant, N. Petela, B. Rothrock, R. Xhafaj: "
              "Dynamics of the no-slip Galton board.")


def _json_default(value):
    """JSON for what ``json`` does not know: numpy scalars and arrays as Python numbers and lists."""
    if hasattr(value, "tolist"):
        return value.tolist()
    try:
        return float(value)
    except (TypeError, ValueError):
        return str(value)


def _attr(value):
    """A netCDF-safe attribute: no dicts, None or bools; structure becomes JSON.

    Dicts, nested or ragged sequences and sequences of anything but numbers
    become JSON strings (``json.loads`` gives them back); a flat sequence of
    numbers stays a netCDF numeric array.
    """
    if isinstance(value, (bool, np.bool_)):
        return int(value)
    if value is None:
        return ""
    if isinstance(value, dict):
        return json.dumps(value, sort_keys=True, default=_json_default)
    if isinstance(value, np.ndarray) and value.ndim > 1:
        return json.dumps(value.tolist())
    if isinstance(value, (list, tuple)):
        try:
            arr = np.asarray(value)
        except ValueError:                       # ragged
            arr = None
        if arr is not None and arr.ndim == 1 and arr.dtype.kind in "iuf":
            return arr
        return json.dumps(list(value), default=_json_default)
    return value


#: The packages whose versions decide a dataset's last bits (recorded in every dataset).
SOFTWARE = ("numpy", "numba", "llvmlite", "xarray", "netCDF4")


@functools.cache
def provenance() -> dict[str, str | int]:
    """What made a dataset: the software versions and the git state of noslipsim's source.

    Returns a dict of netCDF-safe attributes: ``software`` (JSON: Python and
    :data:`SOFTWARE` versions, the machine), ``git_commit`` (the commit of the
    checkout noslipsim was imported from, ``""`` outside a git checkout) and
    ``git_dirty`` (1 if that checkout had uncommitted changes, 0 if not, -1
    unknown).  Chaotic ensembles change with the last bits of the arithmetic,
    so these say which results a rerun can reproduce bit for bit
    (docs/datasets.md, "Provenance").
    """
    software = {"python": platform.python_version(), "machine": platform.machine()}
    for name in SOFTWARE:
        try:
            software[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            software[name] = ""
    source = Path(__file__).resolve().parent
    commit, dirty = "", -1
    try:
        run = functools.partial(subprocess.run, cwd=source, capture_output=True, text=True, timeout=10)
        head = run(["git", "rev-parse", "HEAD"])
        if head.returncode == 0:
            commit = head.stdout.strip()
            status = run(["git", "status", "--porcelain", "--untracked-files=no"])
            dirty = int(bool(status.stdout.strip())) if status.returncode == 0 else -1
    except (OSError, subprocess.SubprocessError):
        pass
    return {"software": json.dumps(software, sort_keys=True), "git_commit": commit, "git_dirty": dirty}


def describe(ds: xr.Dataset, *, title: str | None = None, config: Mapping[str, Any] | None = None,
             history: str | None = None) -> xr.Dataset:
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
        **provenance(),
    )
    if config is not None:
        attrs["config"] = json.dumps(config, sort_keys=True, default=float)
    ds.attrs = {k: _attr(v) for k, v in attrs.items()}
    for var in ds.variables.values():
        var.attrs = {k: _attr(v) for k, v in var.attrs.items()}
    return ds


#: File name endings a dataset may be written under: netCDF is the only format written, and a
#: name that promises another (``orbit.csv``) is refused rather than filled with netCDF.
NETCDF_SUFFIXES = (".nc", ".nc4", ".cdf", ".netcdf")


def check_dataset_path(path: str | os.PathLike, field: str = "path") -> str:
    """``path`` as a string if a dataset can be written there, else ValueError naming ``field``.

    Refused: a name without a netCDF ending (:data:`NETCDF_SUFFIXES`; for CSV, write
    ``ds.to_dataframe().to_csv(...)`` yourself) and an existing folder.
    """
    text = os.fspath(path)
    if os.path.isdir(text):
        raise ValueError(f"{field}: {text!r} is a folder; give the name of the netCDF file to write (e.g. "
                         f"{os.path.join(text, 'orbit.nc')!r})")
    suffix = os.path.splitext(text)[1].lower()
    if suffix not in NETCDF_SUFFIXES:
        raise ValueError(f"{field}: {text!r} does not end in {' or '.join(NETCDF_SUFFIXES)}; datasets are written "
                         "as netCDF only (for CSV: ds.to_dataframe().to_csv(path))")
    return text


def write_dataset(ds: xr.Dataset, path: str | os.PathLike, *, title: str | None = None,
                  config: Mapping[str, Any] | None = None, history: str | None = None) -> xr.Dataset:
    """Write ``ds`` to netCDF at ``path`` atomically (temporary file, then rename).

    Returns the dataset as written (with its global attributes).

    Raises
    ------
    ValueError
        ``path`` is an existing folder, or its name does not end in a netCDF
        suffix (:data:`NETCDF_SUFFIXES`): nothing is written under a name that
        promises another format.
    """
    check_dataset_path(path)
    ds = describe(ds, title=title, config=config, history=history)
    write_netcdf_atomically(ds, path)
    return ds


def open_dataset(path: str | os.PathLike) -> xr.Dataset:
    """Read a noslipsim dataset fully into memory (the file is closed on return)."""
    with xr.open_dataset(path, engine="netcdf4") as ds:
        return ds.load()

"""Stability grids: a quantity over a 2D parameter grid, with a theoretical threshold overlaid."""
from __future__ import annotations

import numpy as np

from .._metadata import long_name


def draw_stability_grid(ax, grid, *, threshold=None, vmin=None, vmax=None, cmap="magma",
                        threshold_color="c", threshold_label="ellipticity threshold", rasterized=True):
    """Draw a 2D grid (e.g. collisions survived over ``R x phi``) with a threshold curve.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    grid : xarray.DataArray
        Two dims, each with a numeric, strictly monotonic coordinate; the
        first dim is drawn vertically, the second horizontally.  NaN cells are
        left blank.
    threshold : (array_like, array_like), optional
        ``(x, y)`` of a theoretical threshold in the grid's coordinates,
        drawn as a dashed line.
    vmin, vmax : float, optional
        Colour limits (default: the data's range).

    Returns
    -------
    matplotlib.collections.QuadMesh
        For a colour bar.

    Raises
    ------
    ValueError
        For a grid that is not 2D with monotonic numeric coordinates, or a
        malformed threshold.
    """
    if getattr(grid, "ndim", None) != 2 or not hasattr(grid, "dims"):
        raise ValueError(f"grid: expected a 2D xarray.DataArray, got {type(grid).__name__} "
                         f"with ndim {getattr(grid, 'ndim', None)}")
    ydim, xdim = grid.dims
    coords = []
    for d in (xdim, ydim):
        if d not in grid.coords:
            raise ValueError(f"grid: dim {d!r} has no coordinate")
        c = np.asarray(grid[d].values, dtype=float)
        step = np.diff(c)
        if len(c) < 2 or not (np.all(step > 0) or np.all(step < 0)):
            raise ValueError(f"grid.{d}: coordinate must have >= 2 strictly monotonic values")
        coords.append(c)
    mesh = ax.pcolormesh(coords[0], coords[1], np.asarray(grid.values, dtype=float), shading="nearest",
                         vmin=vmin, vmax=vmax, cmap=cmap, rasterized=rasterized)
    ax.autoscale_view()
    xlim, ylim = ax.get_xlim(), ax.get_ylim()  # the grid's cells; the threshold must not widen them
    if threshold is not None:
        try:
            tx, ty = (np.asarray(v, dtype=float) for v in threshold)
        except (TypeError, ValueError):
            raise ValueError("threshold: expected (x, y) arrays") from None
        if tx.shape != ty.shape or tx.ndim != 1:
            raise ValueError(f"threshold: x {tx.shape} and y {ty.shape} must be 1D of one length")
        ax.plot(tx, ty, linestyle="--", color=threshold_color, linewidth=1.0, label=threshold_label)
    ax.set_xlim(xlim)
    ax.set_ylim(ylim)
    ax.set_xlabel(long_name(grid[xdim], xdim))
    ax.set_ylabel(long_name(grid[ydim], ydim))
    return mesh

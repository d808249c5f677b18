"""Refuse to draw nothing: an empty dataset or a panel without data is an error, never a figure.

A figure of an empty dataset passes every file check (the PDF and PNG exist,
the title prints "regular 33 %") and shows a blank axis.  Figure scripts read
their datasets with :func:`load_figure_data`, which refuses a dataset whose
required variables hold no finite value, and :func:`~noslipsim.plot.save_figure`
refuses a figure with a panel that shows no data (:func:`check_panels`).
"""
from __future__ import annotations

import numpy as np


class EmptyFigureError(ValueError):
    """A figure would show a dataset or a panel without data."""


def load_figure_data(path, required=None):
    """Load a dataset for a figure, refusing it when it holds nothing to draw.

    Parameters
    ----------
    path : str or os.PathLike
        A netCDF file written by the pipeline.
    required : sequence of str, optional
        Variables that must each hold at least one finite value (default: at
        least one data variable must).

    Returns
    -------
    xarray.Dataset
        Loaded into memory.

    Raises
    ------
    EmptyFigureError
        A required variable is missing or holds no finite value, or the
        dataset has no data at all.
    """
    import xarray as xr

    ds = xr.load_dataset(path)
    names = list(ds.data_vars) if required is None else list(required)
    missing = [name for name in names if name not in ds]
    if missing:
        raise EmptyFigureError(f"{path}: no variable {missing[0]!r} to draw (has {sorted(ds.data_vars)})")
    filled = {name: _has_values(ds[name].values) for name in names}
    if required is None and not any(filled.values()):
        raise EmptyFigureError(f"{path}: every variable is empty or NaN; nothing to draw")
    if required is not None and not all(filled.values()):
        empty = [name for name, ok in filled.items() if not ok]
        raise EmptyFigureError(f"{path}: {', '.join(empty)} hold(s) no finite value; nothing to draw")
    return ds


def require_points(values, what):
    """Raise :class:`EmptyFigureError` unless ``values`` holds at least one finite number (``what`` names the panel)."""
    if not _has_values(np.asarray(values)):
        raise EmptyFigureError(f"{what}: no finite point to draw")


def _has_values(values):
    values = np.asarray(values)
    if values.size == 0:
        return False
    if values.dtype.kind in "fc":
        return bool(np.isfinite(values).any())
    return True


def check_panels(fig):
    """Raise :class:`EmptyFigureError` naming the first panel of ``fig`` that shows no data.

    A panel is an Axes that is drawn (visible); it shows data when one of its
    lines, collections, images or patches has a finite point (an Axes turned
    off, such as a legend or a sketch's frame, may hold text only).
    Colour bars count as data.
    """
    for ax in fig.axes:
        if not ax.get_visible():
            continue
        if _artists_with_data(ax) or (not ax.axison and ax.texts):
            continue
        title = ax.get_title() or ax.get_title("left") or ax.get_ylabel() or f"axes {fig.axes.index(ax)}"
        raise EmptyFigureError(f"panel {title!r} shows no data: refusing to save an empty panel")


def _artists_with_data(ax):
    for line in ax.get_lines():
        if _has_values(_line_data(line)):
            return True
    for coll in ax.collections:
        if _has_values(_collection_data(coll)):
            return True
    for image in ax.get_images():
        if np.asarray(image.get_array()).size:
            return True
    for patch in ax.patches:
        if _has_values(patch.get_path().vertices):
            return True
    return False


def _line_data(line):
    verts = getattr(line, "_verts3d", None)  # a 3D line
    if verts is not None:
        return np.asarray(verts, dtype=float)
    return np.asarray(line.get_xydata(), dtype=float)


def _collection_data(coll):
    from matplotlib.collections import PathCollection

    for attr in ("_offsets3d", "_segments3d", "_vec"):  # 3D scatters, 3D line sets, 3D polygons
        data = getattr(coll, attr, None)
        if data is not None:
            return np.concatenate([np.asarray(v, dtype=float).ravel() for v in data]) if len(data) else np.zeros(0)
    if isinstance(coll, PathCollection):  # markers (scatter): the offsets are the data, the path is the marker
        return np.asarray(coll.get_offsets(), dtype=float)
    verts = [p.vertices for p in coll.get_paths() if len(p.vertices)]
    return np.concatenate(verts) if verts else np.zeros(0)


#: Display points per line segment when a legend is tested against a line (a segment may cross the legend's box
#: between two vertices outside it).
_SEGMENT_SAMPLES = 16


def legend_problems(ax):
    """What the legend of ``ax`` hides: the labels of lines that pass under it, and a spine it straddles.

    A legend belongs either inside the axes, clear of every line, or wholly
    outside them; one that overlaps an edge sits on the spine and its ticks.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        An axes with a legend (the figure is drawn to measure it).

    Returns
    -------
    list of str
        ``"covers LABEL"`` per line drawn under the legend's box (inside the
        axes' view), ``"straddles the spine"`` when the box is neither inside
        nor outside the axes; empty when the legend is clear.

    Raises
    ------
    ValueError
        If ``ax`` has no legend.
    """
    legend = ax.get_legend()
    if legend is None:
        raise ValueError("legend_problems: the axes have no legend")
    ax.figure.canvas.draw()
    box, frame = legend.get_window_extent(), ax.get_window_extent()
    problems = []
    inside = frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1
    if not inside and box.overlaps(frame):
        problems.append("straddles the spine")
    for line in ax.get_lines():
        if _passes_under(line, box, frame):
            problems.append(f"covers {line.get_label()}")
    return problems


def _passes_under(line, box, frame):
    """Whether a 2D line, sampled along each segment in display coordinates, enters ``box`` within ``frame``."""
    xy = np.asarray(line.get_xydata(), dtype=float)
    xy = xy[np.isfinite(xy).all(axis=1)]
    if not line.get_visible() or len(xy) == 0:
        return False
    pts = line.get_transform().transform(xy)
    if len(pts) > 1:
        t = np.linspace(0.0, 1.0, _SEGMENT_SAMPLES, endpoint=False)[:, None, None]
        pts = np.concatenate([(pts[:-1] + t * (pts[1:] - pts[:-1])).reshape(-1, 2), pts[-1:]])
    seen = ((pts[:, 0] >= frame.x0) & (pts[:, 0] <= frame.x1) & (pts[:, 1] >= frame.y0) & (pts[:, 1] <= frame.y1))
    under = (pts[:, 0] > box.x0) & (pts[:, 0] < box.x1) & (pts[:, 1] > box.y0) & (pts[:, 1] < box.y1)
    return bool((seen & under).any())


def check_legend(ax):
    """Raise :class:`ValueError` when the legend of ``ax`` hides a line or straddles a spine
    (:func:`legend_problems`): a figure script refuses to save such a layout."""
    problems = legend_problems(ax)
    if problems:
        title = ax.get_title() or ax.get_ylabel() or "an axes"
        raise ValueError(f"legend of {title!r}: " + ", ".join(problems))

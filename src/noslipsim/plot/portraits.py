r"""Velocity portraits on the unit disk.

At each recorded collision the post-collision vector ``(w, v_t, v_n)`` is
normalised and projected onto the disk ``(v_t, w)``:

.. math::

    (v_t, w) / \lVert (w, v_t, v_n) \rVert \in \{ x^2 + y^2 \le 1 \},

so every point lies on the closed unit disk (the paper's velocity phase
portrait; variables ``vt_unit`` and ``w_unit`` of a portrait dataset,
docs/datasets.md).
"""
from __future__ import annotations

import numpy as np
from matplotlib.patches import Circle as CirclePatch

from .checks import require_points

#: Points may lie this far outside the unit disk (rounding of the normalisation).
UNIT_DISK_TOL = 1e-9


def portrait_points(portrait):
    """``(v_t, w, orbit)`` of every recorded point, NaN padding dropped.

    Raises
    ------
    ValueError
        When ``vt_unit``/``w_unit`` are missing or a point lies off the unit disk.
    EmptyFigureError
        When no point was recorded (a panel would be empty).
    """
    for k in ("vt_unit", "w_unit"):
        if k not in portrait.variables:
            raise ValueError(f"portrait: missing variable {k!r} (expected a portrait dataset, docs/datasets.md)")
    vt = np.asarray(portrait["vt_unit"].values, dtype=float)
    w = np.asarray(portrait["w_unit"].values, dtype=float)
    if vt.shape != w.shape:
        raise ValueError(f"portrait: vt_unit {vt.shape} and w_unit {w.shape} differ in shape")
    orbit = np.broadcast_to(np.arange(vt.shape[0])[:, None], vt.shape) if vt.ndim == 2 else np.zeros(vt.shape, int)
    keep = np.isfinite(vt) & np.isfinite(w)
    vt, w, orbit = vt[keep], w[keep], orbit[keep]
    require_points(vt, "portrait")
    r = np.hypot(vt, w)
    if (r > 1.0 + UNIT_DISK_TOL).any():
        raise ValueError(f"portrait: a point lies off the unit disk (|(v_t, w)| = {r.max():.6g} > 1)")
    return vt, w, orbit


def draw_portrait(ax, portrait, *, color=None, cmap="tab20", size=0.3, rasterized=True, zorder=2):
    """Scatter a velocity portrait on the unit disk ``(v_t, w)``.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    portrait : xarray.Dataset
        ``vt_unit`` and ``w_unit`` along ``(orbit, point)`` (from
        ``simulate_many(..., record='portrait')`` or
        :func:`noslipsim.experiments.phase_portrait`).
    color : color, optional
        One colour for every point; default one colour per orbit from ``cmap``.
    size : float
        Marker area (points^2).
    rasterized : bool
        Rasterize the points in vector output (portraits hold many points).

    Returns
    -------
    matplotlib.collections.PathCollection
    """
    vt, w, orbit = portrait_points(portrait)
    velocity_disk_axes(ax, zorder + 1)
    if color is None:
        pts = ax.scatter(vt, w, c=orbit % 20 if cmap == "tab20" else orbit, cmap=cmap, s=size, linewidths=0,
                         rasterized=rasterized, zorder=zorder, vmin=0, vmax=19 if cmap == "tab20" else None)
    else:
        pts = ax.scatter(vt, w, color=color, s=size, linewidths=0, rasterized=rasterized, zorder=zorder)
    return pts


def velocity_disk_axes(ax, zorder):
    """The axes of a velocity portrait: the unit circle ``v_t^2 + w^2 = 1`` (at ``zorder``), square limits just
    outside it, labels ``v_t`` and ``w``."""
    ax.add_patch(CirclePatch((0.0, 0.0), 1.0, fill=False, edgecolor="0.3", linewidth=0.6, zorder=zorder))
    ax.set_xlim(-1.05, 1.05)
    ax.set_ylim(-1.05, 1.05)
    ax.set_aspect("equal")
    ax.set_xlabel(r"$v_t$")
    ax.set_ylabel(r"$w$")

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

import matplotlib
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


def unvisited_cells(portrait, bins=40):
    """The cells of a ``bins`` x ``bins`` grid on the disk ``(v_t, w)`` that no recorded point falls in.

    A velocity portrait shows where its orbits went, not where orbits cannot go: a
    white area of the disk may simply hold no sampled orbit.  The disk is the
    projection of the reduced phase space with its invariant volume
    ``ds dv_t dw``, so the share of the disk's area is the share of the measure.

    Returns
    -------
    edges : ndarray
        The ``bins + 1`` cell edges on ``[-1, 1]`` (both axes).
    empty : ndarray of bool
        ``(bins, bins)``, indexed ``[v_t cell, w cell]``: no point, cell centre on the disk.
    share : float
        The empty cells' share of the cells whose centre lies on the disk.
    """
    if isinstance(bins, bool) or not isinstance(bins, (int, np.integer)) or bins < 2:
        raise ValueError(f"bins: expected an integer >= 2, got {bins!r}")
    vt, w, _ = portrait_points(portrait)
    edges = np.linspace(-1.0, 1.0, int(bins) + 1)
    counts, _, _ = np.histogram2d(vt, w, bins=(edges, edges))
    centres = 0.5 * (edges[1:] + edges[:-1])
    on_disk = np.hypot(centres[:, None], centres[None, :]) <= 1.0
    empty = on_disk & (counts == 0)
    return edges, empty, float(empty.sum() / on_disk.sum())


def draw_unvisited(ax, portrait, *, bins=40, color="0.55", zorder=0.5):
    """Hatch the cells of the disk that no orbit of ``portrait`` visited (:func:`unvisited_cells`).

    Returns
    -------
    float
        Their share of the disk (of the invariant measure).
    """
    edges, empty, share = unvisited_cells(portrait, bins)
    if empty.any():
        centres = 0.5 * (edges[1:] + edges[:-1])
        with matplotlib.rc_context({"hatch.color": color, "hatch.linewidth": 0.4}):
            ax.contourf(centres, centres, empty.T.astype(float), levels=[0.5, 1.5], colors="none",
                        hatches=["//////"], zorder=zorder)
    return share

r"""Phase portraits beyond the plain velocity disk: one colour per orbit, the chaotic sea apart, Birkhoff and 3D.

Portrait datasets (:func:`noslipsim.experiments.portrait_set`, one case
selected) hold per orbit and point the boundary arclength ``s_boundary``, the
post-collision unit vector projected on the disk ``(vt_unit, w_unit)`` and,
for specular tables, the Birkhoff ``sin_angle``; optionally a flag
``regular`` per orbit (finite-time Lyapunov exponent below a threshold,
:mod:`noslipsim.analysis.islands`).  Coordinates: docs/analysis.md,
"Boundary portraits".

- :func:`orbit_colors`: ``n`` distinct colours, the same on every run;
- :func:`draw_layered_portrait`: the velocity portrait with chaotic orbits in
  one light colour underneath and each regular orbit in its own colour on top
  (so islands hidden by the projection show), or every orbit in its own
  colour;
- :func:`draw_birkhoff`: the specular portrait ``(s, p = sin angle)``;
- :func:`draw_reduced_portrait`: the reduced no-slip portrait in 3D, the solid
  cylinder ``s x {(v_t, w)}`` whose ends are identified.
"""
from __future__ import annotations

import numpy as np
from matplotlib.colors import to_rgba

from .checks import require_points
from .portraits import portrait_points, velocity_disk_axes
from .style import PALETTES, SEA_COLOR, orbit_colors

__all__ = ["PALETTES", "SEA_COLOR", "draw_birkhoff", "draw_layered_portrait", "draw_reduced_portrait",
           "orbit_colors"]


def _regular(portrait, regular, name="vt_unit"):
    """Per-orbit flags, checked against the number of orbits of variable ``name`` (read only when flags are given)."""
    if regular is None:
        return None
    n = portrait[name].shape[0] if portrait[name].ndim == 2 else 1
    flags = np.asarray(regular.values if hasattr(regular, "values") else regular).astype(bool).ravel()
    if flags.shape != (n,):
        raise ValueError(f"regular: expected one flag per orbit ({n}), got shape {flags.shape}")
    return flags


def draw_layered_portrait(ax, portrait, regular=None, *, size=0.3, sea_size=None, sea_color=SEA_COLOR,
                          rasterized=True):
    """Velocity portrait on the unit disk ``(v_t, w)``, the regular orbits drawn over the chaotic sea.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    portrait : xarray.Dataset
        ``vt_unit`` and ``w_unit`` along ``(orbit, point)`` (one case of a
        :func:`noslipsim.experiments.portrait_set` dataset).
    regular : array_like of bool (orbit,), optional
        ``True`` for an orbit on an invariant torus.  Orbits with ``False``
        are drawn first, all in ``sea_color``; the regular ones on top, each
        in its own colour (:func:`orbit_colors`).  ``None``: every orbit in its
        own colour (in orbit order).
    size, sea_size : float
        Marker areas (points^2) of regular and sea points (``sea_size``
        defaults to ``size``).

    Returns
    -------
    dict
        ``{"sea": PathCollection or None, "regular": PathCollection or None}``.
    """
    flags = _regular(portrait, regular)
    vt, w, orbit = portrait_points(portrait)
    velocity_disk_axes(ax, 4)
    out = {"sea": None, "regular": None}
    if flags is None:
        coloured = np.ones(orbit.size, bool)
        colors = orbit_colors(int(orbit.max()) + 1 if orbit.size else 0)
        rank = orbit
    else:
        coloured = flags[orbit]
        sea = ~coloured
        if sea.any():
            out["sea"] = ax.scatter(vt[sea], w[sea], s=size if sea_size is None else sea_size, color=sea_color,
                                    linewidths=0, rasterized=rasterized, zorder=2)
        ranks = np.cumsum(flags) - 1
        colors = orbit_colors(int(flags.sum()))
        rank = ranks[orbit]
    if coloured.any():
        out["regular"] = ax.scatter(vt[coloured], w[coloured], s=size, c=colors[rank[coloured]], linewidths=0,
                                    rasterized=rasterized, zorder=3)
    return out


def _points(portrait, names):
    for k in names:
        if k not in portrait.variables:
            raise ValueError(f"portrait: missing variable {k!r} (expected a portrait_set case, docs/datasets.md)")
    arrays = [np.asarray(portrait[k].values, dtype=float) for k in names]
    shape = arrays[0].shape
    if any(a.shape != shape for a in arrays):
        raise ValueError(f"portrait: variables {names} differ in shape")
    orbit = np.broadcast_to(np.arange(shape[0])[:, None], shape) if len(shape) == 2 else np.zeros(shape, int)
    keep = np.logical_and.reduce([np.isfinite(a) for a in arrays])
    require_points(arrays[0][keep], "portrait")
    return [a[keep] for a in arrays], orbit[keep]


def _colors_for(orbit, flags, sea_color):
    """Per point colour: sea points in ``sea_color``, regular (or all, without flags) by orbit."""
    if flags is None:
        return orbit_colors(int(orbit.max()) + 1 if orbit.size else 0)[orbit], np.ones(orbit.size, bool)
    ranks = np.cumsum(flags) - 1
    table = orbit_colors(int(flags.sum()))
    colored = flags[orbit]
    out = np.tile(np.asarray(to_rgba(sea_color)), (orbit.size, 1))
    out[colored] = table[ranks[orbit[colored]]]
    return out, colored


def draw_birkhoff(ax, portrait, regular=None, *, size=0.3, sea_color=SEA_COLOR, boundary_length=None,
                  rasterized=True):
    """The specular phase portrait in Birkhoff coordinates ``(s, p = sin angle)``.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    portrait : xarray.Dataset
        ``s_boundary`` and ``sin_angle`` along ``(orbit, point)``.
    regular : array_like of bool, optional
        As :func:`draw_layered_portrait` (sea underneath, regular on top).
    boundary_length : float, optional
        Right end of the ``s`` axis (default: the portrait's
        ``boundary_length``, a variable or an attribute, else the largest ``s``).

    Returns
    -------
    matplotlib.collections.PathCollection
    """
    flags = _regular(portrait, regular, "s_boundary")
    (s, p), orbit = _points(portrait, ("s_boundary", "sin_angle"))
    if (np.abs(p) > 1.0 + 1e-9).any():
        raise ValueError("portrait: sin_angle outside [-1, 1]")
    colors, top = _colors_for(orbit, flags, sea_color)
    order = np.argsort(top, kind="stable")                     # sea first, regular on top
    pts = ax.scatter(s[order], p[order], s=size, c=colors[order], linewidths=0, rasterized=rasterized)
    if boundary_length is None:
        # a variable of a portrait_set case, or the attribute analysis.birkhoff_coordinates writes
        known = portrait["boundary_length"] if "boundary_length" in portrait else portrait.attrs.get("boundary_length")
        boundary_length = float(known) if known is not None else float(s.max())
    ax.set_xlim(0.0, boundary_length)
    ax.set_ylim(-1.0, 1.0)
    ax.set_xlabel(r"$s$")
    ax.set_ylabel(r"$p = \sin\alpha$")
    return pts


def draw_reduced_portrait(ax, portrait, regular=None, *, size=0.3, sea_color=SEA_COLOR, sea_alpha=0.3,
                          boundary_length=None, rasterized=True, frame_color="0.35"):
    """The reduced no-slip portrait in 3D: ``s`` along the axis of a solid cylinder, ``(v_t, w)`` across it.

    The reduced phase space ``S^1 x S^2_+`` is the solid cylinder
    ``[0, L] x {v_t^2 + w^2 <= 1}`` with its two ends identified (a solid
    torus); the two end circles and four generators are drawn as a frame.
    The chaotic sea fills the cylinder, so it is drawn translucent (``sea_alpha``)
    and the regular orbits, opaque, show through; much fainter than the
    default and the sea vanishes at print size.

    Parameters
    ----------
    ax : mpl_toolkits.mplot3d.axes3d.Axes3D
        A 3D axes (``fig.add_subplot(..., projection="3d")``).
    portrait : xarray.Dataset
        ``s_boundary``, ``vt_unit`` and ``w_unit`` along ``(orbit, point)``.
    regular, size, sea_color, boundary_length
        As :func:`draw_birkhoff`.
    sea_alpha : float
        Opacity of the sea points.

    Returns
    -------
    dict
        ``{"sea": Path3DCollection or None, "regular": Path3DCollection or None}``.
    """
    if getattr(ax, "name", None) != "3d":
        raise ValueError("ax: expected a 3D axes (projection='3d')")
    flags = _regular(portrait, regular)
    (s, vt, w), orbit = _points(portrait, ("s_boundary", "vt_unit", "w_unit"))
    if (np.hypot(vt, w) > 1.0 + 1e-9).any():
        raise ValueError("portrait: a point lies off the unit disk")
    if boundary_length is None:
        # a variable of a portrait_set case, or the attribute analysis.birkhoff_coordinates writes
        known = portrait["boundary_length"] if "boundary_length" in portrait else portrait.attrs.get("boundary_length")
        boundary_length = float(known) if known is not None else float(s.max())
    colors, top = _colors_for(orbit, flags, sea_color)
    out = {"sea": None, "regular": None}
    sea = ~top
    if sea.any():
        out["sea"] = ax.scatter(s[sea], vt[sea], w[sea], s=size, color=sea_color, alpha=sea_alpha, linewidths=0,
                                depthshade=False, rasterized=rasterized)
    if top.any():
        out["regular"] = ax.scatter(s[top], vt[top], w[top], s=size, c=colors[top], linewidths=0, depthshade=False,
                                    rasterized=rasterized)
    ang = np.linspace(0.0, 2.0 * np.pi, 121)
    for end in (0.0, boundary_length):
        ax.plot(np.full_like(ang, end), np.cos(ang), np.sin(ang), color=frame_color, linewidth=0.6)
    for a in (0.0, 0.5 * np.pi, np.pi, 1.5 * np.pi):
        ax.plot([0.0, boundary_length], [np.cos(a)] * 2, [np.sin(a)] * 2, color=frame_color, linewidth=0.4,
                linestyle=":")
    ax.set_xlim(0.0, boundary_length)
    ax.set_ylim(-1.0, 1.0)
    ax.set_zlim(-1.0, 1.0)
    ax.set_xlabel(r"$s$")
    ax.set_ylabel(r"$v_t$")
    ax.set_zlabel(r"$w$")
    return out

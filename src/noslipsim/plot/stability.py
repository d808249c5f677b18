r"""Stability figures: linear-class boundaries over survival maps, return points, growth, the set-up sketch.

The linear class of a periodic orbit comes from its monodromy
(``elliptic``: eigenvalues on the unit circle, a perturbation rotates about
the orbit; ``hyperbolic``: ``|lambda| > 1``, it grows like ``|lambda|^n``
over ``n`` periods; docs/analysis.md).  These helpers draw what the stability
datasets hold (:func:`noslipsim.analysis.stability_grid`,
:func:`noslipsim.experiments.perturbed_wedge_orbits`); they never simulate.
"""
from __future__ import annotations

import math

import numpy as np
from matplotlib.patches import Arc as ArcPatch
from matplotlib.patches import Circle as CirclePatch
from matplotlib.patches import FancyArrowPatch

from .style import SCATTERER_COLOR, WALL_COLOR

#: Colour of the linear-class boundary drawn over survival maps.
CLASS_COLOR = "#D55E00"


def draw_class_boundary(ax, kinds, *, kind="elliptic", color=CLASS_COLOR, linewidth=1.0, linestyle="-",
                        zorder=1.5):
    """Outline the cells of a 2D grid whose linear class is ``kind``.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    kinds : xarray.DataArray
        2D, strings (``'elliptic'``, ``'hyperbolic'``, ``'parabolic'``), each
        dim with a numeric coordinate; the first dim is drawn vertically (as
        :func:`noslipsim.plot.draw_stability_grid` does).
    kind : str
        The class whose region is outlined.
    zorder : float
        Drawing order: by default above a grid's cells (1) and below lines (2),
        so a threshold curve drawn on the same place stays visible.

    Returns
    -------
    matplotlib.contour.QuadContourSet or None
        ``None`` when no cell, or every cell, has the class (no boundary).

    Raises
    ------
    ValueError
        For a grid that is not 2D with coordinates.
    """
    if getattr(kinds, "ndim", None) != 2 or not hasattr(kinds, "dims"):
        raise ValueError(f"kinds: expected a 2D xarray.DataArray, got {type(kinds).__name__}")
    ydim, xdim = kinds.dims
    for d in (xdim, ydim):
        if d not in kinds.coords:
            raise ValueError(f"kinds: dim {d!r} has no coordinate")
    inside = (np.asarray(kinds.values).astype(str) == kind).astype(float)
    if inside.min() == inside.max():
        return None
    return ax.contour(np.asarray(kinds[xdim].values, float), np.asarray(kinds[ydim].values, float), inside,
                      levels=[0.5], colors=[color], linewidths=linewidth, linestyles=linestyle,
                      zorder=zorder)


def return_points(orbit, element):
    """``(s, w)`` of an orbit's post-collision states on one element (NaN padding dropped).

    Parameters
    ----------
    orbit : xarray.Dataset
        One orbit with the log variables ``element``, ``s`` and ``spin`` along ``collision``.
    element : int
        Element index.
    """
    for k in ("element", "s", "spin"):
        if k not in orbit.variables:
            raise ValueError(f"orbit: missing variable {k!r} (expected a collision log, docs/datasets.md)")
        if orbit[k].dims != ("collision",):
            raise ValueError(f"orbit.{k}: expected dims ('collision',), got {orbit[k].dims}; select one orbit first")
    e = np.asarray(orbit.element.values, dtype=float)
    keep = np.isfinite(e) & (e == element)
    return np.asarray(orbit.s.values, float)[keep], np.asarray(orbit.spin.values, float)[keep]


def draw_return_points(ax, orbit, element, *, fixed=None, color="0.2", size=1.0, fixed_color=CLASS_COLOR,
                       rasterized=True):
    """Scatter the returns of an orbit to one wall in the plane ``(s, w)``; mark the periodic point.

    Around an elliptic periodic point the returns of a perturbed orbit lie on a
    closed curve (an invariant region); around a hyperbolic one they scatter.

    Parameters
    ----------
    orbit : xarray.Dataset
        One orbit (see :func:`return_points`).
    element : int
        The wall whose returns are drawn.
    fixed : xarray.Dataset, optional
        The periodic orbit: its point on ``element`` is marked with a cross.

    Returns
    -------
    matplotlib.collections.PathCollection
    """
    s, w = return_points(orbit, element)
    pts = ax.scatter(s, w, s=size, color=color, linewidths=0, rasterized=rasterized, zorder=2)
    if fixed is not None:
        fs, fw = return_points(fixed, element)
        if fs.size == 0:
            raise ValueError(f"fixed: the periodic orbit has no collision on element {element}")
        ax.plot(fs[:1], fw[:1], marker="x", color=fixed_color, markersize=5, linestyle="none", zorder=3)
    ax.set_xlabel("$s$ (arclength on the wall)")
    ax.set_ylabel("$w$ (scaled spin)")
    return pts


def draw_deviation(ax, orbit, *, lambda_max=None, anchor=None, color=None, label=None, linewidth=0.7):
    r"""Semi-log plot of a perturbed orbit's distance from its periodic orbit against the collision number.

    With ``lambda_max`` (the largest ``|lambda|`` of the periodic orbit's
    ``p``-collision monodromy, here ``p = 2``) a dashed line shows the linear
    growth

    .. math::

        \delta_k = \delta_a\,|\lambda|^{(k - k_a)/2},

    from the first collision ``k_a`` where the distance reaches ``anchor``
    (default: the first collision) on, while it stays below 1.  Near a parabolic orbit (eigenvalues
    ``1, lambda, 1/lambda`` all close to 1) a perturbation first grows
    polynomially (a near-Jordan block), so anchoring past that transient
    compares the exponential rate alone.

    Parameters
    ----------
    orbit : xarray.Dataset
        One orbit with ``deviation`` along ``collision``
        (:func:`noslipsim.experiments.perturbed_wedge_orbits`).
    lambda_max : float, optional
        Largest ``|lambda|`` per two collisions.
    anchor : float, optional
        Distance through which the dashed line passes (when the run reaches it).

    Returns
    -------
    matplotlib.lines.Line2D
    """
    if "deviation" not in orbit.variables or orbit.deviation.dims != ("collision",):
        raise ValueError("orbit: expected one orbit with a 'deviation' variable along 'collision'")
    dev = np.asarray(orbit.deviation.values, float)
    k = np.flatnonzero(np.isfinite(dev) & (dev > 0))
    if k.size == 0:
        raise ValueError("orbit: no positive deviation to draw")
    (line,) = ax.semilogy(k, dev[k], color=color, label=label, linewidth=linewidth)
    if lambda_max is not None:
        lam = float(lambda_max)
        if not (math.isfinite(lam) and lam > 0):
            raise ValueError(f"lambda_max: must be finite and > 0, got {lambda_max!r}")
        a = 0
        if anchor is not None:
            reached = np.flatnonzero(dev[k] >= float(anchor))
            a = int(reached[0]) if reached.size else k.size - 1
        pred = dev[k[a]] * lam ** ((k - k[a]) / 2.0)
        ok = (k >= k[a]) & (pred <= 1.0)
        ax.semilogy(k[ok], pred[ok], color=line.get_color(), linestyle="--", linewidth=0.6)
    ax.set_xlabel("collision")
    ax.set_ylabel("distance from the periodic orbit")
    return line


def draw_two_disk_setup(ax, radius, phi, theta, *, gravity=True, color=CLASS_COLOR):
    r"""Sketch of the stability experiment: two disks, ``q0``, ``q1``, the angles ``phi`` and ``theta``.

    Disks of radius ``R`` centred at ``(-1, 0)`` and ``(1, 0)``;
    ``q0 = (-1 + R cos phi, R sin phi)`` and its mirror image ``q1``; the tangent
    lines at both (the tangential wedge, half-angle ``phi``); the orbit from
    ``q0`` launched at ``theta`` above the chord, a parabola landing on
    ``q1`` (``gravity=True``, the force drawn as an arrow) or the chord.

    Parameters
    ----------
    radius : float
        In ``(0, 1)``.
    phi : float
        In ``(0, pi/2)``.
    theta : float
        In ``(0, pi/2)``.
    """
    R, phi, theta = float(radius), float(phi), float(theta)
    if not 0.0 < R < 1.0:
        raise ValueError(f"radius: must lie in (0, 1), got {radius}")
    for name, a in (("phi", phi), ("theta", theta)):
        if not 0.0 < a < math.pi / 2:
            raise ValueError(f"{name}: must lie in (0, pi/2), got {a}")
    for cx in (-1.0, 1.0):
        ax.add_patch(CirclePatch((cx, 0.0), R, facecolor=SCATTERER_COLOR, edgecolor=WALL_COLOR, zorder=1))
    c, s = math.cos(phi), math.sin(phi)
    q0, q1 = np.array([-1.0 + R * c, R * s]), np.array([1.0 - R * c, R * s])
    d = q1[0] - q0[0]
    # tangent lines through q0 and q1 (direction along the tangent, up and outward), meeting on the axis
    apex_y = q0[1] - (0.0 - q0[0]) * c / s if s > 0 else -np.inf
    for q, sx in ((q0, -1.0), (q1, 1.0)):
        far = q + 0.9 * np.array([sx * s, c]) * R
        near = np.array([0.0, apex_y]) if math.isfinite(apex_y) and apex_y > -1.5 else q - np.array([sx * s, c])
        ax.plot([near[0], far[0]], [near[1], far[1]], color="0.5", linestyle=":", linewidth=0.7, zorder=2)
    ax.plot([-1.0, q0[0]], [0.0, q0[1]], color="0.4", linewidth=0.6, zorder=2)
    ax.plot([q0[0], q1[0]], [q0[1], q1[1]], color="0.4", linestyle="--", linewidth=0.6, zorder=2)
    x = np.linspace(0.0, 1.0, 60) * d
    if gravity:
        y = q0[1] + x * math.tan(theta) * (1.0 - x / d)   # the parabola through q0 and q1 at angle theta
    else:
        y = np.full_like(x, q0[1])
    ax.plot(q0[0] + x, y, color=color, linewidth=1.2, zorder=3)
    ax.plot(*np.c_[q0, q1], marker="o", color="k", markersize=3, linestyle="none", zorder=4)
    ax.annotate("$q_0$", q0, xytext=(-10, 4), textcoords="offset points", ha="right")
    ax.annotate("$q_1$", q1, xytext=(10, 4), textcoords="offset points", ha="left")
    r_phi = 0.45 * R
    ax.add_patch(ArcPatch((-1.0, 0.0), 2 * r_phi, 2 * r_phi, theta1=0.0, theta2=math.degrees(phi), linewidth=0.7))
    ax.plot([-1.0, -1.0 + 1.2 * R], [0.0, 0.0], color="0.4", linewidth=0.6)
    ax.annotate(r"$\varphi$", (-1.0 + r_phi * math.cos(phi / 2), r_phi * math.sin(phi / 2)), xytext=(3, 0),
                textcoords="offset points", va="center")
    r_th = 0.25 * d
    ax.add_patch(ArcPatch(q0, 2 * r_th, 2 * r_th, theta1=0.0, theta2=math.degrees(theta), linewidth=0.7,
                          color=color))
    ax.annotate(r"$\theta$", q0 + r_th * np.array([math.cos(theta / 2), math.sin(theta / 2)]), xytext=(4, -2),
                textcoords="offset points", va="center", color=color)
    if gravity:
        top = max(q0[1] + d * math.tan(theta) / 4.0, R)   # above the flight's apex
        ax.add_patch(FancyArrowPatch((0.0, top + 0.45), (0.0, top + 0.1), arrowstyle="-|>", mutation_scale=8,
                                     color="k", linewidth=0.7))
        ax.annotate("$g$", (0.0, top + 0.28), xytext=(4, 0), textcoords="offset points", va="center")
    ax.set_aspect("equal")
    ax.set_xlim(-1.0 - R - 0.1, 1.0 + R + 0.1)
    return q0, q1

"""Annotations for schematic figures: angle arcs, rays, labelled points.

Angles are in radians, counter-clockwise from the +x axis, in data
coordinates of an equal-aspect axes (as :func:`noslipsim.plot.draw_table`
sets), so an arc of radius ``r`` is a circular arc on the page.
"""
from __future__ import annotations

import math

import numpy as np

from .._validate import positive

#: Samples along an angle arc.
ARC_POINTS = 48


def _point(value, field):
    try:
        x, y = (float(v) for v in value)
    except (TypeError, ValueError):
        raise ValueError(f"{field}: expected a point (x, y), got {value!r}") from None
    if not (math.isfinite(x) and math.isfinite(y)):
        raise ValueError(f"{field}: must be finite, got {value!r}")
    return x, y


def draw_angle(ax, vertex, angle0, angle1, radius, label=None, *, color="k", linewidth=0.6,
               label_distance=1.45, fontsize=None, zorder=6):
    """Draw the angle from direction ``angle0`` to ``angle1`` at ``vertex`` as an arc, with a label.

    The arc runs counter-clockwise from ``angle0`` to ``angle1`` when
    ``angle1 > angle0`` and clockwise otherwise (the shorter way is not
    assumed: give the angles in the order you mean).

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    vertex : (float, float)
        The angle's vertex (data units).
    angle0, angle1 : float
        Directions of its two sides (radians, counter-clockwise from +x).
    radius : float
        Radius of the arc (data units, > 0).
    label : str, optional
        Text placed on the bisector at ``label_distance * radius``.

    Returns
    -------
    matplotlib.lines.Line2D
        The arc.
    """
    x, y = _point(vertex, "vertex")
    radius = positive(radius, "radius")
    a0, a1 = float(angle0), float(angle1)
    if not (math.isfinite(a0) and math.isfinite(a1)):
        raise ValueError(f"angle0, angle1: must be finite, got {angle0!r}, {angle1!r}")
    ang = np.linspace(a0, a1, ARC_POINTS)
    (arc,) = ax.plot(x + radius * np.cos(ang), y + radius * np.sin(ang), color=color, linewidth=linewidth,
                     zorder=zorder)
    if label is not None:
        mid = 0.5 * (a0 + a1)
        ax.text(x + label_distance * radius * math.cos(mid), y + label_distance * radius * math.sin(mid), label,
                ha="center", va="center", color=color, fontsize=fontsize, zorder=zorder)
    return arc


def draw_ray(ax, origin, through, *, beyond=0.25, color="k", linewidth=0.6, linestyle="--", zorder=1):
    """Draw the line from ``origin`` through ``through``, continued ``beyond`` times their distance past it.

    Used for tangent lines and wedge walls in schematic figures.

    Returns
    -------
    matplotlib.lines.Line2D
    """
    p = np.array(_point(origin, "origin"))
    q = np.array(_point(through, "through"))
    if np.array_equal(p, q):
        raise ValueError(f"through: must differ from origin {tuple(p)}")
    beyond = float(beyond)
    if not (math.isfinite(beyond) and beyond >= 0):
        raise ValueError(f"beyond: must be finite and >= 0, got {beyond}")
    end = q + beyond * (q - p)
    (line,) = ax.plot([p[0], end[0]], [p[1], end[1]], color=color, linewidth=linewidth, linestyle=linestyle,
                      zorder=zorder)
    return line


def label_point(ax, xy, text, *, offset=(4.0, 4.0), color="k", marker="o", markersize=3.0, fontsize=None,
                ha="left", va="bottom", zorder=7):
    """Mark a point with a dot and a label ``offset`` points away from it (e.g. ``q_0``, ``q_1``)."""
    x, y = _point(xy, "xy")
    if marker:
        ax.plot([x], [y], marker=marker, markersize=markersize, color=color, linestyle="none", zorder=zorder)
    return ax.annotate(text, (x, y), xytext=offset, textcoords="offset points", color=color, fontsize=fontsize,
                       ha=ha, va=va, zorder=zorder)


def ray_label_offset(origin, through, inside, distance=8.0):
    """Offset (points) and alignment that put a label of ``through`` beside the ray from ``origin``, away from it.

    The label of a point on a wall or tangent line sits across the line when it is offset along the line
    (Figure 6's ``q0``, ``q1`` on the tangents); perpendicular to the ray, on the side away from ``inside``
    (a point of the picture's interior, e.g. the flight's apex), it touches neither the line nor the flight.
    Meant for an equal-aspect axes (:func:`noslipsim.plot.draw_table` sets one), where a perpendicular in data
    coordinates is one on the page.

    Returns
    -------
    offset : tuple of float
        ``(dx, dy)`` in points, of length ``distance``.
    ha, va : str
        Alignment that keeps the label's box on that side.
    """
    p, q, c = (np.array(_point(v, name)) for v, name in ((origin, "origin"), (through, "through"),
                                                          (inside, "inside")))
    if np.array_equal(p, q):
        raise ValueError(f"through: must differ from origin {tuple(p)}")
    u = (q - p) / np.linalg.norm(q - p)
    n = np.array([-u[1], u[0]])
    if np.dot(n, c - q) > 0:
        n = -n
    dx, dy = positive(distance, "distance") * n
    ha = "right" if dx < -1e-9 * distance else "left" if dx > 1e-9 * distance else "center"
    va = "top" if dy < -1e-9 * distance else "bottom" if dy > 1e-9 * distance else "center"
    return (float(dx), float(dy)), ha, va



def draw_force_arrow(ax, force, *, tail=(0.9, 0.95), length=0.2, label=r"$\mathbf{g}$", color="k", zorder=8):
    """An arrow along the force, in a corner of the panel (axes fraction), labelled ``g`` beside it.

    The panel's own aspect may stretch one axis, so the direction is laid out in
    display units: the arrow points as the force does on the page.

    Parameters
    ----------
    force : sequence of 2 float
        The table's constant force (its direction is drawn; its size is not).
    tail : tuple of float
        Where the arrow starts, in axes fraction.
    length : float
        Arrow length as a share of the axes' height.

    Returns
    -------
    matplotlib.text.Annotation
        The arrow (its label is a separate text).
    """
    fx, fy = _point(force, "force")
    size = math.hypot(fx, fy)
    if size == 0.0:
        raise ValueError("force: zero force has no direction to draw")
    x0, y0 = _point(tail, "tail")
    bbox = ax.get_window_extent()
    dx = positive(length, "length") * fx / size * bbox.height / bbox.width   # the same page length both ways
    dy = length * fy / size
    arrow = ax.annotate("", xy=(x0 + dx, y0 + dy), xytext=(x0, y0), xycoords="axes fraction",
                        arrowprops=dict(arrowstyle="-|>", color=color, linewidth=0.8, shrinkA=0, shrinkB=0),
                        zorder=zorder)
    ax.text(x0 + 0.5 * dx - 0.04, y0 + 0.5 * dy, label, transform=ax.transAxes, ha="right", va="center",
            color=color, zorder=zorder)
    return arrow

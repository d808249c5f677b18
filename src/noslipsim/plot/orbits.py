r"""Draw orbits: the exact path between collisions, spin markers, start and end dots.

Between collisions a particle flies the scene's exact flight
(:func:`noslipsim.plot.flights.fly`): under a force the parabola

.. math::

    q(t) = q_k + v_k (t - t_k) + \tfrac12 a (t - t_k)^2, \qquad t_k \le t \le t_{k+1},

with ``a`` the scene's force, the thermostat's closed-form path, or a
cyclotron arc in a magnetic field, so the path is rebuilt from the collision
log (docs/datasets.md) and sampled along every curved flight, not joined by
straight chords.  The scaled spin ``w = gamma R omega`` (counter-clockwise positive,
docs/conventions.md) is constant on a flight; a spin marker is the particle
drawn as a small circle with an arrow inside that turns the way the particle
spins, over an angle proportional to ``|w| / sqrt(|v|^2 + w^2)`` (the share of
the speed carried by the spin).  A marker sits at the middle of its flight or,
when that spot is taken, at the nearest point along the flight where its
circle crosses no wall and overlaps no marker already drawn
(:data:`SPIN_SPOTS`); a flight with no such point gets none.
"""
from __future__ import annotations

import json
import math

import numpy as np
from matplotlib.patches import Circle as CirclePatch
from matplotlib.patches import FancyArrowPatch
from matplotlib.path import Path

from .flights import flight_samples, fly
from .style import law_color
from .table import scene_of

#: Points sampled on each curved flight (force or field; a straight flight needs two).
POINTS_PER_FLIGHT = 24
#: A spin arrow turns this many degrees when all of the speed is spin.
SPIN_ARC_MAX = 300.0
#: Spins below this share of the speed are drawn as a dot (no rotation).
SPIN_ZERO = 1e-9
#: Where along a flight (share of its duration) a spin marker may sit, in order of preference.
SPIN_SPOTS = (0.5, 0.4, 0.6, 0.3, 0.7, 0.2, 0.8, 0.1, 0.9)
#: Least distance between two spin markers' centres, and from a centre to a wall, in marker radii.
SPIN_GAP, SPIN_CLEARANCE = 2.2, 1.15
#: Size of the spin arrow's head (points), readable in print at the figures' 6.5 in width.
SPIN_HEAD = 6.5

_LOG = ("t", "x", "y", "vx", "vy", "spin")


def _scalar(orbit, name):
    value = np.asarray(orbit[name].values, dtype=float)
    if value.ndim != 0:
        raise ValueError(f"orbit.{name}: expected one orbit (a scalar), got shape {value.shape}; "
                         "select one orbit first (ds.isel(orbit=i))")
    return float(value)


def _start(orbit):
    """``(x, y, vx, vy, spin)`` at time 0."""
    if "x_start" in orbit.variables:
        return tuple(_scalar(orbit, f"{k}_start") for k in ("x", "y", "vx", "vy", "spin"))
    if "start" in orbit.attrs:
        start = json.loads(orbit.attrs["start"])
        (x, y), (vx, vy) = start["position"], start["velocity"]
        return float(x), float(y), float(vx), float(vy), float(start.get("spin", 0.0))
    raise ValueError("orbit: no start state (variables x_start, y_start, vx_start, vy_start, spin_start "
                     "or a 'start' attribute as written by noslipsim.simulate)")


def orbit_nodes(orbit):
    """The states that begin each flight of one orbit, and the end time.

    Parameters
    ----------
    orbit : xarray.Dataset
        One orbit: the output of :func:`noslipsim.simulate`, or one orbit of an
        orbit set (:func:`noslipsim.experiments.orbit_set`, ``ds.isel(orbit=i)``):
        the collision log ``t, x, y, vx, vy, spin`` along ``collision`` (NaN
        padding after the end is dropped), ``t_final``, the start state and the
        scene.

    Returns
    -------
    dict
        ``t, x, y, vx, vy, spin`` arrays (start, then every collision),
        ``t_end``, the ``scene`` (whose flights join the nodes) and its force ``(a_x, a_y)``.

    Raises
    ------
    ValueError
        When a variable is missing or the dataset holds more than one orbit.
    """
    missing = [k for k in (*_LOG, "t_final") if k not in orbit.variables]
    if missing:
        raise ValueError(f"orbit: missing variables {missing} (expected a collision log, see docs/datasets.md)")
    for k in _LOG:
        if orbit[k].dims != ("collision",):
            raise ValueError(f"orbit.{k}: expected dims ('collision',), got {orbit[k].dims}; "
                             "select one orbit first (ds.isel(orbit=i))")
    log = {k: np.asarray(orbit[k].values, dtype=float) for k in _LOG}
    keep = np.isfinite(log["t"])
    start = _start(orbit)
    nodes = {k: np.concatenate([[s], log[k][keep]]) for k, s in zip(_LOG, (0.0, *start))}
    nodes["t_end"] = _scalar(orbit, "t_final")
    nodes["scene"] = scene_of(orbit)
    nodes["force"] = nodes["scene"].force
    return nodes


def orbit_path(orbit, points_per_flight=POINTS_PER_FLIGHT):
    """The continuous path ``(x, y)`` of one orbit, every flight sampled on its curve (parabola, arc).

    Parameters
    ----------
    orbit : xarray.Dataset
        One orbit (see :func:`orbit_nodes`).
    points_per_flight : int
        Samples per curved flight (>= 2); straight flights use their two ends.

    Returns
    -------
    (numpy.ndarray, numpy.ndarray)
    """
    if isinstance(points_per_flight, bool) or int(points_per_flight) != points_per_flight or points_per_flight < 2:
        raise ValueError(f"points_per_flight: expected an integer >= 2, got {points_per_flight!r}")
    n = orbit_nodes(orbit)
    _, x, y = flight_samples(n, np.append(n["t"][1:], n["t_end"]), points_per_flight)
    return x.ravel(), y.ravel()


def _flight_points(n, share=0.5):
    """Position, velocity and spin at ``share`` of the duration of every flight (0.5: the middle)."""
    t_next = np.append(n["t"][1:], n["t_end"])
    tau = share * np.clip(t_next - n["t"], 0.0, None)
    return (*fly(n, n["x"], n["y"], n["vx"], n["vy"], tau), n["spin"])


def _spin_spots(n, scene, spin_every, radius):
    """``(x, y, spin, speed)`` of the spin markers: one per ``spin_every``-th flight where one fits.

    A marker must keep :data:`SPIN_CLEARANCE` radii from every wall (in a
    periodic scene the walls are not checked: copies repeat them) and
    :data:`SPIN_GAP` radii from every marker placed before it.  A flight
    whose middle lies within one radius of a marker already placed repeats
    an earlier flight (a periodic orbit) and gets none.
    """
    spots = [_flight_points(n, f) for f in SPIN_SPOTS]
    walls = () if scene.lattice is not None else scene.elements
    placed = []
    for k in range(0, len(n["t"]), int(spin_every)):
        mx, my = float(spots[0][0][k]), float(spots[0][1][k])
        if any(math.hypot(mx - qx, my - qy) < radius for qx, qy, _, _ in placed):
            continue                                   # a flight repeated (a periodic orbit): marked once
        for x, y, vx, vy, w in spots:
            px, py = float(x[k]), float(y[k])
            if any(e.distance(np.array([px, py])) < SPIN_CLEARANCE * radius for e in walls):
                continue
            if any(math.hypot(px - qx, py - qy) < SPIN_GAP * radius for qx, qy, _, _ in placed):
                continue
            speed = math.sqrt(vx[k] ** 2 + vy[k] ** 2 + w[k] ** 2)
            if speed > 0:
                placed.append((px, py, float(w[k]), speed))
            break
    return placed


def draw_spin(ax, x, y, spin, speed, radius, *, color="k", linewidth=0.7, zorder=4):
    """Draw the particle at ``(x, y)`` as a circle with an arrow showing its spin.

    The arrow runs counter-clockwise for ``spin > 0`` and clockwise for
    ``spin < 0``, over ``SPIN_ARC_MAX * |spin| / speed`` degrees; a spin below
    ``SPIN_ZERO * speed`` is drawn as a dot.

    Parameters
    ----------
    x, y : float
        Centre (data units).
    spin : float
        Scaled spin ``w`` (counter-clockwise positive).
    speed : float
        ``sqrt(|v|^2 + w^2)``, the scale of the arrow (> 0).
    radius : float
        Radius of the drawn particle (data units, > 0).
    """
    if not (math.isfinite(radius) and radius > 0):
        raise ValueError(f"radius: must be finite and > 0, got {radius}")
    if not (math.isfinite(speed) and speed > 0):
        raise ValueError(f"speed: must be finite and > 0, got {speed}")
    ax.add_patch(CirclePatch((x, y), radius, fill=False, edgecolor=color, linewidth=linewidth, zorder=zorder))
    share = min(abs(spin) / speed, 1.0)
    if share < SPIN_ZERO:
        ax.plot([x], [y], marker=".", markersize=1.5, color=color, zorder=zorder)
        return
    span = math.radians(SPIN_ARC_MAX * share) * math.copysign(1.0, spin)
    ang = math.pi / 2 + np.linspace(0.0, span, 24)
    r = 0.6 * radius
    path = Path(np.c_[x + r * np.cos(ang), y + r * np.sin(ang)])
    ax.add_patch(FancyArrowPatch(path=path, arrowstyle="-|>", mutation_scale=SPIN_HEAD, color=color,
                                 linewidth=linewidth, shrinkA=0, shrinkB=0, zorder=zorder))


def mark_ends(ax, start, end, *, color="k", size=4.5, zorder=5):
    """Dots at the start (open) and the end (filled) of an orbit."""
    ax.plot([start[0]], [start[1]], marker="o", markersize=size, markerfacecolor="white",
            markeredgecolor=color, linestyle="none", zorder=zorder)
    ax.plot([end[0]], [end[1]], marker="o", markersize=size, color=color, markeredgecolor=color,
            linestyle="none", zorder=zorder)


def draw_orbit(ax, orbit, *, color=None, linewidth=None, label=None, ends=True, spin_every=None,
               spin_radius=None, points_per_flight=POINTS_PER_FLIGHT, alpha=1.0, zorder=2):
    """Draw one orbit: its exact path, optional spin markers, start and end dots.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    orbit : xarray.Dataset
        One orbit (see :func:`orbit_nodes`).
    color : color, optional
        Default: the colour of the scene's law (:data:`noslipsim.plot.LAW_COLORS`).
    ends : bool
        Mark the start (open dot) and the end (filled dot).
    spin_every : int, optional
        Draw a spin marker (:func:`draw_spin`) on every ``spin_every``-th
        flight, starting with the first: at the middle of the flight, or at
        the nearest of :data:`SPIN_SPOTS` where it crosses no wall and
        overlaps no earlier marker; none on a flight without such a spot
        or one that repeats an earlier flight.
    spin_radius : float, optional
        Radius of the spin markers (data units); default 3 % of the larger
        side of the path's bounding box.

    Returns
    -------
    matplotlib.lines.Line2D
        The path.
    """
    n = orbit_nodes(orbit)
    color = law_color(scene_of(orbit).law) if color is None else color
    x, y = orbit_path(orbit, points_per_flight)
    (line,) = ax.plot(x, y, color=color, linewidth=linewidth, label=label, alpha=alpha, zorder=zorder)
    if spin_every is not None:
        if isinstance(spin_every, bool) or int(spin_every) != spin_every or spin_every < 1:
            raise ValueError(f"spin_every: expected a positive integer, got {spin_every!r}")
        if spin_radius is None:
            spin_radius = 0.03 * max(np.ptp(x), np.ptp(y), 1e-12)
        for mx, my, mw, speed in _spin_spots(n, scene_of(orbit), spin_every, spin_radius):
            draw_spin(ax, mx, my, mw, speed, spin_radius, color=color, zorder=zorder + 2)
    if ends:
        mark_ends(ax, (x[0], y[0]), (x[-1], y[-1]), color=color, zorder=zorder + 3)
    return line

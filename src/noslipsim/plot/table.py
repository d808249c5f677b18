"""Draw a billiard table: every element kind, and periodic scenes as a patch of cells.

Walls are drawn as lines with the side away from the table shaded (infinite
lines: each drawn only where it bounds the table, so the two walls of a wedge
stop at its vertex; the shade is opaque, so shades overlapping outside a
corner show no darker patch) or as plain curves (segments, arcs, containers); scatterers (circles
with the table outside) are filled discs.  A periodic scene is drawn as every
copy of its elements that meets the view window.  The element kinds and the
scene format are described in docs/scenes.md.
"""
from __future__ import annotations

import json
import math

import numpy as np
from matplotlib.collections import LineCollection, PatchCollection
from matplotlib.patches import Arc as ArcPatch
from matplotlib.patches import Circle as CirclePatch
from matplotlib.patches import Polygon

from .._engine.lattice import lattice_matrix
from ..outline import Disc, Wall
from ..scenes import Scene
from .style import SCATTERER_COLOR, SHADE_COLOR, WALL_COLOR

#: Relative margin around the elements when the window is chosen automatically.
AUTO_MARGIN = 0.05
#: At most this many lattice cells are drawn (a larger window is almost surely a mistake).
MAX_CELLS = 20_000


def scene_of(source):
    """The :class:`~noslipsim.Scene` behind a dataset, a JSON string, a mapping or a scene.

    Parameters
    ----------
    source : Scene, xarray.Dataset, xarray.DataArray, str or dict
        A dataset carrying the scene as JSON (its ``scene`` attribute, as
        written by :func:`noslipsim.simulate` and :func:`noslipsim.simulate_many`,
        or a 0-d ``scene`` variable of an orbit set), the JSON text itself,
        or the scene's mapping form (docs/scenes.md).

    Raises
    ------
    ValueError
        When no scene can be found or the scene does not validate.
    """
    if isinstance(source, Scene):
        return source
    if isinstance(source, dict):
        return Scene.from_dict(source)
    if isinstance(source, str):
        try:
            return Scene.from_dict(json.loads(source))
        except json.JSONDecodeError as err:
            raise ValueError(f"scene: not valid JSON ({err})") from None
    if hasattr(source, "attrs") and hasattr(source, "variables"):  # a Dataset
        if "scene" in source.variables and source["scene"].ndim == 0:
            return scene_of(str(source["scene"].values))
        if "scene" in source.attrs:
            return scene_of(source.attrs["scene"])
    elif hasattr(source, "attrs") and "scene" in source.attrs:
        return scene_of(source.attrs["scene"])
    raise ValueError(f"scene: expected a Scene, its JSON or a dataset with a 'scene' attribute, "
                     f"got {type(source).__name__}")


def check_window(window):
    """``window`` as finite floats ``(x0, x1, y0, y1)`` with ``x1 > x0`` and ``y1 > y0``, else ValueError."""
    try:
        x0, x1, y0, y1 = (float(v) for v in window)
    except (TypeError, ValueError):
        raise ValueError(f"window: expected (x0, x1, y0, y1), got {window!r}") from None
    if not all(map(math.isfinite, (x0, x1, y0, y1))) or not (x1 > x0 and y1 > y0):
        raise ValueError(f"window: expected finite (x0, x1, y0, y1) with x1 > x0 and y1 > y0, got {window!r}")
    return x0, x1, y0, y1


def auto_window(scene):
    """The bounding box ``(x0, x1, y0, y1)`` of a plain scene's elements, with a small margin.

    Raises
    ------
    ValueError
        For a scene with infinite lines or a lattice (no natural window).
    """
    if scene.lattice is not None or not all(e.bounded for e in scene.elements):
        raise ValueError("window: a scene with infinite lines or a lattice needs an explicit window "
                         "(x0, x1, y0, y1)")
    boxes = np.array([e.bbox() for e in scene.elements])
    x0, y0 = boxes[:, 0].min(), boxes[:, 1].min()
    x1, y1 = boxes[:, 2].max(), boxes[:, 3].max()
    m = AUTO_MARGIN * max(x1 - x0, y1 - y0)
    return x0 - m, x1 + m, y0 - m, y1 + m


def view_window(scene, points=None, *, cells=1, margin=0.1):
    """A window that shows the table of any scene, and ``points`` with it.

    Plain scenes show every finite element and the anchor point of every
    infinite line (``point`` in the scene file), so a floor under a peg is in
    view; a table of lines only shows a square of side ``2 * scene.scale``
    around their anchors.  Periodic scenes show cell 0 and ``cells`` cells on
    every side of it.  ``points`` (an orbit's path) are joined in.

    Parameters
    ----------
    scene : Scene
    points : (array_like, array_like), optional
        ``(x, y)`` to keep in view (non-finite values ignored).
    cells : int
        Lattice cells shown on each side of cell 0 (periodic scenes).
    margin : float
        Margin added on every side, relative to the larger side of the box.

    Returns
    -------
    (x0, x1, y0, y1)
    """
    scene = scene_of(scene)
    corners = []
    if scene.lattice is not None:
        A, _ = lattice_matrix(scene.lattice)
        k = int(cells)
        for n1 in (-k, k + 1):
            for n2 in (-k, k + 1):
                corners.append(A @ np.array([n1 - 0.5, n2 - 0.5]))
    else:
        for e in scene.elements:
            corners += e.view_points()
        if not any(e.bounded for e in scene.elements):
            c = np.mean(corners, axis=0)
            corners += [c - scene.scale, c + scene.scale] if scene.scale > 0 else [c - 1.0, c + 1.0]
    pts = np.array(corners, float).reshape(-1, 2)
    if points is not None:
        px, py = (np.asarray(a, float).ravel() for a in points)
        ok = np.isfinite(px) & np.isfinite(py)
        pts = np.concatenate([pts, np.c_[px[ok], py[ok]]])
    x0, y0 = pts.min(axis=0)
    x1, y1 = pts.max(axis=0)
    pad = margin * max(x1 - x0, y1 - y0, 1e-9 * max(abs(x0), abs(y0), 1.0))
    return float(x0 - pad), float(x1 + pad), float(y0 - pad), float(y1 + pad)


def _clip_half_plane(box, point, normal):
    """The part of the window on the wall side of a line (``(p - point) . normal <= 0``), as a polygon."""
    x0, x1, y0, y1 = box
    poly = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]
    side = [(px - point[0]) * normal[0] + (py - point[1]) * normal[1] for px, py in poly]
    out = []
    for i in range(4):
        p, q = poly[i], poly[(i + 1) % 4]
        sp, sq = side[i], side[(i + 1) % 4]
        if sp <= 0:
            out.append(p)
        if (sp < 0 < sq) or (sq < 0 < sp):
            f = sp / (sp - sq)
            out.append((p[0] + f * (q[0] - p[0]), p[1] + f * (q[1] - p[1])))
    return out


def _clip_line(box, point, direction):
    """The chord of the line ``point + s direction`` inside the window (Liang-Barsky), or None."""
    x0, x1, y0, y1 = box
    lo, hi = -math.inf, math.inf
    for p, d, a, b in ((point[0], direction[0], x0, x1), (point[1], direction[1], y0, y1)):
        if d == 0.0:
            if not a <= p <= b:
                return None
            continue
        s0, s1 = sorted(((a - p) / d, (b - p) / d))
        lo, hi = max(lo, s0), min(hi, s1)
    if not lo < hi:
        return None
    return [(point[0] + lo * direction[0], point[1] + lo * direction[1]),
            (point[0] + hi * direction[0], point[1] + hi * direction[1])]


def _clip_to_walls(seg, lines, own):
    """The part of chord ``seg`` of line ``own`` on the table side of every other infinite line, or None.

    A table bounded by infinite lines is the intersection of their half-planes
    (``(p - point) . normal >= 0`` for each), so a line is part of the
    boundary only where every other line's half-plane holds: the walls of a
    wedge end at its vertex instead of crossing it.
    """
    (ax_, ay_), (bx, by) = seg
    lo, hi = 0.0, 1.0
    for k, (q, n) in enumerate(lines):
        if k == own:
            continue
        fa = (ax_ - q[0]) * n[0] + (ay_ - q[1]) * n[1]
        fb = (bx - q[0]) * n[0] + (by - q[1]) * n[1]
        if fa < 0 and fb < 0:
            return None
        if fa < 0 or fb < 0:
            s = fa / (fa - fb)
            lo, hi = (max(lo, s), hi) if fa < 0 else (lo, min(hi, s))
    if not lo < hi:
        return None
    return [(ax_ + lo * (bx - ax_), ay_ + lo * (by - ay_)), (ax_ + hi * (bx - ax_), ay_ + hi * (by - ay_))]


def _wall_chords(scene, box, copies):
    """For every infinite line among ``copies``: its shade polygon and its visible boundary chord (or None)."""
    lines = []
    for e, dx, dy in copies:
        plane = e.half_plane()
        if plane is not None:
            (px, py), n = plane
            lines.append(((px + dx, py + dy), n))
    out = []
    for k, (p, n) in enumerate(lines):
        seg = _clip_line(box, p, (-n[1], n[0]))
        if seg is not None and scene.lattice is None:   # a lattice repeats the lines: no common inside
            seg = _clip_to_walls(seg, lines, k)
        out.append((_clip_half_plane(box, p, n), seg))
    return out


def _copies(scene, box):
    """``(element, dx, dy)`` for every copy of every element whose bounding box meets the window.

    A bounded lattice (``scene.top``) has no copy whose centre lies above its top."""
    if scene.lattice is None:
        return [(e, 0.0, 0.0) for e in scene.elements]
    A, B = lattice_matrix(scene.lattice)
    x0, x1, y0, y1 = box
    out = []
    for e in scene.elements:
        ex0, ey0, ex1, ey1 = e.bbox()
        # translations t with the element box shifted by t meeting the window
        corners = np.array([[x0 - ex1, y0 - ey1], [x1 - ex0, y0 - ey1], [x0 - ex1, y1 - ey0], [x1 - ex0, y1 - ey0]])
        lat = corners @ B.T
        lo, hi = np.floor(lat.min(axis=0)).astype(int), np.ceil(lat.max(axis=0)).astype(int)
        if (hi[0] - lo[0] + 1) * (hi[1] - lo[1] + 1) > MAX_CELLS:
            raise ValueError(f"window: {box} spans more than {MAX_CELLS} lattice cells")
        for n1 in range(lo[0], hi[0] + 1):
            for n2 in range(lo[1], hi[1] + 1):
                dx, dy = A @ np.array([n1, n2], float)
                if scene.top is not None and e.center[1] + dy > scene.top:
                    continue
                if ex1 + dx >= x0 and ex0 + dx <= x1 and ey1 + dy >= y0 and ey0 + dy <= y1:
                    out.append((e, float(dx), float(dy)))
    return out


def draw_table(ax, scene, window=None, *, wall_color=WALL_COLOR, scatterer_color=SCATTERER_COLOR,
               linewidth=1.0, zorder=1):
    """Draw a table on ``ax`` and set the view to ``window`` with equal aspect.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    scene : Scene, xarray.Dataset or str
        The scene, or anything :func:`scene_of` accepts (a dataset's ``scene``
        attribute rebuilds it).
    window : (x0, x1, y0, y1), optional
        The region shown.  Default: the elements' bounding box, for plain
        scenes without infinite lines; required otherwise.
    wall_color, scatterer_color : color
        Walls and the inside of scatterers.
    linewidth : float
        Width of walls and outlines (points).

    Returns
    -------
    tuple
        ``(x0, x1, y0, y1)``, the window drawn.

    Raises
    ------
    ValueError
        For a malformed window, a scene that cannot be rebuilt, or a missing
        window where one is needed.
    """
    scene = scene_of(scene)
    box = auto_window(scene) if window is None else check_window(window)
    x0, x1, y0, y1 = box
    discs, curves, walls, shades = [], [], [], []
    copies = _copies(scene, box)
    for shade, seg in _wall_chords(scene, box, copies):
        if len(shade) >= 3:
            shades.append(Polygon(shade, closed=True))
        if seg is not None:
            walls.append(seg)
    for part in (part for e, dx, dy in copies for part in e.outline(dx, dy)):
        if isinstance(part, Wall):
            walls.append(part.points)
        elif isinstance(part, Disc):
            discs.append(CirclePatch(part.center, part.radius))
        else:
            curves.append(_curve_patch(part))
    if shades:
        ax.add_collection(PatchCollection(shades, facecolor=SHADE_COLOR, edgecolor="none", zorder=zorder))
    if discs:
        ax.add_collection(PatchCollection(discs, facecolor=scatterer_color, edgecolor=wall_color,
                                          linewidth=linewidth, zorder=zorder))
    for patch in curves:
        patch.set(edgecolor=wall_color, linewidth=linewidth, zorder=zorder)
        ax.add_patch(patch)
    if walls:
        ax.add_collection(LineCollection(walls, colors=wall_color, linewidths=linewidth, zorder=zorder,
                                         capstyle="round"))
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set_aspect("equal")
    return box


def _curve_patch(curve):
    """The matplotlib patch of an unfilled :class:`noslipsim.outline.Curve`: a full circle or an arc of one."""
    if curve.theta1 is None:
        return CirclePatch(curve.center, curve.radius, fill=False)
    return ArcPatch(curve.center, 2 * curve.radius, 2 * curve.radius, theta1=math.degrees(curve.theta0),
                    theta2=math.degrees(curve.theta1))


#: Points per full turn when a circle or an arc is given as a polyline (:func:`table_shapes`).
CURVE_POINTS = 180


def table_shapes(scene, window):
    """The table in ``window`` as plain polylines, for drawing libraries other than matplotlib.

    Parameters
    ----------
    scene : Scene
    window : (x0, x1, y0, y1)
        The region shown; a periodic scene gives every copy meeting it.

    Returns
    -------
    dict
        ``walls``: list of ``(xs, ys)`` polylines (segments, arcs, containers,
        the chord of each infinite line where it bounds the table); ``discs``: list of
        ``(x, y, r)`` scatterers (the table outside them); ``shades``: list of
        ``(xs, ys)`` polygons, the part of the window behind each infinite line.
    """
    scene = scene_of(scene)
    box = check_window(window)
    walls, discs, shades = [], [], []
    copies = _copies(scene, box)
    for shade, seg in _wall_chords(scene, box, copies):
        if len(shade) >= 3:
            shades.append(([q[0] for q in shade], [q[1] for q in shade]))
        if seg is not None:
            walls.append(([seg[0][0], seg[1][0]], [seg[0][1], seg[1][1]]))
    for part in (part for e, dx, dy in copies for part in e.outline(dx, dy)):
        if isinstance(part, Wall):
            walls.append(([p[0] for p in part.points], [p[1] for p in part.points]))
        elif isinstance(part, Disc):
            discs.append((*part.center, part.radius))
        else:  # a container circle or an arc
            walls.append(part.polyline(CURVE_POINTS))
    return {"walls": walls, "discs": discs, "shades": shades}

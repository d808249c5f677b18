"""One look for every figure: the style file, the colours that carry a meaning, equal panels.

Every figure of the paper (workflow/scripts/fig*.py) and ``noslipsim plot``
draw with these, never with colours or sizes of their own:

- :data:`LAW_COLORS` / :func:`law_color`: one colour per collision law
  (specular blue, no-slip vermilion, Okabe-Ito), the same in every figure:
  a curve in one of these colours *is* an orbit or a quantity of that law;
- :data:`SERIES_COLORS`: the style's colour cycle, for curves that are *not*
  a law (two radii, several launch angles of one law); it leaves out the two
  law colours, so a series is never mistaken for a law;
- :func:`orbit_colors`: many distinct colours, only where orbits are the
  subject (phase portraits, one colour per orbit); :data:`SEA_COLOR` is the
  grey background of the chaotic orbits under them;
- :data:`WALL_COLOR`, :data:`SCATTERER_COLOR`, :data:`SHADE_COLOR`: tables
  (walls, disks, the opaque shade behind an infinite wall);
- :data:`REFERENCE_COLOR`: theory and the paper's values (lines to compare
  against);
- :func:`equal_windows`, :func:`equal_panels`: windows of one shape (or one
  size) for the panels of a figure, so that panels drawn to scale have equal
  boxes and their titles line up;
- :func:`frame_legend`: a framed legend placed off the data.
"""
from __future__ import annotations

from pathlib import Path

import matplotlib
import numpy as np
from matplotlib import colormaps

#: The project's matplotlib style file (fonts, sizes, colour cycle, layout, PNG resolution).
STYLE = Path(__file__).with_name("noslipsim.mplstyle")

#: Colour of each collision law, the same in every figure (Okabe-Ito blue and vermilion).
LAW_COLORS = {"specular": "#0072B2", "no-slip": "#D55E00"}

#: Colours for series that are not a law (the style's colour cycle; no law colour among them).
SERIES_COLORS = ("#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#000000", "#F0E442")

#: Colours of tables: walls, scatterers, the outside of a wall (half-planes, shaded).
WALL_COLOR = "0.25"
SCATTERER_COLOR = "0.75"
SHADE_COLOR = "0.87"

#: Colour of the chaotic sea under the regular orbits of a portrait.
SEA_COLOR = "0.72"

#: Colour of theory curves and of the paper's values drawn for comparison.
REFERENCE_COLOR = "k"

#: Qualitative colour maps whose colours :func:`orbit_colors` takes in turn (60 colours).
PALETTES = ("tab20", "tab20b", "tab20c")


def use_style():
    """Apply the project's style (:data:`STYLE`) to every figure made afterwards in this process."""
    matplotlib.style.use(STYLE)


def style_context():
    """Context manager applying the project's style inside a ``with`` block only."""
    return matplotlib.style.context(STYLE)


def law_color(law):
    """The colour of a collision law (``'specular'`` or ``'no-slip'``).

    Raises
    ------
    ValueError
        For an unknown law.
    """
    if law not in LAW_COLORS:
        raise ValueError(f"law: expected one of {sorted(LAW_COLORS)}, got {law!r}")
    return LAW_COLORS[law]


def orbit_colors(n):
    """``n`` distinct RGBA colours (``tab20``, then ``tab20b``, ``tab20c``; cycling beyond 60).

    Only for figures whose subject is many orbits (one colour per orbit in a
    portrait); a figure comparing the laws uses :func:`law_color`.

    Parameters
    ----------
    n : int
        Number of colours (>= 0).

    Returns
    -------
    numpy.ndarray (n, 4)
    """
    if isinstance(n, bool) or int(n) != n or n < 0:
        raise ValueError(f"n: expected a non-negative integer, got {n!r}")
    base = np.concatenate([colormaps[name](np.arange(20)) for name in PALETTES])
    # tab20 pairs a dark and a light shade of each hue: take the dark ones first, then the light
    order = np.concatenate([np.arange(0, 60, 2), np.arange(1, 60, 2)])
    return base[order][np.arange(int(n)) % len(base)]


def equal_windows(windows, *, same_scale=False, aspect=None, margin=0.0):
    """Windows ``(x0, x1, y0, y1)`` widened so that panels drawn from them have equal boxes.

    With an equal aspect ratio (tables drawn to scale) a panel's box has the
    shape of its window, so windows of different shapes give boxes of
    different sizes and titles at different heights.  Compute the windows
    first, pass them here, then draw each panel in its returned window (a
    table's shaded walls then fill the whole box).

    Parameters
    ----------
    windows : sequence of (x0, x1, y0, y1)
        Each panel's content (x0 < x1, y0 < y1).
    same_scale : bool
        ``True``: every window gets the largest width and the largest height
        (one scale for all panels).  ``False``: each window keeps its scale
        and grows in one direction to the common shape ``aspect``.
    aspect : float, optional
        The common shape, height / width (> 0); default the tallest window's.
    margin : float
        Extra room on each side, as a share of the window's size (>= 0).

    Returns
    -------
    list of (float, float, float, float)
        The windows, each centred on its content.
    """
    boxes = [tuple(float(v) for v in w) for w in windows]
    if not boxes:
        raise ValueError("windows: expected at least one window, got none")
    for w in boxes:
        if len(w) != 4 or not all(np.isfinite(w)) or not (w[0] < w[1] and w[2] < w[3]):
            raise ValueError(f"windows: expected (x0, x1, y0, y1) with x0 < x1 and y0 < y1, got {w}")
    if not (np.isfinite(margin) and margin >= 0):
        raise ValueError(f"margin: expected a finite number >= 0, got {margin!r}")
    if aspect is None:
        aspect = max((y1 - y0) / (x1 - x0) for x0, x1, y0, y1 in boxes)
    elif not (np.isfinite(aspect) and aspect > 0):
        raise ValueError(f"aspect: expected a finite number > 0, got {aspect!r}")
    sizes = [(x1 - x0, y1 - y0) for x0, x1, y0, y1 in boxes]
    if same_scale:
        common = (max(w for w, _ in sizes), max(h for _, h in sizes))
        sizes = [common] * len(boxes)
    else:
        sizes = [(max(w, h / aspect), max(h, w * aspect)) for w, h in sizes]
    out = []
    for (x0, x1, y0, y1), (w, h) in zip(boxes, sizes):
        cx, cy, w, h = 0.5 * (x0 + x1), 0.5 * (y0 + y1), w * (1 + 2 * margin), h * (1 + 2 * margin)
        out.append((cx - 0.5 * w, cx + 0.5 * w, cy - 0.5 * h, cy + 0.5 * h))
    return out


def equal_panels(axes, *, same_scale=True, margin=0.04):
    """Give drawn panels equal boxes: :func:`equal_windows` applied to their current limits.

    For panels whose content stops inside the window (orbits, polygons); a
    table with shaded walls must be drawn in windows from
    :func:`equal_windows` instead, or its shade ends inside the box.

    Parameters
    ----------
    axes : sequence of matplotlib.axes.Axes
        The panels, already drawn (their current limits are the content).
    same_scale, margin
        As for :func:`equal_windows`.

    Returns
    -------
    list of (float, float, float, float)
        The windows set.
    """
    axes = list(np.ravel(axes))
    if not axes:
        raise ValueError("axes: expected at least one panel, got none")
    limits = [(*sorted(ax.get_xlim()), *sorted(ax.get_ylim())) for ax in axes]
    windows = equal_windows(limits, same_scale=same_scale, margin=margin)
    for ax, (x0, x1, y0, y1) in zip(axes, windows):
        ax.set_xlim(x0, x1)
        ax.set_ylim(y0, y1)
    return windows


def frame_legend(target, *, outside="below", ncol=None, **kwargs):
    """A framed legend placed outside the data (below or right of the axes).

    Parameters
    ----------
    target : matplotlib.axes.Axes or matplotlib.figure.Figure
        Where the handles come from (an axes: its handles; a figure: every
        axes' handles, one legend for the figure).
    outside : {'below', 'right'}
        Side of the axes (or figure) the legend goes to.
    ncol : int, optional
        Columns; default all handles in one row below, one column right.
    **kwargs
        Passed to :meth:`~matplotlib.axes.Axes.legend`.

    Returns
    -------
    matplotlib.legend.Legend
    """
    if outside not in ("below", "right"):
        raise ValueError(f"outside: expected 'below' or 'right', got {outside!r}")
    if isinstance(target, matplotlib.figure.Figure):
        handles, labels = [], []
        for ax in target.axes:
            h, lab = ax.get_legend_handles_labels()
            handles += h
            labels += lab
    else:
        handles, labels = target.get_legend_handles_labels()
    if not handles:
        raise ValueError("frame_legend: no labelled artist to put in a legend")
    if ncol is None:
        ncol = len(handles) if outside == "below" else 1
    if outside == "below":
        place = dict(loc="upper center", bbox_to_anchor=(0.5, -0.02 if isinstance(target, matplotlib.figure.Figure)
                                                          else -0.18))
    else:
        place = dict(loc="center left", bbox_to_anchor=(1.01, 0.5))
    if isinstance(target, matplotlib.figure.Figure):
        place["loc"] = "outside lower center" if outside == "below" else "outside right center"
        place.pop("bbox_to_anchor")
    options = dict(frameon=True, framealpha=1.0, edgecolor="0.6", fancybox=False, ncol=ncol, **place)
    options.update(kwargs)
    return target.legend(handles, labels, **options)

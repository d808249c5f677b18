"""
The four element kinds of a scene file
======================================

Each panel is one scene built from its scene-file mapping (``Scene.from_dict``,
the same as a YAML file), with the table shaded where :meth:`noslipsim.Scene.contains`
says a start may lie. Arrows: the ``normal`` a ``line`` is given (into the
table), the direction ``p0 -> p1`` of a segment, the counter-clockwise sweep
``theta0 -> theta1`` of an arc, and in red the outward normal ``n`` that the
collision laws use (out of the table, see the conventions page).
"""
import math

import matplotlib.pyplot as plt
import numpy as np

import noslipsim as ns
from noslipsim import plot

plot.use_style()
SCENES = {
    "line: point [0, 0], normal [0.3, 1]": [{"type": "line", "point": [0, 0], "normal": [0.3, 1]}],
    "segment: p0 [-1, 0], p1 [1, 0], side left": [{"type": "segment", "p0": [-1, 0], "p1": [1, 0], "side": "left"}],
    "segment: the same, side right": [{"type": "segment", "p0": [-1, 0], "p1": [1, 0], "side": "right"}],
    "circle: radius 0.8, side outside": [{"type": "circle", "center": [0, 0], "radius": 0.8, "side": "outside"}],
    "circle: radius 1.2, side inside": [{"type": "circle", "center": [0, 0], "radius": 1.2, "side": "inside"}],
    "arc: theta0 -0.5, theta1 2.5, side inside": [
        {"type": "arc", "center": [0, 0], "radius": 1.2, "theta0": -0.5, "theta1": 2.5, "side": "inside"}],
}
WINDOW = (-1.6, 1.6, -1.6, 1.6)
xs = np.linspace(WINDOW[0], WINDOW[1], 241)
grid = np.stack(np.meshgrid(xs, xs), axis=-1)


def arrow(ax, start, vector, color="k"):
    ax.annotate("", xy=(start[0] + vector[0], start[1] + vector[1]), xytext=start,
                arrowprops=dict(arrowstyle="-|>", color=color, lw=1.2), zorder=6)


fig, axes = plt.subplots(2, 3, figsize=(9, 6.4))
for ax, (title, elements) in zip(axes.ravel(), SCENES.items()):
    scene = ns.Scene.from_dict({"elements": elements})
    ax.contourf(xs, xs, scene.contains(grid).astype(float), levels=[0.5, 1.5], colors=["#cfe3f3"])
    plot.draw_table(ax, scene, WINDOW)
    e = scene.elements[0]
    if isinstance(e, ns.Line):
        arrow(ax, e.point, 0.6 * np.array(e.normal))                       # given normal: into the table
        arrow(ax, e.point, -0.6 * np.array(e.normal), color="tab:red")     # outward n
    elif isinstance(e, ns.Segment):
        arrow(ax, (-1, 0), (1.0, 0))                                       # p0 -> p1
        sgn = 1 if e.side == "left" else -1
        arrow(ax, (0.5, 0), (0, -0.6 * sgn), color="tab:red")              # outward n
    elif isinstance(e, ns.Circle):
        sgn = 1 if e.side == "outside" else -1
        p = np.array([math.cos(0.8), math.sin(0.8)]) * e.radius
        arrow(ax, p, -0.5 * sgn * p / e.radius, color="tab:red")          # outward n: into the disk for a scatterer
    else:
        th = np.linspace(e.theta0, e.theta1, 50)
        ax.plot(0.9 * np.cos(th[:-3]), 0.9 * np.sin(th[:-3]), color="k", lw=0.8)
        arrow(ax, (0.9 * math.cos(th[-4]), 0.9 * math.sin(th[-4])),
              (0.9 * (math.cos(th[-1]) - math.cos(th[-4])), 0.9 * (math.sin(th[-1]) - math.sin(th[-4]))))
        p = np.array([math.cos(1.0), math.sin(1.0)]) * e.radius
        arrow(ax, p, 0.4 * p / e.radius, color="tab:red")                  # outward n: out of the container
    ax.set_title(title, fontsize="small")
    ax.set_xticks([])
    ax.set_yticks([])

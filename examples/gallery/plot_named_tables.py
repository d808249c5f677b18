"""
The named tables
================

Every constructor of :mod:`noslipsim.tables`, with its default arguments (a
wedge of half-angle 0.6, two disks in a box, a polygon with a disk), drawn by
:func:`noslipsim.plot.draw_table` with the table shaded where
:meth:`noslipsim.Scene.contains` holds. Periodic tables show a patch of cells;
the element order (the ``element`` index of every collision record) is given
in each constructor's documentation.
"""
import matplotlib.pyplot as plt
import numpy as np

from noslipsim import plot, tables

plot.use_style()
TABLES = {
    "half_plane()": (tables.half_plane(), (-2, 2, -0.5, 2)),
    "wedge(0.6)": (tables.wedge(0.6), (-2, 2, -0.5, 2.5)),
    "wedge(0.6, opening='down')": (tables.wedge(0.6, opening="down"), (-2, 2, -2.5, 0.5)),
    "channel()": (tables.channel(), (-1.5, 1.5, -0.5, 1.5)),
    "polygon(..., disks=...)": (tables.polygon([(0, 0), (2, -0.3), (2.4, 1.2), (1, 2), (-0.2, 1.1)],
                                               disks=[(1.1, 0.8, 0.3)]), None),
    "regular_polygon(6)": (tables.regular_polygon(6), None),
    "rectangle(2, 1, disks=...)": (tables.rectangle(2.0, 1.0, disks=[(1.0, 0.5, 0.2)]), None),
    "two_disks(0.4, box=(4, 2))": (tables.two_disks(0.4, box=(4, 2)), None),
    "lemon()": (tables.lemon(), None),
    "stadium()": (tables.stadium(), None),
    "sinai_torus()": (tables.sinai_torus(), (-1.5, 1.5, -1.5, 1.5)),
    "hex_lorentz_cell()": (tables.hex_lorentz_cell(), (-1.5, 1.5, -1.5, 1.5)),
    "galton_board()": (tables.galton_board(), (-4, 4, -3.5, 2)),
}
fig, axes = plt.subplots(3, 5, figsize=(11, 6.8))
for ax, (title, (scene, window)) in zip(axes.ravel(), TABLES.items()):
    window = plot.auto_window(scene) if window is None else window
    xs = np.linspace(window[0], window[1], 161)
    ys = np.linspace(window[2], window[3], 161)
    inside = scene.contains(np.stack(np.meshgrid(xs, ys), axis=-1))
    ax.contourf(xs, ys, inside.astype(float), levels=[0.5, 1.5], colors=["#cfe3f3"])
    plot.draw_table(ax, scene, window)
    ax.set_title(title, fontsize="small")
    ax.set_xticks([])
    ax.set_yticks([])
for ax in axes.ravel()[len(TABLES):]:
    ax.axis("off")

"""
A lattice: unfolded positions and cells
=======================================

A periodic scene repeats its elements on a lattice; positions are reported
*unfolded* in the plane, with the integer indices ``cell_a1, cell_a2`` of the
cell that holds them (each cell is centred on a lattice point). One no-slip
orbit of the Sinai lattice (a disk of radius 0.3 on the unit square lattice),
drawn in the plane and coloured by cell; the right panel folds the same
collisions back onto one cell by subtracting ``cell_a1 a1 + cell_a2 a2``.
"""
import matplotlib.pyplot as plt
import numpy as np

import noslipsim as ns
from noslipsim import plot, tables

plot.use_style()
scene = tables.sinai_torus(0.3)
orbit = ns.simulate(scene, position=(0.5, 0.5), velocity=(1.0, 0.37), max_collisions=60)
cells = np.c_[orbit.cell_a1, orbit.cell_a2]

fig, (ax, ax2) = plt.subplots(1, 2, figsize=(8.5, 4.2), width_ratios=[1.6, 1])
x, y = plot.orbit_path(orbit)
window = (x.min() - 0.6, x.max() + 0.6, y.min() - 0.6, y.max() + 0.6)
plot.draw_table(ax, scene, window)
plot.draw_orbit(ax, orbit, color="0.4", linewidth=0.6)
_, code = np.unique(cells, axis=0, return_inverse=True)
ax.scatter(orbit.x, orbit.y, c=code.ravel() % 20, cmap="tab20", vmin=0, vmax=19, s=14, zorder=6)
ax.set_title(f"unfolded: {len(np.unique(cells, axis=0))} cells visited", fontsize="small")

a1, a2 = np.array(scene.lattice["a1"]), np.array(scene.lattice["a2"])
folded = np.c_[orbit.x, orbit.y] - cells[:, :1] * a1 - cells[:, 1:] * a2
plot.draw_table(ax2, scene, (-0.5, 0.5, -0.5, 0.5))
ax2.scatter(folded[:, 0], folded[:, 1], c=code.ravel() % 20, cmap="tab20", vmin=0, vmax=19, s=14, zorder=6)
ax2.set_title("folded onto cell (0, 0)", fontsize="small")
print("first cells:", cells[:6].tolist())
print("largest distance of a folded collision from the disk:", float(np.abs(np.hypot(*folded.T) - 0.3).max()))

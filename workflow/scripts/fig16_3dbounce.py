"""Figure 16: a no-slip sphere bouncing on a plane in 3D: drift along e1, 2-periodic along e2."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from noslipsim import plot

VIEW_ELEVATION, VIEW_TURN = 22.0, 30.0  # degrees

ds = plot.load_figure_data(snakemake.input.sphere)
x, y, z = plot.sphere_path(ds)
e1, e2 = ds.e1.values[:2], ds.e2.values[:2]
color = plot.law_color("no-slip")
plot.use_style()
fig = plt.figure(figsize=(6.5, 3.2))
grid = fig.add_gridspec(2, 2, width_ratios=[1.1, 1.0])
ax = fig.add_subplot(grid[:, 0], projection="3d")
ax.plot(x, y, z, color=color, linewidth=0.8)
ax.plot(x, y, np.zeros_like(z), color="0.7", linewidth=0.5)            # shadow on the plane
q = ds.position.values
ax.scatter(q[:, 0], q[:, 1], q[:, 2], color=color, s=4, depthshade=False)
mid = q.mean(axis=0)
length = 0.25 * float(np.ptp(x) + np.ptp(y))
for e, name in ((e1, "$e_1$"), (e2, "$e_2$")):
    plot.draw_arrow3d(ax, (mid[0], mid[1], 0.0), (*(length * e), 0.0))   # quiver's head came off its shaft
    ax.text(mid[0] + 1.15 * length * e[0], mid[1] + 1.15 * length * e[1], 0, name)
ax.set_box_aspect((np.ptp(x), np.ptp(y), np.ptp(z)))                 # equal scales: e1 and e2 look orthogonal
# look from the side of -e2, turned a little: the drift e1 runs across the picture
ax.view_init(elev=VIEW_ELEVATION, azim=np.degrees(np.arctan2(-e2[1], -e2[0])) + VIEW_TURN)
ax.set_xlabel("x")
ax.set_ylabel("y")
ax.set_zlabel("z", labelpad=-8)
ax.set_zticks([0.0, round(float(z.max()), 1)])
ax.locator_params(axis="x", nbins=3)
ax.locator_params(axis="y", nbins=3)
ax.tick_params(labelsize=7.5, pad=0)    # the same size as the 2D panels' ticks: readable in print
ax.set_title(f"$\\gamma^2 = {float(ds.attrs['gamma']) ** 2:.2g}$, {ds.sizes['collision']} bounces")
drift = float(np.hypot(*ds.drift.values[:2]))
for row, (e, name, note) in enumerate(((e1, "$e_1$", f"drift {drift:.3g} per two bounces"),
                                       (e2, "$e_2$", "2-periodic"))):
    ax2 = fig.add_subplot(grid[row, 1])
    ax2.plot(x * e[0] + y * e[1], z, color=color, linewidth=0.8)
    ax2.axhline(0.0, color="0.25", linewidth=1.0)
    ax2.set_xlabel(f"position along {name}")
    ax2.set_ylabel("z")
    ax2.set_title(f"along {name}: {note}")
plot.save_figure(fig, snakemake.output.pdf)

"""Figure 10: specular lemon (Birkhoff), no-slip Sinai torus in the reduced 3D portrait and its velocity portrait."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from noslipsim import plot
from noslipsim.analysis import classify_regular

ds = classify_regular(plot.load_figure_data(snakemake.input.portraits), snakemake.params.threshold)
lemon, sinai = ds.sel(table="lemon"), ds.sel(table="sinai")
gamma = float(sinai.gamma)

plot.use_style()
fig = plt.figure(figsize=(6.5, 2.75))
grid = fig.add_gridspec(1, 3, width_ratios=[1.0, 1.35, 1.0], wspace=0.08)
left = fig.add_subplot(grid[0])
centre = fig.add_subplot(grid[1], projection="3d")
right = fig.add_subplot(grid[2])

plot.draw_birkhoff(left, lemon, lemon.regular, size=0.15)
left.set_title(f"(a) specular lemon\nregular {float(lemon.regular.mean()):.0%}", fontsize=8)
plot.draw_reduced_portrait(centre, sinai, sinai.regular, size=0.15)
centre.view_init(elev=18, azim=-62)
centre.set_box_aspect((1.7, 1.0, 1.0), zoom=0.85)
centre.set(xticks=range(int(float(sinai.s_boundary.max())) + 1), yticks=[-1, 0, 1], zticks=[-1, 0, 1])
centre.tick_params(labelsize=7, pad=-1)    # readable in print; the labels below stay clear of them
for axis, pad in ((centre.xaxis, -2), (centre.yaxis, -3), (centre.zaxis, -9)):
    axis.labelpad = pad
centre.set_title(f"(b) no-slip Sinai torus, $\\gamma$ = {gamma:.3g}:\nreduced portrait (ends identified)", fontsize=8)
plot.draw_layered_portrait(right, sinai, sinai.regular, size=0.15)
right.set_ylabel("$w$", labelpad=-3)
right.set_title(f"(c) its velocity portrait\nregular {float(sinai.regular.mean()):.0%}", fontsize=8)
fig.align_titles()
plot.save_figure(fig, snakemake.output.pdf)  # writes the .pdf and the .png beside it

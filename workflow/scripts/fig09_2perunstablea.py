"""Figure 9: perturbed path-reversing 2-periodic wedge orbits. Top: the perturbed orbit (grey) with the periodic
orbit over it; bottom: its returns to the launch wall in (s, w), the periodic point marked."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import json

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.ticker import MaxNLocator

from noslipsim import plot

MARGIN = 0.1  # share of the perturbed orbit's extent shown around it
LAUNCH_WALL = 0  # q0 is on the left wall (element 0)

ds = plot.load_figure_data(snakemake.input.orbits)
n = ds.sizes["orbit"] // 2
plot.use_style()
fig, axes = plt.subplots(2, n, figsize=(6.5, 3.9), height_ratios=[1.0, 1.0], squeeze=False)
windows = []
for j in range(n):
    x, y = plot.orbit_path(ds.isel(orbit=n + j))
    x, y = np.append(x, 0.0), np.append(y, 0.0)   # the vertex (origin) stays in view
    pad = MARGIN * max(np.ptp(x), np.ptp(y))
    half = max(np.abs(x).max(), 0.5 * np.ptp(y)) + pad
    windows.append((-half, half, y.min() - pad, y.max() + pad))
windows = plot.equal_windows(windows)  # one box shape for the top row: equal panels, titles in line
for j in range(n):
    periodic, perturbed = ds.isel(orbit=j), ds.isel(orbit=n + j)
    top = axes[0, j]
    plot.draw_table(top, periodic, windows[j])
    plot.draw_orbit(top, perturbed, color="0.55", linewidth=0.15, ends=False)
    plot.draw_orbit(top, periodic, linewidth=1.0, ends=False, zorder=3)
    top.set_xticks([])
    top.set_yticks([])
    opening = " (opening down)" if str(periodic.opening.values) == "down" else ""
    top.set_title(f"$\\theta$ = {float(periodic.theta):g}{opening}\n{periodic.linear_kind.values}, "
                  f"$\\lambda + 1/\\lambda$ = {float(periodic.eigen_sum):.3g}", fontsize=7)
    bottom = axes[1, j]
    plot.draw_return_points(bottom, perturbed, LAUNCH_WALL, fixed=periodic, size=1.5)
    end = "" if str(perturbed.stop_reason.values) == "max_collisions" else f", {perturbed.stop_reason.values}"
    bottom.set_title(f"{int(perturbed.n_collisions)} collisions{end}", fontsize=7.5)
    bottom.xaxis.set_major_locator(MaxNLocator(2))
    bottom.set_xlabel("$s$ (launch wall)")
    if j:
        bottom.set_ylabel("")
angle = json.loads(ds.attrs["perturbation"])["angle"]
fig.suptitle(f"velocity turned by {angle:g} rad at the start; returns to the launch wall below", fontsize=8)
plot.save_figure(fig, snakemake.output.pdf)

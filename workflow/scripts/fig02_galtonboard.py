"""Figure 2: Galton-board orbits from one start for gamma = 0 (specular), 1/sqrt 2 and 3; dots at start and end."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from noslipsim import plot

MARGIN = 2.0  # board shown around the orbits (lengths)
ZOOM_BELOW = 4.0  # an orbit smaller than this (lengths) gets a zoomed inset

ds = plot.load_figure_data(snakemake.input.orbits)
paths = [plot.orbit_path(ds.isel(orbit=i)) for i in range(ds.sizes["orbit"])]
x0 = min(x.min() for x, _ in paths) - MARGIN
x1 = max(x.max() for x, _ in paths) + MARGIN
bottom = ds.attrs["terminal_level"]
highest = max(ds.attrs["start"][1], max(y.max() for _, y in paths))
window = (x0, x1, bottom - MARGIN, highest + MARGIN)

n = ds.sizes["orbit"]
aspect = (window[3] - window[2]) / (window[1] - window[0])
plot.use_style()
fig, axes = plt.subplots(1, n, figsize=(6.5, 6.5 / n * aspect + 0.9), sharey=True)
for ax, i in zip(np.atleast_1d(axes), range(n)):
    orbit = ds.isel(orbit=i)
    plot.draw_table(ax, orbit, window, wall_color="0.55", linewidth=0.3)
    ax.axhline(bottom, color="k", linestyle="--", linewidth=0.6)
    plot.draw_orbit(ax, orbit, linewidth=0.5)
    x, y = paths[i]
    if np.ptp(x) < ZOOM_BELOW and np.ptp(y) < ZOOM_BELOW:  # a held orbit: zoom on it
        inset = ax.inset_axes([0.45, 0.05, 0.5, 0.5])
        cx, cy = (x.min() + x.max()) / 2, (y.min() + y.max()) / 2
        half = 0.6 * max(np.ptp(x), np.ptp(y)) + 0.5
        plot.draw_table(inset, orbit, (cx - half, cx + half, cy - half, cy + half), wall_color="0.55", linewidth=0.3)
        plot.draw_orbit(inset, orbit, linewidth=0.3)
        inset.set(xticks=[], yticks=[])
        ax.indicate_inset_zoom(inset, edgecolor="k", linewidth=0.5)
    g = float(orbit.gamma)
    name = "specular, $\\gamma = 0$" if str(orbit.law.values) == "specular" else f"no-slip, $\\gamma = {g:.3g}$"
    arrived = str(orbit.stop_reason.values) == "stop_below"
    fate = f"arrived at t = {float(orbit.t_final):.0f}" if arrived else f"not arrived by t = {float(orbit.t_final):.0f}"
    ax.set_title(f"{name}\n{fate}")
    ax.set_xlabel("x")
axes[0].set_ylabel("y")
plot.save_figure(fig, snakemake.output.pdf)  # writes the .pdf and the .png beside it

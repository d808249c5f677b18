"""Figure 5: the no-slip ball on a floor: 2-periodic (top left), back and forth with drift
(top right), steady drift (bottom)."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from noslipsim import plot

MARGIN = 0.25        # floor shown around each orbit (lengths)
SPIN_RADIUS = 0.05   # drawn particle radius at the middle of each flight
PERIODIC_TOL = 1e-9  # a drift below this (lengths) is rounding: the orbit is 2-periodic

ds = plot.load_figure_data(snakemake.input.bounce)
paths = [plot.orbit_path(ds.isel(orbit=i)) for i in range(ds.sizes["orbit"])]
top = max(float(y.max()) for _, y in paths) + MARGIN
windows = [(float(x.min()) - MARGIN, float(x.max()) + MARGIN, -0.12, top) for x, _ in paths]
widths = [w[1] - w[0] for w in windows]

plot.use_style()
fig = plt.figure(figsize=(6.5, 3.6))
grid = fig.add_gridspec(2, 2, width_ratios=widths[:2])
cells = [grid[0, 0], grid[0, 1]] + [grid[1, :]] * (len(windows) - 2)
for i, (cell, window) in enumerate(zip(cells[:len(windows)], windows)):
    orbit = ds.isel(orbit=i)
    ax = fig.add_subplot(cell)
    plot.draw_table(ax, orbit, window)
    plot.draw_orbit(ax, orbit, spin_every=1, spin_radius=SPIN_RADIUS)
    r, drift = float(orbit.spin_ratio), float(orbit.drift)
    kind = ("2-periodic" if abs(drift) <= PERIODIC_TOL else
            "back and forth with drift" if int(orbit.back_and_forth) else "steady drift")
    ax.set_title(f"{kind}\n$\\gamma w / v_x = {r:g}$, drift per two bounces {drift:.3g}")
    ax.set_yticks([])
ax.set_xlabel("x")
plot.save_figure(fig, snakemake.output.pdf)

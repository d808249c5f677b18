"""Figure 11: velocity portraits of no-slip polygons (gamma = 1/sqrt 2, no force), one colour per orbit."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from noslipsim import plot

RECTANGLE_ORBITS = 5  # the rectangle's orbits are all regular and wide: 30 of them hide one another
UNVISITED_BINS = 40   # cells of the disk's grid (0.05 wide) for the hatched, unvisited part

ds = plot.load_figure_data(snakemake.input.portraits)
n = ds.sizes["table"]

plot.use_style()
fig, axes = plt.subplots(1, n, figsize=(6.5, 6.5 / n + 0.45), sharey=True)
for ax, name in zip(axes, ds.table.values):
    case = ds.sel(table=name)
    label = str(name)
    if int(case.sides) == 4:
        case = case.isel(orbit=slice(0, RECTANGLE_ORBITS))
        label = f"{name} {ds.attrs['rectangle_aspect']:g}:1, {RECTANGLE_ORBITS} orbits"
    plot.draw_layered_portrait(ax, case, size=0.12)  # no flags: every orbit in its own colour
    # white would read as forbidden: hatch what these orbits did not visit, and say how much of the measure it is
    unvisited = plot.draw_unvisited(ax, case, bins=UNVISITED_BINS)
    ax.set_title(f"{label}\nunvisited {unvisited:.0%}", fontsize=8)
for ax in axes[1:]:
    ax.set_ylabel("")
fig.suptitle(f"no-slip, $\\gamma$ = {float(ds.gamma[0]):.3g}, {ds.attrs['n_orbits']} orbits "
             f"x {ds.attrs['n_collisions']:,} collisions each; hatched: visited by none of them (not forbidden)",
             fontsize=8)
plot.save_figure(fig, snakemake.output.pdf)  # writes the .pdf and the .png beside it

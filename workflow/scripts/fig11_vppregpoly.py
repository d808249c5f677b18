"""Figure 11: velocity portraits of no-slip polygons (gamma = 1/sqrt 2, no force), one colour per orbit."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from noslipsim import plot

RECTANGLE_ORBITS = 5  # the rectangle's orbits are all regular and wide: 30 of them hide one another

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
    ax.set_title(label)
for ax in axes[1:]:
    ax.set_ylabel("")
fig.suptitle(f"no-slip, $\\gamma$ = {float(ds.gamma[0]):.3g}, {ds.attrs['n_orbits']} orbits "
             f"x {ds.attrs['n_collisions']:,} collisions each", fontsize=8)
plot.save_figure(fig, snakemake.output.pdf)  # writes the .pdf and the .png beside it

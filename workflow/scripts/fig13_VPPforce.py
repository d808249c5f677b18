"""Figure 13: velocity portraits of a disk in a hexagonal cell, gamma = 1/sqrt 2 and 1, no/small/strong force.

The table is the reading the config chooses (portraits.hex_force.reading; docs/figures.md, "Figure 13",
and Figure S3 give the evidence).
"""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from noslipsim import plot
from noslipsim.analysis import classify_regular

ROWS = ("no force", "small force", "strong force")
TABLES = {"closed": "a closed hexagonal cell (no-slip walls)",
          "specular_walls": "a closed hexagonal cell (specular walls)",
          "periodic": "the periodic hexagonal cell (free fall)",
          "thermostat": "the periodic hexagonal cell (isokinetic thermostat)"}

ds = classify_regular(plot.load_figure_data(snakemake.input.portraits), snakemake.params.threshold)
reading = ds.attrs["reading"]
n_force, n_gamma = ds.sizes["force"], ds.sizes["gamma"]
increasing = list(ds.force.values) == sorted(ds.force.values)
names = ROWS if n_force == 3 and float(ds.force[0]) == 0 and increasing else ["force"] * n_force

plot.use_style()
top = 0.8   # inches above the panels: the table and the title, off the data
fig = plt.figure(figsize=(2.2 * n_gamma + 0.5, 2.05 * n_force + 0.5 + top))
head, body = fig.subfigures(2, 1, height_ratios=[top, fig.get_figheight() - top])
axes = body.subplots(n_force, n_gamma, squeeze=False)
for i, g in enumerate(ds.force.values):
    for j, gamma in enumerate(ds.gamma.values):
        ax = axes[i, j]
        case = ds.isel(force=i, gamma=j)
        plot.draw_layered_portrait(ax, case, case.regular, size=0.1)
        share = f"regular {float(case.regular.mean()):.1%}"
        ax.set_title(f"$\\gamma$ = {gamma:.3g}\n{share}" if i == 0 else share)
        if j == 0:   # the force's direction only on rows that have a force
            arrow = " $\\downarrow$" if g > 0 else ""
            ax.set_ylabel(f"{names[i]}, $g$ = {g:g}{arrow}\n$w$")
        else:
            ax.set_ylabel("")
        if i < n_force - 1:
            ax.set_xlabel("")
inset, text = head.subplots(1, 2, width_ratios=[1, 3.5])
periodic = reading in ("periodic", "thermostat")
plot.draw_table(inset, ds.scene.values.flat[0], window=(-0.75, 0.75, -0.65, 0.65) if periodic else None,
                linewidth=0.5)
inset.set_axis_off()
text.set_axis_off()
text.text(0.0, 0.5, f"disk of radius {ds.attrs['radius']:g} in {TABLES.get(reading, reading)};\nforce (0, $-g$) "
          f"per unit mass, unit start speed;\npoints: collisions with the disk, {ds.attrs['n_collisions']:,} per "
          f"orbit", fontsize=7, va="center", ha="left", transform=text.transAxes)
plot.save_figure(fig, snakemake.output.pdf)  # writes the .pdf and the .png beside it

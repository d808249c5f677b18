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
TABLES = {"closed": "a closed hexagonal cell (no-slip walls)", "specular": "a closed hexagonal cell (specular)",
          "periodic": "the periodic hexagonal cell (free fall)",
          "thermostat": "the periodic hexagonal cell (isokinetic thermostat)"}

ds = classify_regular(plot.load_figure_data(snakemake.input.portraits), snakemake.params.threshold)
reading = ds.attrs["reading"]
n_force, n_gamma = ds.sizes["force"], ds.sizes["gamma"]
increasing = list(ds.force.values) == sorted(ds.force.values)
names = ROWS if n_force == 3 and float(ds.force[0]) == 0 and increasing else ["force"] * n_force

plot.use_style()
top = 0.75   # inches above the panels: the table inset and the title, off the data
fig, axes = plt.subplots(n_force, n_gamma, figsize=(2.2 * n_gamma + 0.5, 2.05 * n_force + 0.5 + top),
                         squeeze=False)
fig.subplots_adjust(top=1.0 - (top + 0.35) / fig.get_figheight())
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
scene = ds.scene.values.flat[0]
left = axes[0, 0].get_position()
inset = fig.add_axes([0.01, left.y1 + 0.55 / fig.get_figheight(), 0.16, (top - 0.05) / fig.get_figheight()])
periodic = reading in ("periodic", "thermostat")
plot.draw_table(inset, scene, window=(-1.05, 1.05, -0.9, 0.9) if periodic else None, linewidth=0.5)
inset.set_axis_off()
last = ds.isel(force=-1).kinetic_final      # free fall, strongest force: closed cell against periodic gas
closed, periodic_gas = (float(last.sel(cell=c).median()) for c in ("closed", "periodic"))
fig.suptitle(f"disk of radius {ds.attrs['radius']:g} in {TABLES.get(reading, reading)}, force (0, $-g$); points "
             f"on the disk.\nFree fall, median kinetic energy after {ds.attrs['energy_collisions']:,} collisions at "
             f"$g$ = {float(ds.force[-1]):g} (start 0.5): closed cell {closed:.2g}, periodic gas {periodic_gas:.3g}",
             fontsize=7, x=0.58)
plot.save_figure(fig, snakemake.output.pdf)  # writes the .pdf and the .png beside it

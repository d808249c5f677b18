"""Figure 13: velocity portraits of a disk in a closed hexagonal cell, gamma = 1/sqrt 2 and 1, no/small/strong force."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from noslipsim import plot
from noslipsim.analysis import classify_regular

ROWS = ("no force", "small force", "strong force")

ds = classify_regular(plot.load_figure_data(snakemake.input.portraits), snakemake.params.threshold)
n_force, n_gamma = ds.sizes["force"], ds.sizes["gamma"]
increasing = list(ds.force.values) == sorted(ds.force.values)
names = ROWS if n_force == 3 and float(ds.force[0]) == 0 and increasing else ["force"] * n_force

plot.use_style()
fig, axes = plt.subplots(n_force, n_gamma, figsize=(2.2 * n_gamma + 0.5, 2.05 * n_force + 0.5), squeeze=False)
for i, g in enumerate(ds.force.values):
    for j, gamma in enumerate(ds.gamma.values):
        ax = axes[i, j]
        case = ds.isel(force=i, gamma=j)
        plot.draw_layered_portrait(ax, case, case.regular, size=0.1)
        share = f"regular {float(case.regular.mean()):.1%}"
        ax.set_title(f"$\\gamma$ = {gamma:.3g}\n{share}" if i == 0 else share)
        if j == 0:
            ax.set_ylabel(f"{names[i]}, $g$ = {g:g}\n$w$")
        else:
            ax.set_ylabel("")
        if i < n_force - 1:
            ax.set_xlabel("")
inset = axes[0, 0].inset_axes([-0.04, 0.76, 0.24, 0.24])    # the table, in the corner the disk leaves free
plot.draw_table(inset, ds.scene.values.flat[-1], linewidth=0.5)
inset.annotate("", xy=(0.75, -0.3), xytext=(0.75, 0.3), arrowprops=dict(arrowstyle="->", linewidth=0.6))
inset.set_xlim(-0.6, 0.9)
inset.set_axis_off()
last = ds.isel(force=-1).kinetic_final      # the evidence for the closed cell: energy under the strongest force
closed, periodic = (float(last.sel(cell=c).median()) for c in ("closed", "periodic"))
fig.suptitle(f"disk of radius {ds.attrs['radius']:g} in a closed hexagonal cell, force (0, $-g$); points on the "
             f"disk.\nKinetic energy after {ds.attrs['energy_collisions']:,} collisions at $g$ = "
             f"{float(ds.force[-1]):g} (median; start 0.5): closed cell {closed:.2g}, periodic gas {periodic:.3g}",
             fontsize=7)
plot.save_figure(fig, snakemake.output.pdf)  # writes the .pdf and the .png beside it

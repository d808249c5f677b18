"""Figure S3 (beyond the paper): Figure 13's readings, the share of regular orbits against the force."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from noslipsim import plot
from noslipsim.analysis import regular_share
from noslipsim.plot.style import LAW_COLORS, SERIES_COLORS

ds = plot.load_figure_data(snakemake.input.readings)
drawn = plot.load_figure_data(snakemake.input.portraits)      # the reading Figure 13 draws, and its forces
chosen = drawn.attrs["reading"]
threshold = snakemake.params.threshold
share, err, n = regular_share(ds.ftle.values, threshold)     # dims (reading, gamma, force)
# specular walls keep the specular law's colour; the other readings take series colours (plot.style)
STYLE = {"closed": (SERIES_COLORS[0], "o"), "specular_walls": (LAW_COLORS["specular"], "s"),
         "periodic": (SERIES_COLORS[2], "^"), "thermostat": (SERIES_COLORS[1], "D")}
LABEL = {"closed": "closed cell, no-slip walls", "specular_walls": "closed cell, specular walls",
         "periodic": "periodic cell, free fall", "thermostat": "periodic cell, isokinetic thermostat"}

plot.use_style()
n_gamma = ds.sizes["gamma"]
fig, axes = plt.subplots(1, n_gamma, figsize=(3.3 * n_gamma, 3.6), squeeze=False, sharey=True)
forces = ds.force.values
for j, gamma in enumerate(ds.gamma.values):
    ax = axes[0, j]
    for i, reading in enumerate(ds.reading.values):
        reading = str(reading)
        color, marker = STYLE.get(reading, ("k", "o"))
        label = LABEL.get(reading, reading) + (" (Figure 13)" if reading == chosen else "")
        ax.errorbar(forces, share[i, j], yerr=err[i, j], color=color, marker=marker, markersize=3.5, capsize=2,
                    linewidth=1.8 if reading == chosen else 0.9, label=label)
    for g in drawn.force.values:          # Figure 13's rows
        ax.axvline(float(g), color="0.75", linewidth=0.6, linestyle=":", zorder=0)
    linthresh = min(f for f in forces if f > 0) if (forces > 0).any() else 1.0
    ax.set_xscale("symlog", linthresh=linthresh)
    ax.set_xlim(-0.3 * linthresh, 1.4 * max(forces.max(), linthresh))
    ax.set(xlabel="force strength $g$", ylim=(-0.03, 1.05), title=f"$\\gamma$ = {gamma:.3g}")
    if j == 0:
        ax.set_ylabel(f"share of regular orbits\n(exponent < {threshold:g} per collision)")
handles, labels = axes[0, 0].get_legend_handles_labels()
fig.legend(handles, labels, fontsize=6.5, loc="outside lower center", ncol=2, frameon=False)   # below the panels
fig.suptitle(f"disk of radius {ds.attrs['radius']:g} in a hexagonal cell, force (0, $-g$), unit start speed: "
             f"{ds.attrs['n_orbits']} orbits per point,\nexponents over {ds.attrs['lyapunov_collisions']:,} "
             f"collisions (twin orbits); dotted: Figure 13's rows", fontsize=7)
plot.save_figure(fig, snakemake.output.pdf)  # writes the .pdf and the .png beside it

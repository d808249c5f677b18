"""Figure S3 (beyond the paper): Figure 13's readings, the share of regular orbits against the force, and the
attracting cycles the thermostatted gas falls onto."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from noslipsim import plot
from noslipsim.analysis import attractor_census, regular_share, threshold_sensitivity
from noslipsim.plot.style import LAW_COLORS, SERIES_COLORS

ds = plot.load_figure_data(snakemake.input.readings)
drawn = plot.load_figure_data(snakemake.input.portraits)      # the reading Figure 13 draws, and its forces
chosen = drawn.attrs["reading"]
threshold = snakemake.params.threshold
share, err, n = regular_share(ds.ftle.values, threshold)     # dims (reading, gamma, force)
# specular walls and the specular gas keep the specular law's colour (told apart by line and marker); the
# other readings take series colours (plot.style)
STYLE = {"closed": (SERIES_COLORS[0], "o", "-"), "specular_walls": (LAW_COLORS["specular"], "s", "-"),
         "periodic": (SERIES_COLORS[2], "^", "-"), "thermostat": (SERIES_COLORS[1], "D", "-"),
         "specular_thermostat": (LAW_COLORS["specular"], "v", "--")}
LABEL = {"closed": "closed cell, no-slip walls", "specular_walls": "closed cell, specular walls",
         "periodic": "periodic cell, free fall", "thermostat": "periodic cell, isokinetic thermostat",
         "specular_thermostat": "periodic cell, thermostat, specular disk"}
cycles = "attractor_period" in ds


def style(reading):
    return STYLE.get(reading, ("k", "o", "-"))


def draw_shares(ax, j):
    """Top row: the regular share of every reading against g; a band for the threshold's sensitivity."""
    for i, reading in enumerate(map(str, ds.reading.values)):
        color, marker, line = style(reading)
        label = LABEL.get(reading, reading) + (" (Figure 13)" if reading == chosen else "")
        ax.errorbar(forces, share[i, j], yerr=err[i, j], color=color, marker=marker, markersize=3.5, capsize=2,
                    linestyle=line, linewidth=1.8 if reading == chosen else 0.9, label=label)
        if reading == chosen:   # where the exponents straddle the line, the share moves with it
            low = min(threshold_sensitivity(ds.ftle.values[i, j], threshold).items())
            ax.fill_between(forces, low[1], share[i, j], color=color, alpha=0.2, linewidth=0,
                            label=f"Figure 13's reading, threshold {low[0]:g} to {threshold:g}")


def draw_cycles(ax, j):
    """Bottom row: the share of orbits on an attracting cycle, labelled with the cycles' periods."""
    for i, reading in enumerate(map(str, ds.reading.values)):
        case = ds.isel(reading=i, gamma=j)
        if not (case.attractor_period > 0).any():
            continue
        color, marker, line = style(reading)
        on = (case.attractor_period > 0).mean("orbit").values
        ax.plot(forces, on, color=color, marker=marker, markersize=3.5, linestyle=line, linewidth=0.9)
        for k, g in enumerate(forces):
            below = reading == chosen and on[k] > 0.5   # Figure 13's reading under its high points, off the other

            found = attractor_census(case.attractor_period.values[k], case.attractor.values[k])
            if found:   # the periods of the two most populated cycles, "+n": n more cycles
                text = ",".join(str(p) for p, _ in found[:2]) + (f"+{len(found) - 2}" if len(found) > 2 else "")
                ax.annotate(text, (g, on[k]), xytext=(0, -4 if below else 4), textcoords="offset points",
                            fontsize=5, color=color, rotation=90, ha="center", va="top" if below else "bottom")


plot.use_style()
n_gamma = ds.sizes["gamma"]
rows = 2 if cycles else 1
fig, axes = plt.subplots(rows, n_gamma, figsize=(3.3 * n_gamma, 3.4 + 2.3 * (rows - 1)), squeeze=False,
                         sharey="row", sharex=True, height_ratios=[1.4, 1][:rows])
forces = ds.force.values
linthresh = min(f for f in forces if f > 0) if (forces > 0).any() else 1.0
for j, gamma in enumerate(ds.gamma.values):
    draw_shares(axes[0, j], j)
    if cycles:
        draw_cycles(axes[1, j], j)
    for ax in axes[:, j]:
        for g in drawn.force.values:          # Figure 13's rows
            ax.axvline(float(g), color="0.75", linewidth=0.6, linestyle=":", zorder=0)
        ax.set_xscale("symlog", linthresh=linthresh)
        ax.set_xlim(-0.3 * linthresh, 1.4 * max(forces.max(), linthresh))
    axes[0, j].set(ylim=(-0.03, 1.05), title=f"$\\gamma$ = {gamma:.3g}")
    axes[-1, j].set_xlabel("force strength $g$")
    if cycles:
        axes[1, j].set_ylim(-0.03, 1.3)
axes[0, 0].set_ylabel(f"share of regular orbits\n(exponent < {threshold:g} per collision)")
if cycles:
    axes[1, 0].set_ylabel("share on an attracting cycle\n(labels: its periods)")
handles, labels = axes[0, 0].get_legend_handles_labels()
fig.legend(handles, labels, fontsize=6.5, loc="outside lower center", ncol=2, frameon=False)   # below the panels
found = (f";\nattracting cycles over {ds.attrs['attractor_collisions']:,} disk collisions (thermostatted readings), "
         "labelled with their periods in disk collisions" if cycles else "")
fig.suptitle(f"disk of radius {ds.attrs['radius']:g} in a hexagonal cell, force (0, $-g$), unit start speed: "
             f"{ds.attrs['n_orbits']} orbits per point,\nexponents over {ds.attrs['lyapunov_collisions']:,} "
             f"collisions (twin orbits); dotted: Figure 13's rows{found}", fontsize=7)
fig.align_ylabels(axes[:, 0])
plot.save_figure(fig, snakemake.output.pdf)  # writes the .pdf and the .png beside it

"""Figure 13: velocity portraits of a disk in a hexagonal cell, gamma = 1/sqrt 2 and 1, no/small/strong force.

Each panel gives its regular share at three thresholds and rings the attracting cycles its orbits end on
(analysis.attractors), with their periods in disk collisions.

The table is the reading the config chooses (portraits.hex_force.reading; docs/figures.md, "Figure 13",
and Figure S3 give the evidence).
"""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from noslipsim import plot
from noslipsim.analysis import attractor_census, classify_regular, portrait_attractors, threshold_sensitivity

ROWS = ("no force", "small force", "strong force")
TABLES = {"closed": "a closed hexagonal cell (no-slip walls)",
          "specular_walls": "a closed hexagonal cell (specular walls)",
          "periodic": "the periodic hexagonal cell (free fall)",
          "thermostat": "the periodic hexagonal cell (isokinetic thermostat)"}

threshold = snakemake.params.threshold
ds = portrait_attractors(classify_regular(plot.load_figure_data(snakemake.input.portraits), threshold))
CYCLE_MARKERS = ("o", "s", "^", "D", "v")   # one per attracting cycle of a panel, most populated first


def shares_text(case):
    """The regular share at the threshold and below it, highest threshold first."""
    shares = threshold_sensitivity(case.ftle.values, threshold)
    return "regular " + " / ".join(f"{100 * p:.0f}" for p in reversed(shares.values())) + " %"


def draw_cycles(ax, case):
    """Ring the points of each attracting cycle and list the cycles' periods (orbits on each)."""
    found = attractor_census(case.attractor_period.values, case.attractor.values)
    for a, (period, _) in enumerate(found[:len(CYCLE_MARKERS)]):
        last = case.isel(orbit=int(np.argmax(case.attractor.values == a)))   # an orbit on the cycle: its last period
        end = int(last.n_points)
        ax.scatter(last.vt_unit.values[end - period:end], last.w_unit.values[end - period:end], s=9,
                   marker=CYCLE_MARKERS[a], facecolors="none", edgecolors="k", linewidths=0.4, zorder=5)
    if found:
        listed = ", ".join(f"{p} ({k})" for p, k in found[:3]) + (", ..." if len(found) > 3 else "")
        ax.text(0.02, 0.02, f"cycles: {listed}", transform=ax.transAxes, fontsize=5, va="bottom")
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
        draw_cycles(ax, case)
        share = shares_text(case)
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
thresholds = list(threshold_sensitivity([], threshold))
plot.draw_table(inset, ds.scene.values.flat[0], window=(-0.75, 0.75, -0.65, 0.65) if periodic else None,
                linewidth=0.5)
inset.set_axis_off()
text.set_axis_off()
text.text(0.0, 0.5, f"disk of radius {ds.attrs['radius']:g} in {TABLES.get(reading, reading)};\nforce (0, $-g$) "
          f"per unit mass, unit start speed;\npoints: collisions with the disk, {ds.attrs['n_collisions']:,} per "
          f"orbit; regular: exponent below\n" + " / ".join(f"{t:g}" for t in reversed(thresholds)) + " per "
          "collision; rings: attracting cycles, period (orbits)", fontsize=7, va="center", ha="left",
          transform=text.transAxes)
plot.save_figure(fig, snakemake.output.pdf)  # writes the .pdf and the .png beside it

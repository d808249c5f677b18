"""Figure 1: specular and no-slip orbits from one start in a rectangle with a scatterer,
spin arrows inside the particle."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from noslipsim import plot

SPIN_RADIUS = 0.055  # drawn particle radius (table lengths); the particle itself is a point

ds = plot.load_figure_data(snakemake.input.specnoslip)
plot.use_style()
aspect = ds.attrs["height"] / ds.attrs["width"]
fig, axes = plt.subplots(1, 2, figsize=(6.5, 3.25 * aspect + 0.5))
for ax, i in zip(axes, range(ds.sizes["orbit"])):
    orbit = ds.isel(orbit=i)
    plot.draw_table(ax, orbit)
    plot.draw_orbit(ax, orbit, spin_every=1, spin_radius=SPIN_RADIUS, linewidth=0.7)
    if str(orbit.role.values) == "specular":
        # to the digits of numbers.json (docs/figures.md quotes 2.5° and 3.9°, not 3° and 4°)
        title, note = "specular", f"leaves the scatterer {float(orbit.exit_from_vertical):.1f}° from the vertical"
    else:
        title = f"no-slip, $\\gamma = {float(orbit.gamma):.3g}$"
        note = f"leaves the scatterer {float(orbit.exit_to_corner):.1f}° off the upper left corner"
    ax.set_title(title)
    ax.text(0.5, -0.03, note, transform=ax.transAxes, ha="center", va="top")
    ax.set_axis_off()
plot.save_figure(fig, snakemake.output.pdf)  # writes the .pdf and the .png beside it

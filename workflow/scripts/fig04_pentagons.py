"""Figure 4: generic specular orbits of a regular and a non-regular pentagon; a no-slip orbit in
a corridor near a 14-periodic point."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from noslipsim import plot

ds = plot.load_figure_data(snakemake.input.pentagons)
orbit = {str(r): ds.isel(orbit=i) for i, r in enumerate(ds.role.values)}
period = int(ds.attrs["period"])
plot.use_style()
fig, axes = plt.subplots(1, 3, figsize=(6.5, 2.5))
panels = [("specular regular", "specular, regular pentagon"),
          ("specular irregular", "specular, non-regular pentagon"),
          ("no-slip corridor", f"no-slip, near a {period}-periodic orbit")]
for ax, (role, title) in zip(axes, panels):
    plot.draw_table(ax, orbit[role])
    plot.draw_orbit(ax, orbit[role], linewidth=0.25, ends=False)
    ax.set_title(title)
    ax.set_axis_off()
plot.draw_orbit(axes[2], orbit["no-slip periodic"], color="k", linewidth=0.6, ends=False, zorder=3)
plot.equal_panels(axes)  # equal boxes, titles in line
axes[2].text(0.5, -0.02, f"{ds.periodic_kind.values!s}, rotation {float(ds.rotation_angle):.3f} rad; "
             f"perturbed by {ds.attrs['perturbation']:g} rad", transform=axes[2].transAxes, ha="center",
             va="top", fontsize=7)
plot.save_figure(fig, snakemake.output.pdf)

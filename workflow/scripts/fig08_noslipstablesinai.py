"""Figure 8: two disks in a box, no force, one start: the specular orbit (lighter) scatters,
the no-slip one stays between the disks."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from noslipsim import plot

ds = plot.load_figure_data(snakemake.input.twodisks)
orbit = {str(r): ds.isel(orbit=i) for i, r in enumerate(ds.role.values)}
width, height = ds.attrs["box"]
plot.use_style()
fig, ax = plt.subplots(figsize=(6.5, 6.5 * height / width + 0.3))
plot.draw_table(ax, orbit["specular"])
n_spec, n_ns = int(orbit["specular"].n_collisions), int(orbit["no-slip"].n_collisions)
plot.draw_orbit(ax, orbit["specular"], alpha=0.45, linewidth=0.6, ends=False,
                label=f"specular, {n_spec} collisions ({int(orbit['specular'].box_collisions)} with the box)")
plot.draw_orbit(ax, orbit["no-slip"], linewidth=0.3, ends=False, zorder=3,
                label=f"no-slip, $\\gamma = {float(orbit['no-slip'].gamma):.3g}$, {n_ns} collisions "
                      f"({int(orbit['no-slip'].box_collisions)} with the box)")
ax.legend(loc="upper center", bbox_to_anchor=(0.5, 0.0), ncol=2, handlelength=1.5)
ax.set_title(f"start: the {ds.kind.values!s} 2-periodic orbit between the disks "
             f"($\\lambda + 1/\\lambda = {float(ds.eigen_sum):.3f}$), velocity turned {ds.attrs['perturbation']:g} rad")
ax.set_axis_off()
plot.save_figure(fig, snakemake.output.pdf)

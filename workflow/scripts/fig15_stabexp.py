"""Figure 15: stability of the two-disk 2-periodic orbits.  Dark: the perturbed orbit survived many collisions
(<= the cap); dashed: the force-free ellipticity threshold R*(phi); solid outline: the orbits whose monodromy is
elliptic (linear theory, with the force where there is one).  Upper right: the set-up."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from noslipsim import plot

LABELS = {"phi": "$\\varphi$ (position of $q_0$)", "theta": "launch angle $\\theta$", "radius": "disk radius $R$"}

grids = {k: plot.load_figure_data(snakemake.input[k]) for k in ("noforce", "force", "theta")}
sketch = snakemake.params.sketch
plot.use_style()
fig, axes = plt.subplots(2, 2, figsize=(6.5, 5.6))
places = {"noforce": axes[0, 0], "force": axes[1, 0], "theta": axes[1, 1]}
titles = {"noforce": "no force",
          "force": f"force, launch angle $\\theta$ = {grids['force'].attrs['theta']:g}",
          "theta": f"force, $\\varphi$ = {grids['theta'].attrs['phi']:g}"}
for key, ds in grids.items():
    ax = places[key]
    second = "phi" if "phi" in ds.dims else "theta"
    threshold = (ds.phi.values, ds.radius_threshold.values) if second == "phi" else None
    mesh = plot.draw_stability_grid(ax, ds.n_collisions, threshold=threshold, cmap="Greys", vmin=0,
                                    vmax=ds.attrs["max_collisions"], threshold_color="#0072B2",
                                    threshold_label="threshold $R^*(\\varphi)$, no force")
    if second == "theta":   # the force-free threshold at this phi: the theta -> 0 limit
        ax.axhline(float(ds.radius_threshold), color="#0072B2", linestyle="--", linewidth=1.0,
                   label="threshold $R^*(\\varphi)$, no force")
    plot.draw_class_boundary(ax, ds.linear_kind)
    ax.plot([], [], color=plot.stability.CLASS_COLOR, label="elliptic (monodromy)")
    ax.set_xlabel(LABELS[second])
    ax.set_ylabel(LABELS["radius"])
    ax.set_title(f"{titles[key]}\n(survival agrees with the class at {ds.attrs['agreement_share']:.1%})",
                 fontsize=7.5)
fig.colorbar(mesh, ax=axes[:, 1], shrink=0.45, label="collisions survived", anchor=(0.0, 0.1))
setup = axes[0, 1]
plot.draw_two_disk_setup(setup, sketch["radius"], sketch["phi"], sketch["theta"])
setup.set_axis_off()
setup.set_title("set-up: disks of radius $R$, centres 2 apart", fontsize=8)
setup.legend(*axes[1, 1].get_legend_handles_labels(), fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.05))
plot.save_figure(fig, snakemake.output.pdf)

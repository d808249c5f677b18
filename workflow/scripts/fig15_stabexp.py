"""Figure 15: stability of the two-disk 2-periodic orbits.  Dark: the perturbed orbit survived many collisions
(<= the cap); dashed: the force-free ellipticity threshold R*(phi); solid outline: the orbits whose monodromy is
elliptic (linear theory, with the force where there is one; elliptic or non-elliptic pockets of fewer than
MIN_CELLS cells are not outlined); dotted: the parabolic line phi + theta = pi/2 under gravity; thin: the 1:3
resonance lambda + 1/lambda = -1 (the white streak inside the elliptic region); dash-dotted (no force): below it
the velocity turned by the perturbation passes over the far disk (the white strip near phi = pi/2).  Upper right:
the set-up."""
import math
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import matplotlib

matplotlib.use("Agg")
import json

import matplotlib.pyplot as plt
import numpy as np
from matplotlib import patheffects

from noslipsim import plot
from noslipsim.analysis import elliptic_boundary

LABELS = {"phi": "$\\varphi$ (position of $q_0$)", "theta": "launch angle $\\theta$", "radius": "disk radius $R$"}
THRESHOLD_COLOR = "#009E73"   # theory (not a law colour)
CLASS_COLOR = plot.law_color("no-slip")   # the class of the no-slip orbit
PARABOLIC_COLOR = "k"
# white-rimmed dots with gaps, on top of the elliptic outline that runs along it: seen on the dark survival map,
# on the white one and on the outline, which shows between the dots
PARABOLIC_STYLE = dict(color=PARABOLIC_COLOR, linestyle=(0, (1.0, 1.6)), linewidth=1.2,
                       path_effects=[patheffects.Stroke(linewidth=2.4, foreground="w"), patheffects.Normal()])
RESONANCE_COLOR = "#CC79A7"   # lambda + 1/lambda = -1: the 1:3 resonance, where the white streak lies
MISS_COLOR = "#56B4E9"        # the turned velocity clears the far disk (the white strip near phi = pi/2)
MIN_CELLS = 10                # smaller pockets of one class are not outlined (single cells, grazing corners)


def components(mask):
    """Labels of the 4-connected components of a boolean 2D mask (0: outside the mask)."""
    labels = np.zeros(mask.shape, dtype=int)
    n = 0
    for start in zip(*np.nonzero(mask)):
        if labels[start]:
            continue
        n += 1
        stack = [start]
        labels[start] = n
        while stack:
            i, j = stack.pop()
            for a, b in ((i + 1, j), (i - 1, j), (i, j + 1), (i, j - 1)):
                if 0 <= a < mask.shape[0] and 0 <= b < mask.shape[1] and mask[a, b] and not labels[a, b]:
                    labels[a, b] = n
                    stack.append((a, b))
    return labels


def without_pockets(kinds, min_cells):
    """``kinds`` with elliptic pockets and non-elliptic holes of fewer than ``min_cells`` cells flipped."""
    inside = np.asarray(kinds.values).astype(str) == "elliptic"
    for value in (True, False):
        labels = components(inside == value)
        sizes = np.bincount(labels.ravel())
        small = np.flatnonzero(sizes < min_cells)
        small = small[small > 0]
        inside[np.isin(labels, small)] = not value
    return kinds.copy(data=np.where(inside, "elliptic", "hyperbolic"))


def parabolic_line(ax, ds, second):
    """The line phi + theta = pi/2 (a launch parallel to the tangent at q1), above the elliptic outline; named in
    the legend (a label in the panel covered the survival map)."""
    x = math.pi / 2 - float(ds.attrs["theta" if second == "phi" else "phi"])
    return ax.axvline(x, zorder=3, **PARABOLIC_STYLE)


def resonance(ax, ds, second):
    """The curve lambda + 1/lambda = -1 inside the elliptic region (rotation by 2 pi/3 per period)."""
    es = ds.eigen_sum.transpose("radius", second).values
    es = np.where(ds.linear_kind.transpose("radius", second).values == "elliptic", es, np.nan)
    ax.contour(ds[second].values, ds.radius.values, es, levels=[-1.0], colors=[RESONANCE_COLOR], linewidths=0.7,
               linestyles="-", zorder=2.5)


def clears_far_disk(ax, ds):
    """Without force: the velocity turned up by delta at mid-chord passes over the far disk's top when
    delta (1 - R cos phi) > R (1 - sin phi), i.e. below R = delta / (1 - sin phi + delta cos phi)."""
    delta = json.loads(ds.attrs["perturbation"])["angle"]
    phi = np.linspace(float(ds.phi[0]), float(ds.phi[-1]), 400)
    r = delta / (1.0 - np.sin(phi) + delta * np.cos(phi))
    keep = r <= float(ds.radius[-1])
    ax.plot(phi[keep], r[keep], color=MISS_COLOR, linewidth=1.0, linestyle="-.", zorder=3)


grids = {k: plot.load_figure_data(snakemake.input[k]) for k in ("noforce", "force", "theta")}
sketch = snakemake.params.sketch
shift = elliptic_boundary(grids["force"]).attrs   # how far the force's elliptic boundary lies below R*(phi)
plot.use_style()
fig, axes = plt.subplots(2, 2, figsize=(6.5, 5.8))
places = {"noforce": axes[0, 0], "force": axes[1, 0], "theta": axes[1, 1]}
titles = {"noforce": "no force",
          "force": f"force, launch angle $\\theta$ = {grids['force'].attrs['theta']:g}",
          "theta": f"force, $\\varphi$ = {grids['theta'].attrs['phi']:g}"}
for key, ds in grids.items():
    ax = places[key]
    second = "phi" if "phi" in ds.dims else "theta"
    threshold = (ds.phi.values, ds.radius_threshold.values) if second == "phi" else None
    mesh = plot.draw_stability_grid(ax, ds.n_collisions, threshold=threshold, cmap="Greys", vmin=0,
                                    vmax=ds.attrs["max_collisions"], threshold_color=THRESHOLD_COLOR,
                                    threshold_label="threshold $R^*(\\varphi)$, no force")
    if second == "theta":   # the force-free threshold at this phi: the theta -> 0 limit
        ax.axhline(float(ds.radius_threshold), color=THRESHOLD_COLOR, linestyle="--", linewidth=1.0,
                   label="threshold $R^*(\\varphi)$, no force")
    plot.draw_class_boundary(ax, without_pockets(ds.linear_kind, MIN_CELLS), color=CLASS_COLOR)
    if key != "noforce":
        parabolic_line(ax, ds, second)
    else:
        clears_far_disk(ax, ds)
    if second == "phi":
        resonance(ax, ds, second)
    ax.set_xlabel(LABELS[second])
    ax.set_ylabel(LABELS["radius"])
    ax.set_title(f"{titles[key]}\n(survival agrees with the class at {ds.attrs['agreement_share']:.1%})",
                 fontsize=7.5)
ax = places["force"]
ax.text(0.03, 0.04, f"elliptic boundary below $R^*$ by up to {shift['max_shift']:.3f}\n"
        f"(mean {shift['mean_shift']:.3f} for $\\varphi \\leq$ {shift['phi_max']:.2f})", transform=ax.transAxes,
        fontsize=6.5, ha="left", va="bottom", bbox=dict(facecolor="white", edgecolor="0.6", alpha=0.9, pad=1.5))
axes[1, 1].plot([], [], color=CLASS_COLOR, label="elliptic (monodromy)")
axes[1, 1].plot([], [], label="parabolic line $\\varphi + \\theta = \\pi/2$", **PARABOLIC_STYLE)
axes[1, 1].plot([], [], color=RESONANCE_COLOR, linewidth=0.7, label="$\\lambda + 1/\\lambda = -1$ (1:3 resonance)")
axes[1, 1].plot([], [], color=MISS_COLOR, linestyle="-.", label="turned velocity clears the far disk")
fig.colorbar(mesh, ax=axes[:, 1], shrink=0.45, label="collisions survived", anchor=(0.0, 0.1))
setup = axes[0, 1]
plot.draw_two_disk_setup(setup, sketch["radius"], sketch["phi"], sketch["theta"], color=CLASS_COLOR)
setup.set_axis_off()
setup.set_title("set-up: disks of radius $R$, centres 2 apart", fontsize=8)
setup.legend(*axes[1, 1].get_legend_handles_labels(), fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.05),
             frameon=True)
plot.save_figure(fig, snakemake.output.pdf)

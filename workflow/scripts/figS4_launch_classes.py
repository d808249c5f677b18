"""Figure S4: does the launch angle alone change the linear class of the two-disk 2-periodic orbits?  Left: per
(phi, R), the classes met along theta.  Right: the measured elliptic boundary R_e(phi) at several launch angles
against the force-free closed form R*(phi) (dashed)."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.colors import BoundaryNorm, ListedColormap

from noslipsim import plot

ds = plot.load_figure_data(snakemake.input.launch, required=["eigen_sum"])
CATEGORIES = ("elliptic at every θ", "hyperbolic at every θ", "elliptic and hyperbolic", "other change")
COLORS = ("#56B4E9", "0.85", plot.law_color("no-slip"), "#E69F00")
N_CURVES = 5   # launch angles drawn on the right


def category(ds):
    """0-3 per (radius, phi) as CATEGORIES (NaN: fewer than two launch angles with an orbit)."""
    kinds = ds.linear_kind.values.astype(str)
    cat = np.where(ds.elliptic_hyperbolic.values == 1, 2.0, np.where(ds.class_changes.values == 1, 3.0, np.nan))
    steady = ds.class_changes.values == 0
    cat[steady & (kinds == "elliptic").any(axis=-1)] = 0.0
    cat[steady & (kinds == "hyperbolic").any(axis=-1)] = 1.0
    return cat


plot.use_style()
fig, (left, right) = plt.subplots(1, 2, figsize=(6.5, 2.9))
cmap = ListedColormap(COLORS)
left.pcolormesh(ds.phi, ds.radius, category(ds), cmap=cmap, norm=BoundaryNorm(np.arange(-0.5, 4.5), cmap.N),
                shading="nearest")
left.plot(ds.phi, ds.radius_threshold, "--", color=plot.REFERENCE_COLOR, linewidth=0.9,
          label="$R^*(\\varphi)$, no force")
for name, color in zip(CATEGORIES, COLORS):
    left.plot([], [], "s", color=color, label=name)
left.set(xlabel="$\\varphi$ (position of $q_0$)", ylabel="disk radius $R$", ylim=(ds.radius[0], ds.radius[-1]),
         title=f"{ds.attrs['n_changing']} of {ds.attrs['n_columns']} columns change class")
left.legend(fontsize=6, loc="lower left", framealpha=0.9)

picks = np.unique(np.linspace(0, ds.sizes["theta"] - 1, N_CURVES).round().astype(int))
for color, j in zip(plot.SERIES_COLORS, picks):
    b = ds.boundary.isel(theta=j)
    right.plot(ds.phi, b, "-", color=color, linewidth=1.0, label=f"$\\theta$ = {float(ds.theta[j]):.2f}")
right.plot(ds.phi, ds.radius_threshold, "--", color=plot.REFERENCE_COLOR, linewidth=0.9, label="$R^*(\\varphi)$")
right.set(xlabel="$\\varphi$", ylabel="elliptic above $R_e(\\varphi)$", ylim=(0, 1),
          title="measured class boundary")
right.legend(fontsize=6, loc="lower right")
plot.save_figure(fig, snakemake.output.pdf)

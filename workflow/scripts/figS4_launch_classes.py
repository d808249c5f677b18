"""Figure S4: does the launch angle alone change the linear class of the two-disk 2-periodic orbits?  Left: per
(phi, R), the classes met along theta below the parabolic line theta = pi/2 - phi (above it every orbit is
hyperbolic).  Right: the measured elliptic boundary R_e(phi) at several launch angles
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
CATEGORIES = ("elliptic at every θ", "hyperbolic at every θ", "elliptic at some θ, hyperbolic at others")
COLORS = ("#56B4E9", "0.85", plot.law_color("no-slip"))
N_CURVES = 5   # launch angles drawn on the right


def category(ds):
    """0-2 per (radius, phi) as CATEGORIES, below the parabolic line (NaN: fewer than two launch angles there)."""
    below = ds.theta < np.pi / 2 - ds.phi - ds.attrs["margin"]
    kinds = ds.linear_kind.where(below, "").transpose("radius", "phi", "theta").values.astype(str)
    ell, hyp = (kinds == "elliptic").any(axis=-1), (kinds == "hyperbolic").any(axis=-1)
    cat = np.where(ell & hyp, 2.0, np.where(ell, 0.0, np.where(hyp, 1.0, np.nan)))
    cat[(kinds != "").sum(axis=-1) < 2] = np.nan
    return cat


plot.use_style()
fig, (left, right) = plt.subplots(1, 2, figsize=(6.5, 3.3))
cmap = ListedColormap(COLORS)
left.pcolormesh(ds.phi, ds.radius, category(ds), cmap=cmap, norm=BoundaryNorm(np.arange(-0.5, 3.5), cmap.N),
                shading="nearest")
left.plot(ds.phi, ds.radius_threshold, "--", color=plot.REFERENCE_COLOR, linewidth=0.9,
          label="$R^*(\\varphi)$, no force")
for name, color in zip(CATEGORIES, COLORS):
    left.plot([], [], "s", color=color, label=name)
left.set(xlabel="$\\varphi$ (position of $q_0$)", ylabel="disk radius $R$", ylim=(ds.radius[0], ds.radius[-1]),
         title=f"θ < π/2 - φ: {ds.attrs['n_changing_below']} of {ds.attrs['n_columns_below']} change class")
# below the panels: inside the left one it would hide a class
fig.legend(*left.get_legend_handles_labels(), fontsize=6, loc="outside lower left", ncol=2)

measured = np.flatnonzero(np.isfinite(ds.boundary).sum("phi").values >= 2)   # launch angles with a boundary
picks = measured[np.unique(np.linspace(0, measured.size - 1, N_CURVES).round().astype(int))]
for color, j in zip(plot.SERIES_COLORS, picks):
    b = ds.boundary.isel(theta=j)
    right.plot(ds.phi, b, "-", color=color, linewidth=1.0, label=f"$\\theta$ = {float(ds.theta[j]):.2f}")
right.plot(ds.phi, ds.radius_threshold, "--", color=plot.REFERENCE_COLOR, linewidth=0.9, label="$R^*(\\varphi)$")
right.set(xlabel="$\\varphi$", ylabel="elliptic above $R_e(\\varphi)$", ylim=(0, 1),
          title="measured class boundary")
right.legend(fontsize=6, loc="upper right")
plot.save_figure(fig, snakemake.output.pdf)

"""Figure 14: a wedge of full angle 2 pi/7 (half-angle pi/7); 2-periodic orbits launched at 1.122 ... 1.126 rad,
each perturbed identically.  Top: the perturbed orbits (walls drawn from the vertex up); bottom: their distance
delta_k from the periodic orbit against the collision number (dashed: the linear growth |lambda|^(k/2)), and
lambda + 1/lambda along the launch angle, with theta* = pi/2 - pi/7 = 1.121997 (the elliptic -> hyperbolic
transition) drawn on top of the five launch angles (dots on the curve)."""
import json
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from noslipsim import plot

COLORS = plot.SERIES_COLORS  # the launch angles are not laws: never the specular blue or the no-slip vermilion
ZOOM = 0.006  # half-width (rad) of the zoom around the transition
ANCHOR = 1e-2  # the dashed growth lines pass through the distance 1e-2 (past the polynomial transient)

ds = plot.load_figure_data(snakemake.input.orbits)
scan = plot.load_figure_data(snakemake.input.scan)
n = ds.sizes["orbit"] // 2
phi = ds.attrs["phi"]
plot.use_style()
fig = plt.figure(figsize=(6.5, 4.6))
grid = fig.add_gridspec(2, 1, height_ratios=[1.0, 1.15])
upper, lower = grid[0].subgridspec(1, n), grid[1].subgridspec(1, 3, wspace=0.1)
paths = [plot.orbit_path(ds.isel(orbit=n + j)) for j in range(n)]
top = max(p[1].max() for p in paths) * 1.05
half = max(np.abs(p[0]).max() for p in paths) * 1.05
for j in range(n):
    ax = fig.add_subplot(upper[0, j])
    periodic, perturbed = ds.isel(orbit=j), ds.isel(orbit=n + j)
    plot.draw_table(ax, periodic, (-half, half, 0.0, top))  # the window starts at the vertex: walls stop there
    plot.draw_orbit(ax, perturbed, color="0.55", linewidth=0.2, ends=False)
    plot.draw_orbit(ax, periodic, color=COLORS[j % len(COLORS)], linewidth=1.0, ends=False, zorder=3)
    ax.set_title(f"$\\theta$ = {float(periodic.theta):.3f}\n$|\\lambda|$ = {float(periodic.lambda_max):.4f}",
                 fontsize=7.5)
    ax.set_xticks([])
    ax.set_yticks([])
growth, wide, zoom = (fig.add_subplot(lower[0, k]) for k in range(3))
for j in range(n):
    o = ds.isel(orbit=n + j)
    plot.draw_deviation(growth, o, lambda_max=float(o.lambda_max), anchor=ANCHOR, color=COLORS[j % len(COLORS)],
                        label=f"{float(o.theta):.3f}")
growth.set_ylim(1e-7, 3.0)   # room below the data for the legend, inside the spines
growth.legend(title="$\\theta$", fontsize=6, title_fontsize=6.5, loc="lower right", ncol=2, frameon=True,
              columnspacing=0.6, handlelength=1.0, borderaxespad=0.3)
growth.set_ylabel("distance $\\delta_k$ from the periodic orbit\n"
                  "$\\max(|\\Delta s|/\\ell,\\,|\\Delta w|/V,\\,|\\Delta v_t|/V)$", fontsize=7)
angle = json.loads(ds.attrs["perturbation"])["angle"]
growth.set_title(f"velocity turned by {angle:g} rad", fontsize=7.5)
for ax in (wide, zoom):
    for i, p in enumerate(scan.phi.values):
        sevenths = round(p / np.pi * 7)
        name = f"{p:.4g}"
        if np.isclose(p, sevenths * np.pi / 7):
            name = f"{sevenths if sevenths > 1 else ''}\\pi/7"
        label = f"$\\varphi = {name}$" + (" (top row)" if np.isclose(p, phi) else "")
        ax.plot(scan.theta, scan.eigen_sum.isel(phi=i), color="k" if np.isclose(p, phi) else "0.6",
                linestyle="-" if np.isclose(p, phi) else "--", label=label)
    ax.axhline(2.0, color="0.3", linewidth=0.5, linestyle=":")
    ax.set_xlabel("launch angle $\\theta$")
t_star = float(scan.theta_transition.sel(phi=phi, method="nearest"))
zoom.set_xlim(t_star - ZOOM, t_star + ZOOM)
sel = np.abs(scan.theta.values - t_star) <= ZOOM
ys = scan.eigen_sum.sel(phi=phi, method="nearest").values[sel]
zoom.set_ylim(ys.min() - 0.02, ys.max() + 0.02)
for j in range(n):  # each launch angle as a dot on the curve, so that the theta* line stays visible
    o = ds.isel(orbit=j)
    zoom.plot([float(o.theta)], [float(o.eigen_sum)], "o", color=COLORS[j % len(COLORS)], markersize=4,
              markeredgecolor="k", markeredgewidth=0.4, zorder=4)
for ax in (wide, zoom):
    ax.axvline(t_star, color="k", linewidth=0.9, linestyle="--", zorder=5)
past = float(ds.theta[0]) - t_star
zoom.text(0.98, 0.03, f"$\\theta^* = {t_star:.6f}$\n$= \\pi/2 - \\pi/7$\n{float(ds.theta[0]):g}: $+${past:.1e}",
          transform=zoom.transAxes, fontsize=6, ha="right", va="bottom")
zoom.set_title(f"elliptic below $\\theta^* = {t_star:.6f}$", fontsize=7.5)
wide.set_ylim(-2.2, 8.0)
wide.axhline(-2.0, color="0.3", linewidth=0.5, linestyle=":")
wide.set_ylabel("$\\lambda + 1/\\lambda$")
wide.legend(fontsize=6, loc="upper left", handlelength=1.5)  # left of the theta* line
wide.set_title("elliptic where $|\\lambda + 1/\\lambda| < 2$", fontsize=7.5)
for ax in (growth, wide):   # each legend clear of the curves, inside its spines
    plot.check_legend(ax)
plot.save_figure(fig, snakemake.output.pdf)

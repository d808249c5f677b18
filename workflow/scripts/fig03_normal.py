"""Figure 3: terminal horizontal displacements, specular vs no-slip (gamma = 1/sqrt 2), with the share not arrived.

Top: the counts against the normal of the same sigma (the paper's view).  Bottom left: the same
distributions as densities on a log scale (the tails, where a normal law and a heavier-tailed one
differ).  Bottom right: the excess kurtosis against the number of rows (0 for a normal law).
"""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import matplotlib.ticker
import numpy as np

from noslipsim import plot
from noslipsim.analysis import excess_kurtosis

SPAN = 4.5  # half-width of the histogram, in standard deviations

ds = plot.load_figure_data(snakemake.input.distribution)
rows = plot.load_figure_data(snakemake.input.rows)
x = ds.x_terminal
# Particles cross the terminal depth in the gaps between the pegs of the terminal row, so the
# displacements cluster one spacing apart: one bin per bin_gaps gaps, centred on the gaps (other
# bins alias), over +-SPAN standard deviations of the wider law (the few beyond are not drawn).
width = snakemake.params.histogram["bin_gaps"] * ds.attrs["spacing"]
xs_all = x.values[np.isfinite(x.values)]
phase = np.angle(np.exp(2j * np.pi * xs_all / ds.attrs["spacing"]).mean()) / (2 * np.pi) * ds.attrs["spacing"]
reach = np.ceil(SPAN * float(x.std("particle").max()) / width) * width
edges = phase - width / 2 + np.arange(-reach, reach + width, width)
grid = np.linspace(edges[0], edges[-1], 400)

plot.use_style()
fig = plt.figure(figsize=(6.5, 5.2), constrained_layout=True)
top = fig.subfigures(2, 1, height_ratios=[1.0, 1.0])
axes = top[0].subplots(1, ds.sizes["law"], sharex=True, sharey=True)
low, kurt = top[1].subplots(1, 2)
for ax, i in zip(np.atleast_1d(axes), range(ds.sizes["law"])):
    case = ds.isel(law=i)
    law = str(case.law.values)
    xs = case.x_terminal.values[np.isfinite(case.x_terminal.values)]
    mean, std = xs.mean(), xs.std(ddof=1)
    ax.hist(xs, bins=edges, color=plot.law_color(law), alpha=0.75, label="arrived")
    gauss = len(xs) * width * np.exp(-0.5 * ((grid - mean) / std) ** 2) / (std * np.sqrt(2 * np.pi))
    ax.plot(grid, gauss, color="k", linewidth=0.8, label=f"normal, $\\sigma$ = {std:.2f}")
    name = "specular" if law == "specular" else f"no-slip, $\\gamma$ = {float(case.gamma):.3g}"
    ax.set_title(name)
    ax.text(0.02, 0.97, f"{case.sizes['particle']:,} particles\nnot arrived by\nT = {ds.attrs['max_time']:g}: "
            f"{float(case.share_not_arrived):.2%}", transform=ax.transAxes, va="top", fontsize=7)
    ax.set_xlabel("terminal horizontal displacement")
    ax.legend(loc="upper right", fontsize=7)
    # the log-density view: the histogram as a density, against the normal of the same sigma
    counts, _ = np.histogram(xs, bins=edges)
    dens = counts / (len(xs) * width)
    centres = 0.5 * (edges[:-1] + edges[1:])
    z = (centres - mean) / std
    k, ke = excess_kurtosis(xs)
    low.plot(z[counts > 0], dens[counts > 0] * std, "o" if law == "specular" else "s", markersize=3,
             color=plot.law_color(law), markerfacecolor="none" if law == "specular" else plot.law_color(law),
             alpha=0.9, label=f"{name}: $\\kappa$ = {k:.2f} ± {ke:.2f}", zorder=3 if law == "specular" else 2)
gaps = snakemake.params.histogram["bin_gaps"]
np.atleast_1d(axes)[0].set_ylabel(f"particles per bin ({gaps} gap{'s' * (gaps > 1)})")
zz = np.linspace(-SPAN, SPAN, 300)
low.plot(zz, np.exp(-0.5 * zz**2) / np.sqrt(2 * np.pi), color="k", linewidth=0.8, label="normal of the same $\\sigma$")
low.set(yscale="log", xlabel="displacement / $\\sigma$ (from the mean)", ylabel="density × $\\sigma$",
        xlim=(-SPAN, SPAN), ylim=(0.5 / len(xs_all), 1.0), title="the tails, log scale ($\\kappa$: excess kurtosis)")
low.legend(fontsize=5.5, loc="lower center")

# excess kurtosis against the number of rows (arrived particles), both laws
for j, law in enumerate(("specular", "no-slip")):
    ks = []
    for c in range(rows.sizes["case"]):
        v = rows.x_terminal.isel(case=c).sel(law=law).values
        ks.append(excess_kurtosis(v[np.isfinite(v)]))
    ks = np.array(ks)
    shift = 1.0 + 0.04 * (j - 0.5)  # the two laws side by side, not on top of each other
    # only particles arrived by T count: where many have not, say how many did (the sample is the faster ones)
    for r, (k, _), share in zip(rows.rows.values, ks, rows.share_not_arrived.sel(law=law).values):
        if share > 0.05:
            kurt.annotate(f"{1 - share:.0%}", (r * shift, k), textcoords="offset points",
                          xytext=(-12 if law == "specular" else 4, 6 if law == "specular" else -10), fontsize=6,
                          color=plot.law_color(law))
    kurt.errorbar(rows.rows.values * shift, ks[:, 0], yerr=ks[:, 1], marker="o" if law == "specular" else "s",
                  markersize=3.5, capsize=2, color=plot.law_color(law),
                  markerfacecolor="none" if law == "specular" else plot.law_color(law), linewidth=0.8,
                  label=law if law == "specular" else f"no-slip, $\\gamma$ = {float(rows.gamma.sel(law=law)):.3g}")
kurt.axhline(0.0, color="k", linewidth=0.6)
kurt.set_xscale("log")
kurt.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
kurt.set_xticks(rows.rows.values, [str(int(r)) for r in rows.rows.values])
kurt.set(xlabel="rows to the terminal depth", ylabel="excess kurtosis of the arrived",
         title=f"{rows.attrs['n_particles']:,} particles per point (% arrived by T)")
kurt.legend(fontsize=7, loc="upper right")
plot.save_figure(fig, snakemake.output.pdf)  # writes the .pdf and the .png beside it

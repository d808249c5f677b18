"""Figure 3: terminal horizontal displacements, specular vs no-slip (gamma = 1/sqrt 2), with the share not arrived.

Top: the counts against the normal of the same sigma (the paper's view), with the particles beyond
+-SPAN sigma counted.  Bottom left: the same distributions as densities on a log scale over every particle (the tails,
where a normal law and a heavier-tailed one differ).  Bottom middle and right: the excess kurtosis and the
share beyond 3 sigma against the number of rows (0 and 0.27 % for a normal law); a board where fewer than
ARRIVED_CLAIM of the particles arrived is drawn open and grey (its sample is the faster particles).
"""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import matplotlib.ticker
import numpy as np

from noslipsim import plot
from noslipsim.analysis import excess_kurtosis, tail_share

SPAN = 4.5  # half-width of the top histograms, in standard deviations (the few beyond are counted, not drawn)
ARRIVED_CLAIM = 0.95  # the rows panels claim only boards where at least this share arrived
SIGMAS = 3.0  # the robust tail statistic: share beyond SIGMAS standard deviations

ds = plot.load_figure_data(snakemake.input.distribution)
rows = plot.load_figure_data(snakemake.input.rows)
x = ds.x_terminal
spacing = ds.attrs["spacing"]
# Particles cross the terminal depth in the gaps between the pegs of the terminal row, so the
# displacements cluster one spacing apart: one bin per bin_gaps gaps, centred on the gaps (other
# bins alias).
width = snakemake.params.histogram["bin_gaps"] * spacing
xs_all = x.values[np.isfinite(x.values)]
phase = np.angle(np.exp(2j * np.pi * xs_all / spacing).mean()) / (2 * np.pi) * spacing


def edges_to(reach):
    """Bin edges centred on the gaps, covering [-reach, reach] around the gaps' phase."""
    reach = np.ceil(reach / width) * width
    return phase - width / 2 + np.arange(-reach, reach + width, width)


edges = edges_to(SPAN * float(x.std("particle").max()))  # the top panels: +-SPAN sigma of the wider law
edges_all = edges_to(np.abs(xs_all - phase).max() + width)  # the tails panel: every particle
grid = np.linspace(edges[0], edges[-1], 400)


def law_name(law, gamma):
    return "specular" if law == "specular" else f"no-slip, $\\gamma$ = {gamma:.3g}"


def law_marker(law):
    """Specular: open circles drawn on top; no-slip: filled squares (neither hides the other)."""
    filled = law != "specular"
    return dict(marker="s" if filled else "o", color=plot.law_color(law),
                markerfacecolor=plot.law_color(law) if filled else "none")


def counts_panel(ax, case, xs, mean, std):
    """The paper's view: counts per bin against the normal of the same sigma, the clipped ones counted.

    The text gives the share not arrived, the particles beyond SPAN standard deviations (the axes
    reach SPAN of the wider law's), the excess kurtosis and the share beyond SIGMAS standard
    deviations (the tails panel below draws every particle).
    """
    law = str(case.law.values)
    ax.hist(xs, bins=edges, color=plot.law_color(law), alpha=0.75, label="arrived")
    gauss = len(xs) * width * np.exp(-0.5 * ((grid - mean) / std) ** 2) / (std * np.sqrt(2 * np.pi))
    ax.plot(grid, gauss, color="k", linewidth=0.8, label=f"normal, $\\sigma$ = {std:.2f}")
    beyond = int(np.sum(np.abs(xs - mean) > SPAN * std))  # as galton.beyond_histogram_* counts them
    k, ke = excess_kurtosis(xs)
    p, pe, _ = tail_share(xs, sigmas=SIGMAS)
    ax.set_title(law_name(law, float(case.gamma)))
    ax.text(0.02, 0.97, f"{case.sizes['particle']:,} particles\nnot arrived by\nT = {ds.attrs['max_time']:g}: "
            f"{float(case.share_not_arrived):.2%}\nbeyond ±{SPAN:g}$\\sigma$: {beyond}\n"
            f"$\\kappa$ = {k:.2f} ± {ke:.2f}\nbeyond {SIGMAS:g}$\\sigma$: {p:.2%} ± {pe:.2%}", transform=ax.transAxes,
            va="top", fontsize=6.5)
    ax.set_xlabel("terminal horizontal displacement")
    ax.legend(loc="upper right", fontsize=7)


def tails_panel(ax, law, gamma, xs, mean, std):
    """Density x sigma on a log scale against z = (x - mean)/sigma, every particle drawn."""
    counts, _ = np.histogram(xs, bins=edges_all)
    dens = counts / (len(xs) * width)
    z = (0.5 * (edges_all[:-1] + edges_all[1:]) - mean) / std
    ax.plot(z[counts > 0], dens[counts > 0] * std, linestyle="none", markersize=3, alpha=0.9,
            zorder=3 if law == "specular" else 2, label=law_name(law, gamma), **law_marker(law))
    return np.abs(z[counts > 0]).max()


plot.use_style()
fig = plt.figure(figsize=(6.5, 5.6), constrained_layout=True)
top = fig.subfigures(2, 1, height_ratios=[1.0, 1.0])
axes = np.atleast_1d(top[0].subplots(1, ds.sizes["law"], sharex=True, sharey=True))
low, kurt, share = top[1].subplots(1, 3, width_ratios=[1.2, 1.0, 1.0])
zmax = SPAN
for ax, i in zip(axes, range(ds.sizes["law"])):
    case = ds.isel(law=i)
    xs = case.x_terminal.values[np.isfinite(case.x_terminal.values)]
    mean, std = xs.mean(), xs.std(ddof=1)
    counts_panel(ax, case, xs, mean, std)
    zmax = max(zmax, tails_panel(low, str(case.law.values), float(case.gamma), xs, mean, std))
gaps = snakemake.params.histogram["bin_gaps"]
axes[0].set_ylabel(f"particles per bin ({gaps} gap{'s' * (gaps > 1)})")
zmax = np.ceil(zmax + 0.5)
zz = np.linspace(-zmax, zmax, 400)
low.plot(zz, np.exp(-0.5 * zz**2) / np.sqrt(2 * np.pi), color="k", linewidth=0.8,
         label=f"normal (beyond {SIGMAS:g}$\\sigma$: {tail_share([0, 1])[2]:.2%})")
for side in (-SIGMAS, SIGMAS):
    low.axvline(side, color="0.6", linewidth=0.5, linestyle=":")
low.set(yscale="log", xlabel="displacement / $\\sigma$ (from the mean)", ylabel="density × $\\sigma$",
        xlim=(-zmax, zmax), ylim=(0.3 / len(xs_all), 1.0), title="every particle, log scale")
low.legend(fontsize=5.5, loc="lower center")  # the peak fills the top, the tails the sides


def against_rows(ax, statistic):
    """``statistic(sample) -> (value, error)`` of the arrived particles against the rows, both laws."""
    for j, law in enumerate(("specular", "no-slip")):
        shift = 1.0 + 0.05 * (j - 0.5)  # the two laws side by side, not on top of each other
        arrived = 1.0 - rows.share_not_arrived.sel(law=law).values
        values = np.array([statistic(v[np.isfinite(v)]) for v in rows.x_terminal.sel(law=law).values])
        ok = arrived >= ARRIVED_CLAIM
        style = law_marker(law)
        ax.errorbar(rows.rows.values[ok] * shift, values[ok, 0], yerr=values[ok, 1], markersize=3.5, capsize=2,
                    linewidth=0.8, label=law_name(law, float(rows.gamma.sel(law=law))), **style)
        # fewer arrived: the sample is the faster particles; drawn open and grey, not claimed
        ax.errorbar(rows.rows.values[~ok] * shift, values[~ok, 0], yerr=values[~ok, 1], marker=style["marker"],
                    markersize=3.5, capsize=2, linestyle="none", color="0.6", markerfacecolor="none")
        for r, v, a in zip(rows.rows.values[~ok], values[~ok, 0], arrived[~ok]):
            ax.annotate(f"{a:.1%}", (r * shift, v), textcoords="offset points", xytext=(4, -8 + 12 * j), fontsize=6,
                        color=plot.law_color(law))
    ax.set_xscale("log")
    ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
    ax.set_xticks(rows.rows.values, [str(int(r)) for r in rows.rows.values])
    ax.set_xlabel("rows")


against_rows(kurt, excess_kurtosis)
kurt.axhline(0.0, color="k", linewidth=0.6)
kurt.set(ylabel="excess kurtosis $\\kappa$", title="$\\kappa$ (0: normal)")
kurt.legend(fontsize=6, loc="upper right")
against_rows(share, lambda v: tail_share(v, sigmas=SIGMAS)[:2])
normal = tail_share([0, 1], sigmas=SIGMAS)[2]
share.axhline(normal, color="k", linewidth=0.6)
share.text(0.98, normal, "normal", transform=share.get_yaxis_transform(), ha="right", va="bottom", fontsize=6.5)
share.yaxis.set_major_formatter(matplotlib.ticker.PercentFormatter(1.0))
share.set(ylabel=f"share beyond {SIGMAS:g}$\\sigma$", title=f"beyond {SIGMAS:g}$\\sigma$")
top[1].suptitle(f"{rows.attrs['n_particles']:,} particles per board (rows to the terminal depth), deeper ones run "
                f"longer; grey: fewer than {ARRIVED_CLAIM:.0%} arrived (the share given)", fontsize=7)
plot.save_figure(fig, snakemake.output.pdf)  # writes the .pdf and the .png beside it

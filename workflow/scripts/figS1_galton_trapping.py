"""Figure S1: share not arrived against time (slow or trapped?) and the long-time share against peg radius."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from noslipsim import plot
from noslipsim.analysis import arrival_curve

arrivals = plot.load_figure_data(snakemake.input.arrivals)
sweep = plot.load_figure_data(snakemake.input.sweep)
curves = arrival_curve(arrivals)
long_run = arrival_curve(sweep)
T = arrivals.attrs["termination_time"]
at = arrival_curve(sweep, times=[T, sweep.attrs["max_time"]])  # not arrived by T and by the run's end
GAMMA_STYLES = ["-", "--", ":", "-."]

plot.use_style()
fig, (left, right) = plt.subplots(1, 2, figsize=(6.5, 2.8))
for i in range(curves.sizes["law"]):
    c = curves.isel(law=i)
    law = str(c.law.values)
    label = "specular" if law == "specular" else f"no-slip, $\\gamma$ = {float(c.gamma):.3g}"
    style = "-" if law == "specular" else GAMMA_STYLES[(i - 1) % len(GAMMA_STYLES)]
    keep = c.share_not_arrived > 0  # log axes
    left.plot(c.time[keep], c.share_not_arrived[keep], style, color=plot.law_color(law), label=label)
left.axvline(T, color="0.5", linewidth=0.6)
left.text(T, 0.98, " T", color="0.4", va="top", fontsize=7, transform=left.get_xaxis_transform())
left.set(xscale="log", yscale="log", xlabel="time", ylabel="share not arrived",
         title=f"{arrivals.attrs['n_particles']:,} particles per case")
left.legend(fontsize=7, loc="lower left")

step = 0.015 * float(np.ptp(at.radius.values))  # the laws side by side: specular points never hide under no-slip ones
for law, shift, marker, z in (("no-slip", step, "s", 2), ("specular", -step, "o", 3)):
    sel = at.sel(law=law)
    for k, (fill, when) in enumerate((("none", "T"), (None, f"{sweep.attrs['time_factor']:g} T"))):
        right.errorbar(sel.radius + shift, sel.share_not_arrived.isel(time=k),
                       yerr=sel.share_not_arrived_stderr.isel(time=k), marker=marker, markersize=3, capsize=2,
                       color=plot.law_color(law), markerfacecolor=fill, linestyle="--" if k == 0 else "-",
                       linewidth=0.8, zorder=z, label=f"{law}, not arrived by {when}")
sel = long_run.sel(law="no-slip")
# the tail estimate only where it extrapolates (late arrivals still decaying): elsewhere it is the 10 T share again
ok = np.isfinite(sel.trapped_share) & (sel.arrivals_late > 0) & (sel.share_not_arrived_final > 0)
if bool(ok.any()):
    right.plot(sel.radius[ok], sel.trapped_share[ok], "x", color="k", markersize=4,
               label="no-slip, never arriving (tail extrapolated)")
right.axvline(sweep.attrs["board_radius"], color="0.5", linewidth=0.6, linestyle="--")
right.set(xlabel=f"peg radius (spacing {sweep.attrs['spacing']:g})", ylabel="share not arrived", ylim=(-0.02, 1.0),
          title=f"{sweep.attrs['n_particles']:,} particles per radius, {sweep.attrs.get('board', 'unbounded')} board")
right.legend(fontsize=7, loc="upper left")
plot.save_figure(fig, snakemake.output.pdf)  # writes the .pdf and the .png beside it

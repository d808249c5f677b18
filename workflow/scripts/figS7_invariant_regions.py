"""Figure S7: invariant regions around the two-disk path-reversing orbits as the force grows (the invariant-regions
conjecture).  Left: the region's area against the force, per flight and branch.  Middle: the share of starts that
stay, ring by ring.  Right: every start by outcome (stays, converges onto an attractor, escapes, stopped by the
engine for another reason)."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.ticker import NullFormatter

from noslipsim import plot
from noslipsim.experiments.invariant import OUTCOMES, region_counts

ds = plot.load_figure_data(snakemake.input.invariant, required=["start_outcome", "region_area"])
counts = region_counts(ds)
OUTCOME_COLORS = {"invariant": plot.law_color("no-slip"), "attracted": "#E69F00", "escaped": "0.8",
                  "stopped": "0.4"}
CASES = [(f, b) for f in ds.flight.values for b in ds.branch.values if int(ds.exists.sel(flight=f, branch=b).sum())]
# open markers and dashes after the first case: equal areas or shares of two cases stay visible
STYLE = {case: dict(color=color, marker=marker, fillstyle=fill, linestyle=line) for case, color, marker, fill, line in
         zip(CASES, plot.SERIES_COLORS, "osD^v", ("full", "none", "none", "none"), ("-", "--", ":", "-."))}


def label(flight, branch):
    kinds = {str(k) for k in ds.linear_kind.sel(flight=flight, branch=branch).values if str(k)}
    return f"{flight}, {branch}" + (f" ({'/'.join(sorted(kinds))})" if kinds else "")


plot.use_style()
fig, (area, share, bars) = plt.subplots(1, 3, figsize=(6.5, 2.6), width_ratios=(1.0, 1.0, 1.2))
g = ds.force.values
for flight, branch in CASES:
    case = ds.sel(flight=flight, branch=branch)
    area.plot(g, case.region_area, label=label(flight, branch), linewidth=1.0, markersize=3,
              **STYLE[(flight, branch)])
area.set(xscale="log", xlabel="force g (unit speed)", ylabel="region area (rad × spin/speed)",
         title="every start stays")
area.set_xticks(g, [f"{x:g}" for x in g])
area.xaxis.set_minor_formatter(NullFormatter())
fig.legend(*area.get_legend_handles_labels(), fontsize=6.5, loc="outside upper center", ncol=len(CASES))

staying = ds.starts_by_outcome.sel(outcome="invariant") / ds.sizes["start"]
for flight, branch in CASES:
    for j, f in enumerate(g):
        if int(ds.exists.sel(flight=flight, branch=branch, force=f)):
            share.plot(ds.ring_radius, staying.sel(flight=flight, branch=branch, force=f), linewidth=0.8,
                       alpha=0.35 + 0.65 * (j + 1) / g.size, color=STYLE[(flight, branch)]["color"],
                       linestyle=STYLE[(flight, branch)]["linestyle"])
share.set(xlabel="ring radius", ylabel="share of starts that stay", ylim=(-0.03, 1.03),
          title="darker: larger force")

rows = [(f, b, x) for f, b in CASES for x in g if int(ds.exists.sel(flight=f, branch=b, force=x))]
left = np.zeros(len(rows))
for outcome in OUTCOMES:
    n = np.array([int(counts.starts.sel(flight=f, branch=b, force=x, outcome=outcome)) for f, b, x in rows])
    bars.barh(np.arange(len(rows)), n, left=left, color=OUTCOME_COLORS[outcome], label=f"{outcome}: {n.sum()}")
    left += n
bars.set_yticks(np.arange(len(rows)), [f"{'ff' if f == 'free fall' else 'iso'} {b} g={x:g}" for f, b, x in rows],
               fontsize=5.5)
bars.invert_yaxis()
bars.set(xlabel="starts", xlim=(0, 1.75 * left.max()))   # room on the right for the legend, clear of the bars
bars.set_title(f"{int(left.sum())} starts, {ds.attrs['max_collisions']:,} collisions", fontsize=8)
bars.legend(fontsize=5.5, loc="center right")
plot.check_legend(bars)
plot.save_figure(fig, snakemake.output.pdf)

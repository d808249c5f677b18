"""Figure S5: periodic orbits of no-slip wedges under a force from random starts.  Left: every search by outcome,
per requested period.  Right: the distinct orbits found, per minimal period, isolated (no eigenvalue 1) or on a
family."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from noslipsim import plot
from noslipsim.experiments import census_counts

ds = plot.load_figure_data(snakemake.input.census, required=["residual"])
counts = census_counts(ds)
OUTCOME_COLORS = {"found": plot.law_color("no-slip"), "not converged": "0.6", "no return": "0.85"}

plot.use_style()
fig, (left, right) = plt.subplots(1, 2, figsize=(6.5, 2.8))
bottom = np.zeros(counts.sizes["period"])
for outcome, color in OUTCOME_COLORS.items():
    n = counts.searches.sel(outcome=outcome).values
    left.bar(counts.period, n, bottom=bottom, color=color, label=outcome)
    bottom += n
left.set(xlabel="period requested", ylabel="searches", xticks=counts.period.values,
         title=f"{ds.sizes['search']:,} searches")
left.legend(fontsize=7, loc="upper right")

m = counts.minimal_period.values
right.bar(m, counts.family, color="#56B4E9", label="on a family (eigenvalue 1)")
right.bar(m, counts.isolated, bottom=counts.family, color=plot.law_color("no-slip"), label="isolated")
for x, n in zip(m, counts.distinct.values):   # the small counts would not show as bars
    if n:
        right.text(x, n, f"{int(n)}", ha="center", va="bottom", fontsize=6)
right.set(xlabel="minimal period", ylabel="distinct orbits", xticks=m, ylim=(0, 1.12 * int(counts.distinct.max()) + 1),
          title=f"{int(counts.isolated.sum())} isolated of {int(counts.distinct.sum())} distinct")
right.legend(fontsize=7, loc="upper right")
plot.save_figure(fig, snakemake.output.pdf)

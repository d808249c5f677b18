"""Figure S6: non-path-reversing 2-periodic orbits between pairs of boundary points (conjecture, part i).  Top:
every sampled pair by outcome, per table: random pairs (left), balanced pairs (right; the only ones that can carry
such an orbit).  Bottom: on two tables (other than a wedge where there are), the orbit found whose two flight times are
the most even, both flights drawn exactly."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.ticker import MaxNLocator

from noslipsim import plot
from noslipsim.experiments.accessible import OUTCOMES, accessible_table, pair_counts

ds = plot.load_figure_data(snakemake.input.accessible, required=["balance"])
counts = pair_counts(ds)
COLORS = {"found": plot.law_color("no-slip"), "not found": "0.45", "not periodic": "#E69F00",
          "not minimal": "#CC79A7", "unbalanced": "0.7", "inaccessible": "0.88"}


def examples():
    """Two tables whose first found orbit is drawn: tables other than wedges first (a wedge's is Figure 7's)."""
    found = [str(t) for t in counts.table.values
             if int(counts.pairs.sel(table=t, sample="balanced", outcome="found"))]
    return ([t for t in found if "wedge" not in t] + [t for t in found if "wedge" in t])[:2]


def outcome_bars(ax, sample):
    """Horizontal bars per table, stacked by outcome; returns the total of pairs."""
    names = counts.table.values
    left = np.zeros(names.size)
    for outcome in OUTCOMES:
        n = counts.pairs.sel(sample=sample, outcome=outcome).values
        if n.any():
            ax.barh(np.arange(names.size), n, left=left, color=COLORS[outcome], label=outcome)
        left += n
    ax.set_yticks(np.arange(names.size), names, fontsize=7)
    ax.invert_yaxis()
    ax.set_xlabel("pairs")
    ax.xaxis.set_major_locator(MaxNLocator(integer=True))
    return int(left.sum())


def flights(o, gravity):
    """The two parabolic flights of a found orbit, ``q0 -> q1`` in time ``T`` and back in ``T2``."""
    a = np.array([0.0, -gravity])
    q0, q1 = np.array([float(o.q0_x), float(o.q0_y)]), np.array([float(o.q1_x), float(o.q1_y)])
    out = []
    for start, end, T in ((q0, q1, float(o.flight_time)), (q1, q0, float(o.flight_time_back))):
        v = (end - start) / T - 0.5 * a * T
        t = np.linspace(0.0, T, 200)[:, None]
        out.append(start + v * t + 0.5 * a * t * t)
    return out


plot.use_style()
fig, axes = plt.subplots(2, 2, figsize=(6.5, 5.2), height_ratios=(1.0, 1.25))
n_random = outcome_bars(axes[0, 0], "random")
axes[0, 0].set_title(f"{n_random} random pairs", fontsize=8)
n_balanced = outcome_bars(axes[0, 1], "balanced")
axes[0, 1].set_yticklabels([])
axes[0, 1].set_title(f"{n_balanced} balanced pairs", fontsize=8)
handles = {h.get_label(): h for ax in axes[0] for h in ax.get_legend_handles_labels()[0]}
fig.legend([handles[o] for o in OUTCOMES if o in handles], [o for o in OUTCOMES if o in handles], fontsize=6.5,
           loc="outside upper center", ncol=6)

gravity = float(ds.attrs["gravity"])
for ax in axes[1][len(examples()):]:
    ax.remove()   # fewer than two tables with an orbit: no empty panel
for ax, name in zip(axes[1], examples()):
    rows = np.flatnonzero((ds.table.values == name) & (ds.outcome.values == "found"))
    ax.set_xticks([])
    ax.set_yticks([])
    o = ds.isel(pair=int(rows[0]))
    scene = accessible_table(name, float(ds.attrs["gamma"]), gravity)
    paths = flights(o, gravity)
    pts = np.vstack(paths)
    box = np.array([e.bbox() for e in scene.elements if np.isfinite(e.bbox()).all()]).reshape(-1, 4)  # all pieces
    xs, ys = np.r_[pts[:, 0], box[:, 0], box[:, 2]], np.r_[pts[:, 1], box[:, 1], box[:, 3]]
    plot.draw_table(ax, scene, plot.view_window(scene, (xs, ys)))
    for path, color in zip(paths, plot.SERIES_COLORS):
        ax.plot(path[:, 0], path[:, 1], color=color, linewidth=1.0)
    ax.plot([float(o.q0_x), float(o.q1_x)], [float(o.q0_y), float(o.q1_y)], "o", color="k", markersize=3)
    ax.set_title(f"{name}: {o.linear_kind.values}, $T'/T$ = {float(o.flight_time_back) / float(o.flight_time):.2f}\n"
                 f"orbits confirmed: {int(counts.orbits.sel(table=name).sum())}, on "
                 f"{int(counts.pairs.sel(table=name, sample='balanced', outcome='found'))} pair(s)", fontsize=7.5)
plot.save_figure(fig, snakemake.output.pdf)

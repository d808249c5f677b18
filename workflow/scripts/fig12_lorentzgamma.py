"""Figure 12: velocity portraits of the no-slip Sinai torus against gamma; below, the regular share and its onset."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from noslipsim import plot
from noslipsim.analysis import classify_regular, islands_onsets

PAPER_ONSET = 0.3  # the paper: "no signs of invariant regions (closed loops) until gamma > 0.3"

threshold = snakemake.params.threshold
ds = classify_regular(plot.load_figure_data(snakemake.input.portraits), threshold)
isl = islands_onsets(plot.load_figure_data(snakemake.input.islands), threshold, snakemake.params.level)
n = ds.sizes["gamma"]

plot.use_style()
fig = plt.figure(figsize=(6.5, 4.9))
grid = fig.add_gridspec(2, n, height_ratios=[1.0, 1.1])
for i, g in enumerate(ds.gamma.values):
    ax = fig.add_subplot(grid[0, i])
    case = ds.isel(gamma=i)
    plot.draw_layered_portrait(ax, case, case.regular, size=0.1)
    ax.set_title(f"$\\gamma$ = {g:g}\nregular {float(case.regular.mean()):.1%}")
    if i:
        ax.set_ylabel("")

ax = fig.add_subplot(grid[1, :])
level = isl.attrs["visible_share"]
for k, R in enumerate(isl.radius.values):
    case = isl.isel(radius=k)
    color = f"C{k}"
    ax.errorbar(case.gamma, case.share_regular, case.share_regular_stderr, color=color, marker="o", markersize=2.5,
                linewidth=0.8, capsize=1.5, label=f"$R$ = {R:g}" + (" (portraits above)" if k == 0 else ""))
    onset, low, high = (float(case[v]) for v in ("onset_gamma", "onset_gamma_low", "onset_gamma_high"))
    ax.axvspan(low, high, color=color, alpha=0.25, linewidth=0)
    ax.plot([onset], [level], marker="v", color=color, markersize=5,
            label=f"islands visible: $\\gamma$ = {onset:.3f} ± {float(case.onset_gamma_stderr):.3f}")
    ax.axvline(float(case.head_on_onset), color=color, linestyle=":", linewidth=0.9,
               label=f"head-on 2-periodic orbit elliptic: $\\gamma > {float(case.head_on_onset):.3f}$")
# the portraits' own shares (the panel titles): fewer orbits, a longer exponent window, so not the curve's points
shares = ds.regular.mean("orbit")
spread = (shares * (1 - shares) / ds.sizes["orbit"]) ** 0.5   # binomial standard error
ax.errorbar(ds.gamma, shares, spread, color="C0", marker="s", markersize=4, markerfacecolor="white", linestyle="none",
            capsize=1.5, zorder=4, clip_on=False, label=f"titles above ({ds.attrs['n_orbits']} orbits)")
ax.axhline(level, color="0.4", linestyle="--", linewidth=0.6, label=f"visibility level {level:.0%}")
ax.axvline(PAPER_ONSET, color="k", linestyle="-.", linewidth=0.7, label=f"paper: $\\gamma > {PAPER_ONSET:g}$")
ax.set_xlim(float(isl.gamma.min()), float(isl.gamma.max()))
ax.set_ylim(bottom=-0.01)
ax.set_xlabel("$\\gamma$")
ax.set_ylabel("regular share")
ax.set_title(f"share of {isl.attrs['n_orbits']} orbits (uniform in $ds\\,dv_t\\,dw$) whose finite-time Lyapunov "
             f"exponent over {isl.attrs['lyapunov_collisions']} collisions is < {isl.attrs['regular_threshold']:g}",
             fontsize=8)
handles, labels = ax.get_legend_handles_labels()
order = sorted(range(len(labels)), key=lambda i: (not labels[i].startswith(("$R$", "titles")), i))  # data first
ax.legend([handles[i] for i in order], [labels[i] for i in order], loc="upper center", bbox_to_anchor=(0.5, -0.22),
          fontsize=6.5, ncol=3)  # framed (style), below the axis: off the data
fig.suptitle(f"no-slip Sinai torus, scatterer radius $R$ = {ds.attrs['radius']:g} (unit torus); grey: chaotic "
             "orbits, colours: regular orbits", fontsize=8)
plot.save_figure(fig, snakemake.output.pdf)  # writes the .pdf and the .png beside it

"""Figure S2: what the Galton board's not-arrived share depends on.

The drop, the release, the peg radius, the rows and the side walls; the last panel sets side by side the
boards that all leave about 40 % not arrived by T, which only the share still out at 10 T tells apart.
"""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import matplotlib.ticker
import numpy as np

from noslipsim import plot
from noslipsim.analysis import arrival_curve

ev = plot.load_figure_data(snakemake.input.evidence)
T, factor = ev.attrs["termination_time"], ev.attrs["time_factor"]
DROPS = {"board": ("bounded board", "o", "-"), "gap": ("gap drop", "s", "--")}
DROP_CURVES = {**DROPS, "gap-bounded": ("gap drop, bounded board", "^", ":")}
WHEN = ((T, "T", "none"), (factor * T, f"{factor:g} T", None))  # open markers by T, filled by 10 T


def not_arrived(case, law, by):
    t = ev.t_terminal.sel(case=case, law=law).values
    p = np.mean(~(t <= by))
    return p, np.sqrt(p * (1 - p) / t.size)


def cases_of(group, drop=None):
    out = [str(c) for c in ev.case.values if str(ev.group.sel(case=c).values) == group
           and (drop is None or str(c).startswith(drop + "-"))]
    return out + ([drop] if drop else [])


plot.use_style()
fig, axes = plt.subplots(3, 2, figsize=(6.5, 8.0), constrained_layout=True)
(a, b), (c, d), (walls, readings) = axes

# (a) share not arrived against time, both drops, both laws
# the gap drop on the bounded board: energy keeps a particle dropped in the top gap below the next row's
# pegs, so its arrival times are those of the unbounded lattice; drawn only if they differ
same = np.array_equal(ev.t_terminal.sel(case="gap").values, ev.t_terminal.sel(case="gap-bounded").values,
                      equal_nan=True)
drops = DROPS if same else DROP_CURVES
curves = arrival_curve(ev.sel(case=list(drops)))
for drop, (label, _, style) in drops.items():
    for law in ("specular", "no-slip"):
        cur = curves.sel(case=drop, law=law)
        keep = cur.share_not_arrived > 0
        a.plot(cur.time[keep], cur.share_not_arrived[keep], style, color=plot.law_color(law),
               label=f"{law}, {label}")
a.axvline(T, color="0.5", linewidth=0.6)
a.text(T, 0.02, " T", color="0.4", va="bottom", fontsize=7, transform=a.get_xaxis_transform())
if same:
    a.text(0.03, 0.58, "gap drop on the bounded board:\nthe same arrival times", transform=a.transAxes,
           ha="left", va="top", fontsize=6.5, color="0.3")
a.set(xscale="log", yscale="log", xlabel="time", ylabel="share not arrived", title="(a) the drop")
a.legend(fontsize=6.5, loc="best")  # clear of the curves wherever this run's arrivals put them
if plot.legend_problems(a):  # no free corner inside: beneath the axes, where nothing is drawn
    a.legend(fontsize=6, loc="upper center", bbox_to_anchor=(0.5, -0.22), ncol=2)

# (b) the bounded board's release: point, spread, speed (no-slip)
groups = [("point", lambda k: f"({float(k.start_x):g}, {float(k.start_y):g})"),
          ("spread", lambda k: f"{float(k.spread):g}"), ("speed", lambda k: f"{float(k.speed):g}")]
ticks, labels, x = [], [], 0
for g, (group, name) in enumerate(groups):
    sel = [*cases_of(group), "board"]
    key = ((lambda k: (float(ev.start_y.sel(case=k)), float(ev.start_x.sel(case=k)))) if group == "point"
           else (lambda k, group=group: float(ev[group].sel(case=k))))
    for case in sorted(sel, key=key):
        for by, when, fill in WHEN:
            p, e = not_arrived(case, "no-slip", by)
            b.errorbar(x, p, yerr=e, marker="o", markersize=3.5, capsize=2, color=plot.law_color("no-slip"),
                       markerfacecolor=fill, linestyle="none",
                       label=f"no-slip, by {when}" if (x == 0) else None)
        ticks.append(x)
        labels.append(name(ev.sel(case=case)) + (" *" if case == "board" else ""))
        x += 1
    b.text(x - 1 - (len(sel) - 1) / 2, 1.02, group, ha="center", va="bottom", fontsize=7,
           transform=b.get_xaxis_transform())
    if g < len(groups) - 1:
        b.axvline(x - 0.5, color="0.7", linewidth=0.6)
b.set_xticks(ticks, labels, rotation=60, fontsize=6, ha="right")
b.set(ylabel="share not arrived", ylim=(-0.02, 1.0))
b.set_title("(b) the release (bounded board)", pad=12)
b.legend(fontsize=6.5, loc="upper right")

# (c, d) peg radius and rows, both drops
for ax, group, xlabel, title in ((c, "radius", f"peg radius (spacing {ev.attrs['spacing']:g})", "(c) the peg radius"),
                                 (d, "rows", "rows to the terminal depth", "(d) the number of rows")):
    for drop, (label, marker, _) in DROPS.items():
        sel = sorted(cases_of(group, drop), key=lambda k: float(ev[group].sel(case=k)))
        xs = [float(ev[group].sel(case=k)) for k in sel]
        for by, when, fill in WHEN:
            ps = np.array([not_arrived(k, "no-slip", by) for k in sel])
            ax.errorbar(xs, ps[:, 0], yerr=ps[:, 1], marker=marker, markersize=3.5, capsize=2,
                        color=plot.law_color("no-slip"), markerfacecolor=fill,
                        linestyle="--" if fill == "none" else "-", linewidth=0.8,
                        label=f"no-slip, {label}, by {when}")
        ps = np.array([not_arrived(k, "specular", T) for k in sel])
        ax.plot(xs, ps[:, 0], marker=marker, markersize=3, color=plot.law_color("specular"),
                markerfacecolor="none", linestyle=":", linewidth=0.8, label=f"specular, {label}, by T")
    ax.set(xlabel=xlabel, ylabel="share not arrived", ylim=(-0.02, 1.0), title=title)
    if group == "rows":
        ax.set_xscale("log")
        ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        ax.set_xticks(sorted({float(v) for v in ev.rows.values}), [f"{int(v)}" for v in sorted(set(ev.rows.values))])
c.legend(fontsize=5.5, loc="upper left")
d.text(0.97, 0.97, "markers and lines as in (c)", transform=d.transAxes, ha="right", va="top", fontsize=6,
       color="0.3")


def by_t_and_10t(ax, xs, cases, connect=True, **style):
    """No-slip shares not arrived by T (open, dashed) and by 10 T (filled, solid) at ``xs``."""
    for by, when, fill in WHEN:
        ps = np.array([not_arrived(k, "no-slip", by) for k in cases])
        line = ("--" if fill == "none" else "-") if connect else "none"  # categories are not joined
        ax.errorbar(xs, ps[:, 0], yerr=ps[:, 1], capsize=2, color=plot.law_color("no-slip"), markerfacecolor=fill,
                    linestyle=line, linewidth=0.8, label=f"no-slip, by {when}", **style)


# (e) the side walls: walled boards of several half-widths, against the same board without walls
def walled_cases(wall_law):
    """Cases of the walled boards whose walls have ``wall_law`` ('pegs': the pegs' law), by width."""
    return sorted((k for k in cases_of("width") if str(ev.wall_law.sel(case=k).values) == wall_law),
                  key=lambda k: float(ev.width.sel(case=k)))


walled = walled_cases("pegs")
widths = [float(ev.width.sel(case=k)) for k in walled]
by_t_and_10t(walls, widths, walled, marker="o", markersize=3.5)
specular_walls = walled_cases("specular")
for by, when, fill in WHEN:
    ps = np.array([not_arrived(k, "no-slip", by) for k in specular_walls]).reshape(-1, 2)
    beside = [1.08 * float(ev.width.sel(case=k)) for k in specular_walls]  # beside the pegs' walls, not on top
    walls.errorbar(beside, ps[:, 0], yerr=ps[:, 1], marker="^", markersize=4, capsize=2, linestyle="none",
                   color=plot.law_color("no-slip"), markerfacecolor=fill, label=f"no-slip, specular walls, by {when}")
ps = np.array([not_arrived(k, "specular", T) for k in walled])
walls.plot(widths, ps[:, 0], marker="o", markersize=3, color=plot.law_color("specular"), markerfacecolor="none",
           linestyle=":", linewidth=0.8, label="specular, by T")
drawn = [not_arrived(k, "no-slip", T)[0] for k in walled + specular_walls + ["board"]]
top = min(1.0, max(0.25, 1.4 * max(drawn)))  # the walled shares are small: an axis to their scale
for by, when, fill in WHEN:
    p, _ = not_arrived("board", "no-slip", by)
    walls.axhline(p, color=plot.law_color("no-slip"), linewidth=0.6, linestyle="--" if fill == "none" else "-",
              alpha=0.5)
    walls.text(0.99, p, f"no walls, by {when}", transform=walls.get_yaxis_transform(), fontsize=6, va="bottom",
           ha="right", color=plot.law_color("no-slip"))
walls.set_xscale("log")
walls.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
walls.set_xticks(widths, [f"{w:g}" for w in widths])
walls.set_xlim(widths[0] / 1.5, widths[-1] * 3.0)  # room for the no-walls labels on the right
walls.set(xlabel="half-width of the walled board (walls at x = ±width)", ylabel="share not arrived",
          ylim=(-0.02 * top, top),
      title="(e) the side walls (walls of the pegs' law unless said)")
walls.legend(fontsize=5.5, loc="upper left")

# (f) the readings near 40 % by T: by T alone they look alike, by 10 T the trapped one stands out
board_rows, board_radius = ev.attrs["board_rows"], ev.attrs["board_radius"]
near = [("gap", f"gap drop\n(r = {board_radius:g}, {board_rows} rows)")]
near += [(k, f"bounded board,\n{int(ev.rows.sel(case=k))} rows") for k in cases_of("rows", "board")
         if int(ev.rows.sel(case=k)) == 2 * board_rows]
near += [(k, f"bounded board,\nr = {float(ev.radius.sel(case=k)):g}") for k in cases_of("radius", "board")
         if abs(not_arrived(k, "no-slip", T)[0] - not_arrived("gap", "no-slip", T)[0]) < 0.1]
by_t_and_10t(readings, np.arange(len(near)), [k for k, _ in near], connect=False, marker="s", markersize=4)
readings.set_xticks(np.arange(len(near)), [name for _, name in near], fontsize=6.5)
readings.set_xlim(-0.5, len(near) - 0.5)
readings.set(ylabel="share not arrived", ylim=(-0.02, 1.0), title=f"(f) alike by T, apart by {factor:g} T")
readings.legend(fontsize=6.5, loc="upper right")
fig.suptitle(f"no-slip γ = {float(ev.gamma.sel(law='no-slip')):.3g}; {ev.attrs['n_particles']:,} particles per case "
             f"and law; T = {T:g}", fontsize=8)
plot.save_figure(fig, snakemake.output.pdf)  # writes the .pdf and the .png beside it

"""Figure 7: wedges under gravity (force down). Left: four path-reversing 2-periodic orbits; left centre: the
same in a wedge opening down; right centre: a period-8 orbit; right: a 2-periodic orbit that is not path reversing."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from noslipsim import plot

MARGIN = 0.12  # share of the orbits' extent shown around them

ds = plot.load_figure_data(snakemake.input.orbits)
cases = ds.case.values.astype(str)
panels = [("path-reversing, 2-periodic", np.flatnonzero(cases == "path-reversing")),
          ("wedge opening down", np.flatnonzero(cases == "path-reversing, wedge opening down"))]
panels += [(c, np.flatnonzero(cases == c)) for c in dict.fromkeys(cases) if not c.startswith("path-reversing")]
panels = [(title, rows) for title, rows in panels if rows.size]


def describe(o):
    ev = o.eigenvalue_real.values + 1j * o.eigenvalue_imag.values
    rot = np.abs(np.angle(ev)).max()
    text = f"{o.linear_kind.values},\neigenvalues 1, $e^{{\\pm {rot:.3f} i}}$" if o.linear_kind == "elliptic" \
        else f"{o.linear_kind.values}, $|\\lambda| = {np.abs(ev).max():.3g}$"
    if not int(o.path_reversing):
        text += f"\n$\\max|v_t - \\gamma w|/|V| = {float(o.reversal_mismatch):.2f}$"
    return text


plot.use_style()
fig, axes = plt.subplots(1, len(panels), figsize=(6.5, 2.1))
windows = []
for _, rows in panels:
    paths = [plot.orbit_path(ds.isel(orbit=int(i))) for i in rows]
    x = np.concatenate([p[0] for p in paths] + [[0.0]])   # the vertex at the origin stays in view
    y = np.concatenate([p[1] for p in paths] + [[0.0]])
    pad = MARGIN * max(np.ptp(x), np.ptp(y))
    half = max(np.abs(x).max(), 0.5 * (np.ptp(y) + 2 * pad)) + pad   # centred on the bisector
    windows.append((-half, half, y.min() - pad, y.max() + pad))
windows = plot.equal_windows(windows)  # one box shape for all: equal panels, titles in line
for ax, (title, rows), window in zip(np.atleast_1d(axes), panels, windows):
    plot.draw_table(ax, ds.isel(orbit=int(rows[0])), window)
    for k, i in enumerate(rows):
        o = ds.isel(orbit=int(i))
        # several launch angles: one series colour each; a single orbit: its law's colour
        color = plot.SERIES_COLORS[k % len(plot.SERIES_COLORS)] if len(rows) > 1 else None
        plot.draw_orbit(ax, o, color=color, linewidth=0.9, ends=False, label=f"{float(o.theta):g}")
    note = "" if len(rows) > 1 else "\n" + describe(ds.isel(orbit=int(rows[0])))
    ax.set_title(f"{title}{note}", fontsize=7.5)
    ax.set_xticks([])
    ax.set_yticks([])
    # the caption's downward force, in the shaded region left of the left wall (every panel has one there)
    plot.draw_force_arrow(ax, plot.scene_of(ds.isel(orbit=int(rows[0]))).force, tail=(0.11, 0.52), length=0.2)
    if len(rows) > 1:   # the key from colour to launch angle, below the panel: off the orbits
        plot.frame_legend(ax, outside="below", ncol=2, title="launch angle $\\theta$", fontsize=6.5,
                          title_fontsize=6.5, handlelength=1.2, columnspacing=0.8)
plot.save_figure(fig, snakemake.output.pdf)

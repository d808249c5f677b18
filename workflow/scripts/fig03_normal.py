"""Figure 3: terminal horizontal displacements, specular vs no-slip (gamma = 1/sqrt 2), with the share not arrived."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from noslipsim import plot

SPAN = 4.5  # half-width of the histogram, in standard deviations

ds = plot.load_figure_data(snakemake.input.distribution)
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
fig, axes = plt.subplots(1, ds.sizes["law"], figsize=(6.5, 2.6), sharex=True, sharey=True)
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
gaps = snakemake.params.histogram["bin_gaps"]
axes[0].set_ylabel(f"particles per bin ({gaps} gap{'s' * (gaps > 1)})")
plot.save_figure(fig, snakemake.output.pdf)  # writes the .pdf and the .png beside it

"""The paper's Galton numbers, computed: shares not arrived at T and at 10 T, terminal standard deviations, kurtosis."""
import json
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import numpy as np
import xarray as xr

from noslipsim.analysis import arrival_curve, excess_kurtosis, tail_share
from noslipsim.plot.numbers import rounded, significant

dist = xr.load_dataset(snakemake.input.distribution)
long_run = xr.load_dataset(snakemake.input.arrivals)
sweep = xr.load_dataset(snakemake.input.sweep)
rows = xr.load_dataset(snakemake.input.rows)
T, n = dist.attrs["max_time"], dist.attrs["n_particles"]
# Each value is kept to the digits its computation determines (docs/figures.md, "Which numbers and figures are the
# same on every machine").  A share of n <= 1e5 particles is k/n: 6 significant digits tell every k apart.  A
# statistic of many samples (standard deviation, kurtosis) carries summation-order noise in its last bits and a
# sampling error in its third digit: 6 significant digits.  A standard error is itself uncertain by about
# 1/sqrt(2n) (a bootstrap's by its resampling): 3 significant digits.
SHARE, STATISTIC, ERROR = 6, 6, 3
gamma = float(dist.gamma.sel(law="no-slip"))
board = (f"the {dist.attrs['board']} board" + (f", released at {dist.attrs['start']} ± {dist.attrs['spread']:g} with "
                                               f"speed {dist.attrs['speed']:g}" if dist.attrs["board"] == "bounded"
                                               else f", dropped at {dist.attrs['start']}"))


def share(ds, law, gamma=None):
    """Share not arrived by the run's end and its binomial standard error, for one case."""
    case = ds.isel(law=next(i for i, (name, g) in enumerate(zip(ds.law.values, ds.gamma.values))
                        if name == law and (gamma is None or np.isclose(g, gamma))))
    p = float(case.share_not_arrived)
    return significant(p, SHARE), significant(np.sqrt(p * (1 - p) / case.sizes["particle"]), ERROR)


def arrived_x(law):
    x = dist.x_terminal.sel(law=law).values
    return x[np.isfinite(x)]


numbers = {}
p, e = share(dist, "no-slip", gamma)
numbers["share_not_arrived_noslip"] = dict(
    description=f"no-slip (γ = {gamma:.3g}) share not arrived by the termination time T = {T:g}",
    value=p, stderr=e, format=".2%", paper="roughly 40 %",
    note=f"{n:,} particles, {board}; the paper's drop reading gives 40 % (evidence numbers, Figure S2)")
p, e = share(dist, "specular")
numbers["share_not_arrived_specular"] = dict(
    description=f"specular share not arrived by T = {T:g}", value=p, stderr=e, format=".2%",
    paper="almost none", note=f"{n:,} particles")
for law in ("specular", "no-slip"):
    numbers[f"std_terminal_{law.replace('-', '')}"] = dict(
        description=f"{law} standard deviation of the terminal horizontal displacement",
        value=significant(np.std(arrived_x(law), ddof=1), STATISTIC), format=".2f",
        paper="similar for both laws (no value given)")
for law in ("specular", "no-slip"):
    k, ke = excess_kurtosis(arrived_x(law))
    numbers[f"kurtosis_terminal_{law.replace('-', '')}"] = dict(
        description=f"{law} excess kurtosis of the terminal horizontal displacement (0 for a normal law)",
        value=significant(k, STATISTIC), stderr=rounded(ke, 2), format=".2f", paper="apparently Gaussian")
SPAN, ARRIVED_CLAIM = 4.5, 0.95  # Figure 3: the top panels' half-width in sigma; boards claimed in its rows panels
for law in ("specular", "no-slip"):
    x = arrived_x(law)
    p, e, normal = tail_share(x)
    numbers[f"tail_share_terminal_{law.replace('-', '')}"] = dict(
        description=f"{law} share of the arrived terminal displacements beyond 3 standard deviations from the mean "
                    f"(normal law: {normal:.2%})",
        value=significant(p, SHARE), stderr=rounded(e, 4), format=".2%", paper="apparently Gaussian",
        note="noslipsim.analysis.tail_share: a count, not set by the farthest few as the kurtosis is")
    numbers[f"beyond_histogram_{law.replace('-', '')}"] = dict(
        description=f"{law} arrived particles beyond ±{SPAN:g} standard deviations from the mean (counted in Figure "
                    "3's top panels, whose axes reach as far for the wider law; its tails panel draws every particle)",
        value=int(np.sum(np.abs(x - x.mean()) > SPAN * x.std(ddof=1))), format="d")
for law in ("specular", "no-slip"):
    kurtoses, shares, arrived = [], [], []
    for c in range(rows.sizes["case"]):
        r = int(rows.rows.values[c])
        x = rows.x_terminal.isel(case=c).sel(law=law).values
        x = x[np.isfinite(x)]
        k, ke = excess_kurtosis(x)
        p, e, _ = tail_share(x)
        kurtoses.append(f"{r}: {k:.2f} ± {ke:.2f}")
        shares.append(f"{r}: {p:.2%} ± {e:.2%}")
        arrived.append(f"{r}: {x.size / rows.sizes['particle']:.0%} by {float(rows.max_time.values[c]):.0f}")
    name = law.replace("-", "")
    note = (f"{rows.attrs['n_particles']:,} particles per number of rows, the arrived ones; boards where fewer than "
            f"{ARRIVED_CLAIM:.0%} arrived are not claimed (arrived_against_rows_{name})")
    numbers[f"kurtosis_against_rows_{name}"] = dict(
        description=f"{law} excess kurtosis of the terminal displacement against the number of rows (Figure 3)",
        value=", ".join(kurtoses), paper="apparently Gaussian", note=note + "; bootstrap errors")
    numbers[f"tail_share_against_rows_{name}"] = dict(
        description=f"{law} share of the terminal displacements beyond 3 standard deviations against the number "
                    f"of rows (Figure 3; normal law: {tail_share([0, 1])[2]:.2%})",
        value=", ".join(shares), paper="apparently Gaussian", note=note + "; binomial errors")
    numbers[f"arrived_against_rows_{name}"] = dict(
        description=f"{law} share arrived against the number of rows, and the time each board ran to (deeper "
                    "boards run longer, galton.rows_sweep.time_exponent)",
        value=", ".join(arrived))
    # the deepest board alone, as numbers the prose can quote: where the tails stand after the most rows
    x = rows.x_terminal.isel(case=-1).sel(law=law).values
    arrived_share = float(np.isfinite(x).mean())
    x = x[np.isfinite(x)]
    deepest = int(rows.rows.values[-1])
    k, ke = excess_kurtosis(x)
    p, e, normal = tail_share(x)
    numbers[f"kurtosis_deepest_{name}"] = dict(
        description=f"{law} excess kurtosis of the terminal displacement on the deepest board ({deepest} rows, "
                    f"{arrived_share:.1%} arrived by {float(rows.max_time.values[-1]):.0f})",
        # the error to the places it is printed with: 0.125 would print 0.12 or 0.13 one ulp apart
        value=significant(k, STATISTIC), stderr=rounded(ke, 2), format=".2f", paper="apparently Gaussian")
    numbers[f"tail_share_deepest_{name}"] = dict(
        description=f"{law} share beyond 3 standard deviations on the deepest board ({deepest} rows; normal law: "
                    f"{normal:.2%})",
        value=significant(p, SHARE), stderr=rounded(e, 4), format=".2%", paper="apparently Gaussian")
factor, m = long_run.attrs["time_factor"], long_run.attrs["n_particles"]
for law, g in (("no-slip", gamma), ("specular", None)):
    p, e = share(long_run, law, g)
    name = "noslip" if law == "no-slip" else "specular"
    numbers[f"share_not_arrived_{name}_{factor:g}T"] = dict(
        description=f"{law} share still not arrived at {factor:g} T = {factor * T:g}",
        value=p, stderr=e, format=".2%",
        paper="the phenomenon persists (no value given)" if law == "no-slip" else "",
        note=f"a subsample of {m:,} particles")
curve = arrival_curve(long_run)
trapped = curve.isel(law=next(i for i, g in enumerate(curve.gamma.values) if np.isclose(g, gamma)))
# the tail estimate only where it extrapolates (late arrivals decaying, particles left to extrapolate to);
# otherwise it would only repeat the 10 T share
if (np.isfinite(float(trapped.trapped_share)) and int(trapped.arrivals_late) > 0
        and float(trapped.share_not_arrived_final) > 0):
    numbers["trapped_share_noslip"] = dict(
        description=f"no-slip (γ = {gamma:.3g}) share that never arrives, extrapolated from the arrival tail",
        value=significant(trapped.trapped_share, STATISTIC), stderr=significant(trapped.trapped_share_stderr, ERROR),
        format=".2%",
        note=f"noslipsim.analysis.arrival_curve; arrivals in the last two half-decades of the run: "
             f"{int(trapped.arrivals_early)}, {int(trapped.arrivals_late)}")

noslip = dist.sel(law="no-slip")
left = noslip.arrived.values == 0
if dist.attrs["board"] == "bounded":
    top = dist.attrs["top_row"] * dist.attrs["spacing"] * np.sqrt(3) / 2
    above = noslip.y_end.values + dist.attrs["start"][1] > top
    numbers["not_arrived_on_top_row"] = dict(
        description="no-slip particles not arrived by T that are still on or above the top row at T",
        value=significant(above[left].mean(), SHARE) if left.any() else 0.0, format=".1%",
        note="hopping along the top row of the bounded board; the others are still descending")
else:
    near = np.hypot(noslip.x_end.values, noslip.y_end.values) < dist.attrs["spacing"] / 2
    numbers["held_near_drop_point"] = dict(
        description="no-slip particles not arrived by T that end within half a spacing of the drop point",
        value=significant(near[left].mean(), SHARE) if left.any() else 0.0, format=".1%",
        note="held in the gap between the two top pegs")
at_end = arrival_curve(sweep, times=[T, sweep.attrs["max_time"]]).sel(law="no-slip")
for k, when in ((0, "T"), (1, f"{sweep.attrs['time_factor']:g} T")):
    numbers[f"not_arrived_against_radius_{when.replace(' ', '')}"] = dict(
        description=f"no-slip share not arrived by {when} against peg radius (spacing {sweep.attrs['spacing']:g})",
        value=", ".join(f"{r:g}: {p:.0%}" for r, p in zip(at_end.radius.values,
                                                         at_end.share_not_arrived.isel(time=k).values)),
        paper="no geometry given", note=f"{sweep.attrs['n_particles']:,} particles per radius, {board}")

with open(snakemake.output.numbers, "w") as fh:
    json.dump(numbers, fh, indent=1, ensure_ascii=False)

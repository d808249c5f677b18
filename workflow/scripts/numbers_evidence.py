"""The Galton evidence in numbers (Figure S2): what the not-arrived share depends on, by T and by 10 T."""
import json
import math
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import numpy as np
import xarray as xr

from noslipsim.plot.numbers import significant

ev = xr.load_dataset(snakemake.input.evidence)
T, factor, n = ev.attrs["termination_time"], ev.attrs["time_factor"], ev.attrs["n_particles"]
gamma = float(ev.gamma.sel(law="no-slip"))
when = {"T": T, f"{factor:g}T": factor * T}
spoken = {"T": "T", f"{factor:g}T": f"{factor:g} T"}


def not_arrived(case, law, by):
    """Share of one case and law not arrived by time ``by``, with its binomial standard error."""
    t = ev.t_terminal.sel(case=case, law=law).values
    p = float(np.mean(~(t <= by)))
    # k/n of n <= 1e5 particles: 6 significant digits tell every k apart; a binomial standard error: 3
    # (docs/figures.md, "Which numbers and figures are the same on every machine")
    return significant(p, 6), significant(np.sqrt(p * (1 - p) / t.size), 3)


numbers = {}
for drop, what in (("gap", "the unbounded lattice, dropped in the gap between two pegs (the reading before)"),
                   ("gap-bounded", "the same drop in the gap between two pegs of the bounded board's top row"),
                   ("board", "the bounded board, released above its top row (the configuration of Figures 2, 3, S1)")):
    for law in ("no-slip", "specular"):
        for label, by in when.items():
            p, e = not_arrived(drop, law, by)
            numbers[f"{drop.replace('-', '_')}_{law.replace('-', '')}_not_arrived_{label}"] = dict(
                description=f"{law}{f' (γ = {gamma:.3g})' if law == 'no-slip' else ''} share not arrived by "
                            f"{spoken[label]} = {by:g}, {what}",
                value=p, stderr=e, format=".1%",
                paper=("roughly 40 %" if law == "no-slip" else "almost none") if label == "T" else "",
                note=f"{n:,} particles")
gap = ev.sel(case="gap", law="no-slip")
left = np.isnan(gap.t_terminal.values)
near = np.hypot(gap.x_end.values, gap.y_end.values) < ev.attrs["spacing"] / 2
numbers["gap_held_near_drop_point"] = dict(
    description=f"gap drop: no-slip particles not arrived by {factor:g} T that end within half a spacing of "
                "the drop point",
    value=significant(near[left].mean(), 6) if left.any() else 0.0, format=".1%",
    note="held in the gap where they start, bouncing between two pegs as in a no-slip channel")


def release_name(group, case):
    k = ev.sel(case=case)
    return {"point": f"({float(k.start_x):g}, {float(k.start_y):g})", "spread": f"{float(k.spread):g}",
            "speed": f"{float(k.speed):g}"}[group]


def release_key(group, case):
    k = ev.sel(case=case)
    return (float(k.start_y), float(k.start_x)) if group == "point" else (float(k[group]),)


for group in ("point", "spread", "speed"):
    sel = [*(str(c) for c in ev.case.values if str(ev.group.sel(case=c).values) == group), "board"]
    order = sorted(sel, key=lambda c, group=group: release_key(group, c))
    for label, by in when.items():
        numbers[f"board_noslip_not_arrived_{label}_against_{group}"] = dict(
            description=f"bounded board, no-slip share not arrived by {spoken[label]} against the "
                        f"release {group}",
            value=", ".join(f"{release_name(group, c)}: {not_arrived(c, 'no-slip', by)[0]:.0%}" for c in order),
            note=f"{n:,} particles per case; the other release settings as configured")
for group, fmt in (("radius", "{:g}"), ("rows", "{:d}")):
    what = "peg radius" if group == "radius" else "number of rows"
    for drop in ("board", "gap"):
        sel = [str(c) for c in ev.case.values
               if str(ev.group.sel(case=c).values) == group and str(c).startswith(drop + "-")]
        sel.append(drop)
        sel.sort(key=lambda c, group=group: float(ev[group].sel(case=c)))
        for label, by in when.items():
            numbers[f"{drop}_noslip_not_arrived_{label}_against_{group}"] = dict(
                description=f"{'bounded board' if drop == 'board' else 'gap drop'}, no-slip share not arrived by "
                            f"{spoken[label]} against the {what}",
                value=", ".join(f"{fmt.format(ev[group].sel(case=c).values.item())}: "
                                f"{not_arrived(c, 'no-slip', by)[0]:.0%}" for c in sel),
                note=f"{n:,} particles per case")

walled = sorted((str(c) for c in ev.case.values if str(ev.group.sel(case=c).values) == "width"
                 and str(ev.wall_law.sel(case=c).values) == "pegs"), key=lambda c: float(ev.width.sel(case=c)))
specular_walls = [str(c) for c in ev.case.values if str(ev.group.sel(case=c).values) == "width"
                  and str(ev.wall_law.sel(case=c).values) == "specular"]
for label, by in when.items():
    numbers[f"walled_noslip_not_arrived_{label}_against_width"] = dict(
        description=f"bounded board between side walls at x = ±width, no-slip share not arrived by {spoken[label]} "
                    "against the width (no walls: the board_noslip record)",
        value=", ".join(f"{float(ev.width.sel(case=c)):g}: {not_arrived(c, 'no-slip', by)[0]:.1%}" for c in walled),
        note=f"{n:,} particles per case; noslipsim.tables.walled_galton_board, walls of the pegs' law")
for c in walled + specular_walls:
    w, walls = float(ev.width.sel(case=c)), str(ev.wall_law.sel(case=c).values)
    p, e = not_arrived(c, "no-slip", T)
    numbers[f"walled_{w:g}{'_specular_walls' * (walls == 'specular')}_noslip_not_arrived_T"] = dict(
        description=f"bounded board between side walls at x = ±{w:g} "
                    f"({'specular walls' if walls == 'specular' else 'walls of the pegs law'}), no-slip share not "
                    f"arrived by T = {T:g}",
        value=p, stderr=e, format=".1%", note=f"{n:,} particles")
for law in ("no-slip", "specular"):
    x = ev.x_terminal.sel(case="board", law=law).values
    x = x[np.isfinite(x)]
    for c in walled:
        w = float(ev.width.sel(case=c))
        numbers[f"board_{law.replace('-', '')}_arrived_beyond_{w:g}"] = dict(
            description=f"bounded board without walls: share of the {law} particles arrived by {factor:g} T that "
                        f"cross the terminal depth beyond x = ±{w:g} (where walls would have stood)",
            value=significant(np.mean(np.abs(x) > w), 6), format=".0%", note=f"{x.size:,} arrived of {n:,}")
# the readings that leave about 40 % by T (Figure S2 f): the share still out at 10 T tells trapped from slow
near = ["gap", *(str(c) for c in ev.case.values if str(c).startswith("board-")
                 and abs(not_arrived(str(c), "no-slip", T)[0] - not_arrived("gap", "no-slip", T)[0]) < 0.1)]
numbers["near_40_percent_readings"] = dict(
    description="no-slip boards that leave about as many particles out by T as the gap drop: share not arrived by "
                f"T, then by {factor:g} T",
    value="; ".join(f"{c}: {not_arrived(c, 'no-slip', T)[0]:.0%} → {not_arrived(c, 'no-slip', factor * T)[0]:.0%}"
                    for c in near),
    paper="roughly 40 %", note="slow particles arrive by 10 T, trapped ones do not; by T alone they look alike")
for c in near[1:]:
    for label, by in when.items():
        p, e = not_arrived(c, "no-slip", by)
        numbers[f"{c.replace('-', '_')}_noslip_not_arrived_{label}"] = dict(
            description=f"{c} (bounded board, one setting changed), no-slip share not arrived by {spoken[label]}",
            value=p, stderr=e, format=".1%", paper="roughly 40 %" if label == "T" else "",
            note=f"{n:,} particles; about as many out by T as the gap drop")


def fisher_exact(k1, n1, k2, n2):
    """Two-sided p of Fisher's exact test: k1 of n1 against k2 of n2 (the tables no likelier than the one seen)."""
    k, total = k1 + k2, n1 + n2

    def prob(a):
        return math.comb(n1, a) * math.comb(n2, k - a) / math.comb(total, k)

    seen = prob(k1)
    return min(1.0, sum(prob(a) for a in range(max(0, k - n2), min(k, n1) + 1) if prob(a) <= seen * (1 + 1e-9)))


# Figure S1's radius sweep and Figure S2's board at the largest radius they share, by 10 T: two samples of one
# share (other seeds and sizes), and how many of each still arrived in the run's last half (a share still falling)
sweep = xr.load_dataset(snakemake.input.sweep)
radius = max(set(np.round(sweep.radius.values, 9)) & {round(float(ev.radius.sel(case=c)), 9) for c in ev.case.values
                                                       if str(c).startswith("board-radius-")})
counts = {}
for figure, t in (("S1", sweep.t_terminal.sel(law="no-slip").sel(radius=radius, method="nearest").values.ravel()),
                  ("S2", ev.t_terminal.sel(case=f"board-radius-{radius:g}", law="no-slip").values.ravel())):
    counts[figure] = (int(np.sum(~(t <= factor * T))), t.size)
    for what, share in (("not_arrived_10T", np.mean(~(t <= factor * T))),
                        ("arrived_late", np.mean((t > factor * T / 2) & (t <= factor * T)))):
        numbers[f"radius_{radius:g}_{figure}_{what}"] = dict(
            description=f"bounded board, peg radius {radius:g}, no-slip, Figure {figure}'s run: "
                        + (f"share not arrived by {factor:g} T" if what == "not_arrived_10T" else
                           f"share arrived in the run's last half ({factor / 2:g} T to {factor:g} T)"),
            value=significant(share, 6), stderr=significant(np.sqrt(share * (1 - share) / t.size), 3), format=".1%",
            note=f"{t.size:,} particles")
numbers[f"radius_{radius:g}_S1_S2_fisher_p"] = dict(
    description=f"peg radius {radius:g}: Fisher's exact test (two-sided) of Figure S1's and Figure S2's counts not "
                f"arrived by {factor:g} T ({'/'.join(map(str, counts['S1']))} and {'/'.join(map(str, counts['S2']))})",
    value=significant(fisher_exact(*counts["S1"], *counts["S2"]), 3), format=".2g",
    note="other seeds and sizes of one board; a share still falling at 10 T (slow, not trapped)")

with open(snakemake.output.numbers, "w") as fh:
    json.dump(numbers, fh, indent=1, ensure_ascii=False)

"""The Galton evidence in numbers (Figure S2): what the not-arrived share depends on, by T and by 10 T."""
import json
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

with open(snakemake.output.numbers, "w") as fh:
    json.dump(numbers, fh, indent=1, ensure_ascii=False)

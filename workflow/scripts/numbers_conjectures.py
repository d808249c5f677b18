"""Counts of four of the paper's conjectures: the launch angle and the class of 2-periodic orbits (Figure S4),
isolated and family periodic orbits of wedges under a force (Figure S5), non-path-reversing 2-periodic orbits
between accessible points (Figure S6), invariant regions around elliptic orbits between two disks (Figure S7).
Counts, and shares to three digits."""
import json
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import numpy as np
import xarray as xr

from noslipsim.experiments import census_counts, pair_counts, region_counts
from noslipsim.plot.numbers import significant

# shares k/n are exact ratios of counts: 6 significant digits (the table prints 3); the boundary
# distances are interpolated on the radius grid, known far below their printed 2-3 decimals: 6 too
SHARE, BOUNDARY = 6, 6

launch, census = xr.load_dataset(snakemake.input.launch), xr.load_dataset(snakemake.input.census)
counts = census_counts(census)
numbers = {}

# ------------------------------------------------------------------ launch angle (Figure S4)
n_col, n_changing, n_both, n_missing = (int(launch.attrs[k]) for k in ("n_columns", "n_changing",
                                                                      "n_elliptic_hyperbolic", "n_missing"))
grid = f"{launch.sizes['radius']} R × {launch.sizes['phi']} φ × {launch.sizes['theta']} θ"
numbers["launch_columns"] = dict(description=f"two disks, force (0, -g): (R, φ) columns of the {grid} grid with an "
                                 "orbit at two launch angles at least", value=n_col, format="d")
numbers["launch_share_changing"] = dict(
    description="share of those columns whose linear class changes with the launch angle θ alone (θ over (0, π/2), "
                "across the parabolic line θ = π/2 - φ)",
    value=significant(n_changing / n_col, SHARE), format=".1%", paper="stability depends on the launch angle",
    note=f"{n_changing} of {n_col} columns")
numbers["launch_share_elliptic_hyperbolic"] = dict(
    description="share of the columns that are elliptic at some θ and hyperbolic at another",
    value=significant(n_both / n_col, SHARE), format=".1%",
    note=f"{n_both} of {n_col} columns")
below, n_below = int(launch.attrs["n_changing_below"]), int(launch.attrs["n_columns_below"])
numbers["launch_share_changing_below_line"] = dict(
    description=f"the same away from the parabolic line: launch angles θ < π/2 - φ - {launch.attrs['margin']:g} "
                "only, share of columns elliptic at some θ and hyperbolic at another",
    value=significant(below / n_below, SHARE),
    format=".1%", paper="stability depends on the launch angle", note=f"{below} of {n_below} columns")
# the columns below the line, split by the force-free threshold R*(phi)
line = launch.theta < np.pi / 2 - launch.phi - launch.attrs["margin"]
kinds = launch.linear_kind.where(line, "").transpose("radius", "phi", "theta").values.astype(str)
counted = (kinds != "").sum(axis=-1) >= 2
steady_elliptic = (kinds == "elliptic").any(axis=-1) & ~(kinds == "hyperbolic").any(axis=-1)
small = launch.radius.values[:, None] < launch.radius_threshold.values[None, :]
changing = launch.elliptic_hyperbolic_below.values.astype(bool)
for key, side, mask, what in (("below", "R < R*(φ)", counted & small, changing),
                              ("above", "R > R*(φ)", counted & ~small, steady_elliptic)):
    verb = "change class along θ" if key == "below" else "are elliptic at every θ"
    numbers[f"launch_share_{key}_threshold"] = dict(
        description=f"below the parabolic line, columns with {side} (force-free threshold) that {verb}",
        value=significant(int((mask & what).sum()) / int(mask.sum()), SHARE), format=".1%",
        note=f"{int((mask & what).sum())} of {int(mask.sum())} columns")
n_above, n_above_hyp = int(launch.attrs["n_above"]), int(launch.attrs["n_above_hyperbolic"])
numbers["launch_share_hyperbolic_above_line"] = dict(
    description=f"share of the orbits launched above the line, θ > π/2 - φ + {launch.attrs['margin']:g}, "
                "that are hyperbolic", value=significant(n_above_hyp / n_above, SHARE), format=".1%",
    note=f"{n_above_hyp} of {n_above}")
numbers["launch_points_without_orbit"] = dict(
    description="grid points where the 2-periodic orbit does not exist (its flight meets the table elsewhere)",
    value=n_missing, format="d", note=f"of {launch.linear_kind.size} points")
shift = launch.radius_shift
first = shift.isel(theta=0)
numbers["launch_boundary_at_smallest_theta"] = dict(
    description=f"largest |R* - R_e| over φ at θ = {float(launch.theta[0]):.2f}: the measured elliptic boundary "
                "against the force-free closed form", value=significant(float(np.nanmax(np.abs(first))), BOUNDARY),
    format=".3f",
    paper="the stability threshold is unaltered (Figure 15, lower left)",
    note=f"radius step {float(launch.radius[1] - launch.radius[0]):.3f}; {int(np.isfinite(first).sum())} φ columns")
k = np.unravel_index(int(np.nanargmax(shift.values)), shift.shape)
numbers["launch_boundary_largest_shift"] = dict(
    description="largest R* - R_e over every (φ, θ) with a measured boundary: how far the launch angle moves the "
                "elliptic region to smaller disks", value=significant(float(shift.values[k]), BOUNDARY), format=".2f",
    note=f"at φ = {float(launch.phi[k[0]]):.2f}, θ = {float(launch.theta[k[1]]):.2f}; "
         f"{int(np.isfinite(shift).sum())} (φ, θ) columns, φ + θ within {launch.attrs['margin']:g} of π/2 left out")

# ------------------------------------------------------------------ periodic census (Figure S5)
outcomes = counts.searches.sum("period")
n_of = lambda key: np.atleast_1d(census.attrs[key]).size  # noqa: E731 (a one-item list reads back a scalar)
where = (f"{n_of('phis')} half-angles × {n_of('force_angles')} force directions, periods "
         f"{int(counts.period.min())}-{int(counts.period.max())}, {census.attrs['starts']} starts each")
numbers["census_searches"] = dict(description="wedges under a force: searches of the periodic-orbit finder",
                                  value=int(census.sizes["search"]), format="d", note=where)
for outcome in ("found", "not converged", "no return"):
    numbers[f"census_{outcome.replace(' ', '_')}"] = dict(
        description=f"searches that ended '{outcome}'", value=int(outcomes.sel(outcome=outcome)), format="d")


def per(name):
    """``minimal period: count`` of one census count, periods with none left out."""
    return ", ".join(f"{int(m)}: {int(v)}" for m, v in zip(counts.minimal_period.values, counts[name].values) if v)


numbers["census_distinct"] = dict(description="distinct periodic orbits found (up to the wedge's scaling)",
                                  value=int(counts.distinct.sum()), format="d",
                                  note="by minimal period: " + (per("distinct") or "none"))
numbers["census_isolated"] = dict(description="distinct orbits that are isolated (no eigenvalue 1)",
                                  value=int(counts.isolated.sum()), format="d",
                                  paper="isolated higher order periodic orbits exist on a wedge",
                                  note="by minimal period: " + (per("isolated") or "none"))
numbers["census_family"] = dict(description="distinct orbits on a family (an eigenvalue 1 at fixed energy)",
                                value=int(counts.family.sum()), format="d",
                                note="by minimal period: " + (per("family") or "none"))
even = counts.minimal_period.values % 2 == 0
numbers["census_isolated_even"] = dict(description="isolated distinct orbits of even minimal period",
                                       value=int(counts.isolated.values[even].sum()), format="d",
                                       paper="an isolated period-8 orbit (Figure 7)")
# ------------------------------------------------------------------ accessible pairs (Figure S6)
accessible = xr.load_dataset(snakemake.input.accessible)
pairs = pair_counts(accessible).pairs.sum("table")
sample, outcome = (accessible[k].values.astype(str) for k in ("sample", "outcome"))
tables_note = ", ".join(pair_counts(accessible).table.values)
n_random = int(pairs.sel(sample="random").sum())
n_inacc = int(pairs.sel(sample="random", outcome="inaccessible"))
numbers["accessible_random_pairs"] = dict(
    description="random pairs of boundary points sampled on wedges, polygons, disks and mixed tables under a force",
    value=n_random, format="d", note=f"{accessible.attrs['pairs']} per table: {tables_note}")
numbers["accessible_share_inaccessible"] = dict(
    description="share of the random pairs that are inaccessible (tangent lines form no wedge, or the chord meets "
                "the table elsewhere)", value=significant(n_inacc / n_random, SHARE), format=".1%",
    note=f"{n_inacc} of {n_random}")
n_unbal = int(pairs.sel(sample="random", outcome="unbalanced"))
numbers["accessible_share_unbalanced"] = dict(
    description="share of the accessible random pairs that are unbalanced, so that no non-path-reversing "
                "2-periodic orbit joins them (the normal velocity is reversed at both impacts)",
    value=significant(n_unbal / (n_random - n_inacc), SHARE), format=".1%",
    paper="non-path-reversing 2-periodic orbits exist between any two accessible points",
    note=f"{n_unbal} of {n_random - n_inacc}")
numbers["accessible_random_found"] = dict(description="random pairs joined by a non-path-reversing 2-periodic orbit",
                                          value=int(pairs.sel(sample="random", outcome="found")), format="d")
balanced = sample == "balanced"
accessible_balanced = balanced & (outcome != "inaccessible")
numbers["accessible_balanced_pairs"] = dict(
    description="accessible balanced pairs (the only pairs that can carry the orbit), from the balanced partners "
                "of random points", value=int(accessible_balanced.sum()), format="d",
    note=f"and {int((balanced & (outcome == 'inaccessible')).sum())} inaccessible balanced pairs")
for name in ("found", "not found", "not periodic", "not minimal"):
    numbers[f"accessible_balanced_{name.replace(' ', '_')}"] = dict(
        description=f"accessible balanced pairs that ended '{name}'", value=int((balanced & (outcome == name)).sum()),
        format="d")
reason = accessible.reason.values.astype(str)
NO_TIMES = "T T' not positive"
for key, why in (("spin_reversed", "spin reversed"), ("no_flight_times", NO_TIMES)):
    numbers[f"accessible_not_found_{key}"] = dict(
        description=f"balanced pairs not found because: {why}", value=int((balanced & (reason == why)).sum()),
        format="d")
found = outcome == "found"
mirror, family = accessible.mirror.values.astype(bool), accessible.family.values.astype(bool)
numbers["accessible_found_mirror"] = dict(
    description="found pairs that are mirror images of each other about a line along the force",
    value=int((found & mirror).sum()), format="d", note=f"of {int(found.sum())} found pairs")
numbers["accessible_mirror_pairs"] = dict(
    description="accessible balanced pairs that are mirror images about a line along the force",
    value=int((accessible_balanced & mirror).sum()), format="d",
    note=f"{int((accessible_balanced & mirror & (reason == NO_TIMES)).sum())} of them with T T' <= 0")
numbers["accessible_asymmetric_found"] = dict(
    description="accessible balanced pairs that are not mirror images and carry a confirmed orbit",
    value=int((accessible_balanced & ~mirror & found).sum()), format="d",
    note=f"of {int((accessible_balanced & ~mirror).sum())} such pairs")
numbers["accessible_family_pairs"] = dict(
    description="accessible balanced pairs whose orbits form a one-parameter family (the two-flight equations hold "
                "for every flight time)", value=int((accessible_balanced & family).sum()), format="d",
    note=f"of which {int((accessible_balanced & family & mirror).sum())} are mirror-symmetric")
for kind in ("elliptic", "hyperbolic", "parabolic"):
    numbers[f"accessible_orbits_{kind}"] = dict(
        description=f"confirmed orbits (family members tried on found pairs) that are {kind}",
        value=int(accessible[f"n_{kind}"].sum()), format="d")

# ------------------------------------------------------------------ invariant regions (Figure S7)
invariant = xr.load_dataset(snakemake.input.invariant)
starts = region_counts(invariant).starts
exists = invariant.exists
forces_note = lambda mask: ", ".join(f"{g:g}" for g in invariant.force.values[mask]) or "none"  # noqa: E731
numbers["invariant_starts"] = dict(
    description="two disks, force (0, -g): starts on rings around the path-reversing 2-periodic orbits, each run "
                f"{invariant.attrs['max_collisions']:,} collisions", value=int(starts.sum()), format="d",
    note=f"{int(exists.sum())} orbits, {invariant.sizes['ring']} rings × {invariant.sizes['start']} starts each")
for outcome in ("invariant", "attracted", "escaped", "stopped"):
    for flight in invariant.flight.values:
        key = flight.replace(" ", "_")
        numbers[f"invariant_{key}_{outcome}"] = dict(
            description=f"{flight}: starts that ended '{outcome}'", value=int(starts.sel(flight=flight,
                                                                                        outcome=outcome).sum()),
            format="d", **({"paper": "stable periodic orbits under a force create invariant regions"}
                           if outcome == "attracted" else {}))
if "free fall" in invariant.flight.values:
    ff = invariant.sel(flight="free fall")
    numbers["invariant_free_fall_missing"] = dict(
        description="forces with no free-fall orbit at unit launch speed (g d > 1)",
        value=int((ff.exists.sum("branch") == 0).sum()), format="d",
        note=f"g = {forces_note((ff.exists.sum('branch') == 0).values)}")
    kinds = ff.linear_kind.values.astype(str)
    numbers["invariant_free_fall_elliptic"] = dict(
        description="free-fall orbits that are elliptic (exact monodromy)", value=int((kinds == "elliptic").sum()),
        format="d", note=f"of {int(ff.exists.sum())}")
    hyperbolic = kinds == "hyperbolic"
    numbers["invariant_hyperbolic_staying"] = dict(
        description="starts around the hyperbolic free-fall orbits that stay",
        value=int(starts.sel(flight="free fall", outcome="invariant").values[hyperbolic].sum()), format="d",
        note=f"of {int(starts.sel(flight='free fall').sum('outcome').values[hyperbolic].sum())}")
    for branch in ("low", "high"):
        radius = ff.region_radius.sel(branch=branch).values
        elliptic = kinds[:, list(ff.branch.values).index(branch)] == "elliptic"
        if elliptic.any():
            numbers[f"invariant_free_fall_{branch}_radius"] = dict(
                description=f"free fall, {branch} launch, elliptic orbits: region radius (every start stays) "
                            "from the smallest to the largest force",
                value=significant(float(radius[elliptic][-1]), BOUNDARY), format=".2f",
                note="g: radius " + ", ".join(f"{g:g}: {r:.2f}" for g, r in
                                                 zip(ff.force.values[elliptic], radius[elliptic])))
if "isokinetic" in invariant.flight.values:
    iso = invariant.sel(flight="isokinetic", branch="apex")
    radius = iso.region_radius.values
    numbers["invariant_isokinetic_radius"] = dict(
        description="isokinetic thermostat: region radius (every start stays) at the largest force",
        value=significant(float(radius[-1]), BOUNDARY), format=".2f",
        note="g: radius " + ", ".join(f"{g:g}: {r:.2f}" for g, r in zip(iso.force.values, radius)))
    near = iso.tail_distance.isel(ring=0).max("start").values   # NaN where every ring-1 start escaped
    if np.isfinite(near).any():
        numbers["invariant_isokinetic_ring1_distance"] = dict(
            description="isokinetic thermostat, at the largest force with a ring-1 survivor: how far those "
                        "survivors' last collisions lie from the orbit's own (largest max-norm distance in element, "
                        "s, unit v_t, unit w)",
            value=significant(float(near[np.isfinite(near)][-1]), BOUNDARY), format=".2f",
            note="g: distance " + ", ".join(f"{g:g}: {d:.2f}" for g, d in zip(iso.force.values, near)))
    leaves = (iso.exists == 1) & (iso.orbit_period != 2)
    numbers["invariant_isokinetic_orbit_leaves"] = dict(
        description="isokinetic thermostat: forces where the unperturbed orbit itself leaves its cycle",
        value=int(leaves.sum()), format="d", note=f"g = {forces_note(leaves.values)}")
with open(snakemake.output.numbers, "w") as fh:
    json.dump(numbers, fh, indent=1, ensure_ascii=False)

"""The paper's portrait numbers, computed: the gamma at which islands appear in the no-slip Sinai torus, and
Figure 13's readings (the share of regular orbits against the force and its threshold sensitivity, the
attracting cycles of the thermostatted gas, the kinetic energy in free fall, the horizon of the lattice)."""
import json
import math
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import numpy as np
import xarray as xr

from noslipsim.analysis import attractor_census, portrait_attractors
from noslipsim.analysis.islands import islands_onsets, onset_gamma, regular_share, threshold_sensitivity
from noslipsim.experiments import DISSIPATIVE_READINGS
from noslipsim.plot.numbers import significant

# Each value is kept to the digits its computation determines (docs/figures.md, "Which numbers and figures are the
# same on every machine"): an onset interpolated between counted shares and a median of many orbits carry at most
# summation-order noise in their last bits (6 significant digits); a bootstrap error is itself uncertain in its
# second digit (3); a closed form in double precision is good to ~1e-15 (12).
STATISTIC, ERROR, CLOSED_FORM = 6, 3, 12

isl = islands_onsets(xr.load_dataset(snakemake.input.islands), snakemake.params.threshold, snakemake.params.level)
threshold, level, seed = isl.attrs["regular_threshold"], isl.attrs["visible_share"], int(isl.attrs["seed"])
gammas = isl.gamma.values


def onset(radius, thr=threshold, lev=level):
    """Onset gamma of one radius for another threshold or level (sensitivity of the number)."""
    share, _, n = regular_share(isl.ftle.sel(radius=radius).values, thr)
    return onset_gamma(gammas, np.rint(share * n).astype(int), n, level=lev, seed=seed)["value"]


numbers = {}
for k, R in enumerate(isl.radius.values):
    case = isl.isel(radius=k)
    value = significant(case.onset_gamma, STATISTIC) if np.isfinite(case.onset_gamma) else math.nan
    others = {f"threshold {t:g}": onset(R, thr=t) for t in (threshold / 3, threshold * 3)}
    others.update({f"level {lv:.1%}": onset(R, lev=lv) for lv in (level / 2, level * 2)})
    spread = ", ".join(f"{k_}: {v:.3f}" for k_, v in others.items())
    found = np.isfinite(value)
    numbers[f"islands_onset_gamma_R{R:g}"] = dict(
        description=f"no-slip Sinai torus, scatterer radius {R:g}: smallest γ at which regular orbits (finite-time "
                    f"Lyapunov exponent < {threshold:g} per collision) hold {level:.0%} of the phase space",
        value=value if found else f"not reached by γ = {gammas[-1]:g}", format=".3f",
        **({"stderr": significant(case.onset_gamma_stderr, ERROR)}
           if found and np.isfinite(case.onset_gamma_stderr) else {}),
        paper="γ > 0.3 (radius not stated)",
        note=f"{isl.attrs['n_orbits']} orbits per γ; head-on 2-periodic orbit elliptic for "
             f"γ > {float(case.head_on_onset):.3f}; other choices: {spread}")
radius_for_paper = 1.0 / (2.0 * (1.0 + 0.3 ** 2))
numbers["islands_radius_for_paper_onset"] = dict(
    description="scatterer radius at which the head-on 2-periodic orbit turns elliptic at γ = 0.3 "
                "(R = 1/(2 (1 + γ²)); the measured onsets follow this orbit)",
    value=significant(radius_for_paper, CLOSED_FORM), format=".3f", paper="radius not stated",
    note="linear theory, no simulation")

# ---------------------------------------------------------------- Figure 13's readings (Figure S3)
readings = xr.load_dataset(snakemake.input.hex_readings)
drawn = xr.load_dataset(snakemake.input.hex_force)
chosen = drawn.attrs["reading"]
share, err, n = regular_share(readings.ftle.values, threshold)       # dims (reading, gamma, force)
forces = readings.force.values
force_list = ", ".join(f"{g:g}" for g in forces)
for i, reading in enumerate(readings.reading.values):
    reading = str(reading)
    rows = "; ".join(f"γ = {gm:.3g}: " + " / ".join(f"{100 * p:.0f}" for p in share[i, j])
                     for j, gm in enumerate(readings.gamma.values))
    numbers[f"hex_regular_share_{reading}"] = dict(
        description=f"Figure 13's table read as: {readings.reading_table.values[i]}; share of regular orbits (%) "
                    f"at g = {force_list}",
        value=rows + (" (Figure 13's reading)" if reading == chosen else ""),
        paper="structure with no force, kept at a small force, dissipating as it grows; new invariant regions "
              "at a strong force",
        note=f"{readings.attrs['n_orbits']} orbits per point, twin-orbit exponents over "
             f"{readings.attrs['lyapunov_collisions']} collisions, threshold {threshold:g}; Figure S3")
strong = drawn.isel(force=-1).kinetic_final
for cell in ("closed", "periodic"):
    numbers[f"hex_kinetic_median_{cell}"] = dict(
        description=f"free fall at g = {float(drawn.force[-1]):g}: median kinetic energy after "
                    f"{drawn.attrs['energy_collisions']:,} collisions (start 0.5), "
                    + ("closed hexagonal cell" if cell == "closed" else "periodic hexagonal cell (Lorentz gas)"),
        value=significant(strong.sel(cell=cell).median(), STATISTIC), format=".3g",
        note=f"max {float(strong.sel(cell=cell).max()):.3g}; {strong.sizes['orbit']} orbits per gamma, both gammas "
             "pooled; why free fall in the periodic gas is not Figure 13's reading")


# ---------------------------------------------------------------- Figure 13's panels: thresholds and cycles
def percents(values):
    return " / ".join(f"{100 * p:.0f}" for p in values)


def cycles_text(periods, labels):
    found = attractor_census(periods, labels)
    return ", ".join(f"{p} ({k})" for p, k in found) if found else "none"


panels = portrait_attractors(drawn)
ladder = list(threshold_sensitivity([], threshold))[::-1]          # 0.03, 0.02, 0.01: highest first
numbers["hex_fig13_regular_thresholds"] = dict(
    description="Figure 13's panels: share of regular orbits (%) with exponent below "
                + " / ".join(f"{t:g}" for t in ladder) + " per collision",
    value="; ".join(f"γ = {gm:.3g}, g = {g:g}: "
                    + percents(list(threshold_sensitivity(panels.ftle.sel(gamma=gm, force=g).values,
                                                          threshold).values())[::-1])
                    for gm in panels.gamma.values for g in panels.force.values),
    note=f"{panels.sizes['orbit']} orbits per panel, twin-orbit exponents over {drawn.attrs['lyapunov_collisions']:,} "
         "collisions; where the shares differ the exponents straddle the line")
for gm in panels.gamma.values:
    lam = panels.ftle.sel(gamma=gm).isel(force=-1).values
    tag = f"{gm:.3g}"
    numbers[f"hex_fig13_strong_exponents_gamma{tag}"] = dict(
        description=f"Figure 13, γ = {tag}, strong force g = {float(panels.force[-1]):g}: 5th to 95th percentile of "
                    "the finite-time exponents per collision",
        value=" to ".join(f"{q:.3f}" for q in np.nanpercentile(lam, [5, 95])),
        note=f"median {np.nanmedian(lam):.3f}; regular threshold {threshold:g}")
    case = panels.sel(gamma=gm).isel(force=-1)
    numbers[f"hex_fig13_strong_on_cycle_gamma{tag}"] = dict(
        description=f"Figure 13, γ = {tag}, strong force g = {float(panels.force[-1]):g}: share of orbits that end "
                    "on an attracting periodic orbit (analysis.attractors)",
        value=significant(float((case.attractor_period > 0).mean()), STATISTIC), format=".0%",
        note="cycles, period in disk collisions (orbits): " + cycles_text(case.attractor_period.values,
                                                                          case.attractor.values))
numbers["hex_fig13_cycles"] = dict(
    description="Figure 13's panels: attracting periodic orbits, period in disk collisions (orbits on it)",
    value="; ".join(f"γ = {gm:.3g}, g = {g:g}: " + cycles_text(panels.attractor_period.sel(gamma=gm, force=g).values,
                                                              panels.attractor.sel(gamma=gm, force=g).values)
                    for gm in panels.gamma.values for g in panels.force.values),
    note=f"{drawn.attrs['n_collisions']:,} disk collisions per orbit; a cycle repeats "
         f"{panels.attrs['attractor_repeats']} times more within {panels.attrs['attractor_tolerance']:g}; "
         "the mirror x -> -x maps a cycle to a cycle of the same period")

# ---------------------------------------------------------------- Figure S3: cycles and thresholds against g
if "attractor_period" in readings:
    for i, reading in enumerate(map(str, readings.reading.values)):
        case = readings.isel(reading=i)
        if reading not in DISSIPATIVE_READINGS:     # searched only where the flow contracts phase volume
            continue
        rows = "; ".join(f"γ = {gm:.3g}: " + percents((case.attractor_period.sel(gamma=gm) > 0).mean("orbit").values)
                         for gm in readings.gamma.values)
        top = "; ".join(f"γ = {gm:.3g}, g = {g:g}: " + cycles_text(case.attractor_period.sel(gamma=gm, force=g).values,
                                                                   case.attractor.sel(gamma=gm, force=g).values)
                        for gm in readings.gamma.values for g in forces
                        if (case.attractor_period.sel(gamma=gm, force=g) > 0).any())
        numbers[f"hex_on_cycle_share_{reading}"] = dict(
            description=f"{readings.reading_table.values[i]}: share of orbits (%) that end on an attracting periodic "
                        f"orbit at g = {force_list}",
            value=rows, note=f"{readings.attrs['attractor_collisions']:,} disk collisions per orbit; cycles, period "
                             f"(orbits): {top or 'none'}; Figure S3, bottom row")
    names = [str(r) for r in readings.reading.values]
    if chosen in names:
        chosen_i = names.index(chosen)
        ladder_shares = threshold_sensitivity(readings.ftle.values[chosen_i], threshold)   # (gamma, force) each
        numbers[f"hex_regular_share_{chosen}_thresholds"] = dict(
            description=f"Figure 13's reading, share of regular orbits (%) at g = {force_list} for the exponent "
                        "thresholds " + ", ".join(f"{t:g}" for t in ladder_shares),
            value="; ".join(f"γ = {gm:.3g}, {t:g}: " + percents(p[j]) for j, gm in enumerate(readings.gamma.values)
                            for t, p in ladder_shares.items()),
            note=f"{readings.attrs['n_orbits']} orbits per point over {readings.attrs['lyapunov_collisions']:,} "
                 "collisions; Figure S3's band")

# ---------------------------------------------------------------- the horizon of the lattice
radius = float(drawn.attrs["radius"])
numbers["hex_finite_horizon_radius"] = dict(
    description="unit triangular lattice: the smallest disk radius with a finite horizon (√3/4: the rows of disks "
                "along a lattice direction, √3/2 apart, close their corridor)",
    value=significant(math.sqrt(3) / 4, CLOSED_FORM), format=".4f", note="closed form, no simulation")
numbers["hex_corridor_width"] = dict(
    description=f"width of the open corridors (along the three lattice directions, none along the field) at Figure "
                f"13's radius {radius:g}: √3/2 − 2R",
    value=significant(math.sqrt(3) / 2 - 2 * radius, CLOSED_FORM), format=".3f", note="closed form, no simulation")
for g in drawn.force.values[drawn.force.values > 0]:
    numbers[f"hex_thermostat_drift_bound_g{g:g}"] = dict(
        description=f"isokinetic thermostat, field g = {g:g}: bound π v²/g on the drift across the field during one "
                    "flight (speed v <= 1)",
        value=significant(math.pi / g, CLOSED_FORM), format=".3g",
        note="closed form: the heading turns towards the field at the rate (g/v) sin of its angle to it")
with open(snakemake.output.numbers, "w") as fh:
    json.dump(numbers, fh, indent=1, ensure_ascii=False)

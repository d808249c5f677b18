"""The paper's portrait numbers, computed: the gamma at which islands appear in the no-slip Sinai torus, and
Figure 13's readings (the share of regular orbits against the force, the kinetic energy in free fall)."""
import json
import math
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import numpy as np
import xarray as xr

from noslipsim.analysis.islands import islands_onsets, onset_gamma, regular_share
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
with open(snakemake.output.numbers, "w") as fh:
    json.dump(numbers, fh, indent=1, ensure_ascii=False)

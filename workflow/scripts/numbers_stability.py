"""The paper's stability claims, computed: the grids against the ellipticity threshold and the monodromy, the
pattern along the launch angle, the wedge's launch-angle transition, the period-8 and non-path-reversing orbits."""
import json
import math
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import numpy as np
import xarray as xr

from noslipsim.analysis import elliptic_boundary
from noslipsim.experiments import survival_pattern
from noslipsim.plot.numbers import below, eigenvalues_text, rounded, significant

band, min_run = snakemake.params.band, snakemake.params.min_run
grid = {k: xr.load_dataset(snakemake.input[k]) for k in ("noforce", "force", "theta")}
scan, wedge = xr.load_dataset(snakemake.input.scan), xr.load_dataset(snakemake.input.wedge)
launch = xr.load_dataset(snakemake.input.launch)
# Each value is kept to the digits its computation determines (docs/figures.md, "Which numbers and figures are the
# same on every machine").  A share of n <= 1e5 counted points is k/n: 6 significant digits tell every k apart,
# whatever order a mean summed the points in.
SHARE = 6


def threshold_side(ds):
    """Share of the points |R - R*(phi)| >= band whose survival is on the side the force-free threshold predicts."""
    R, Rs = ds.radius.values[:, None], ds.radius_threshold.values[None, :]
    keep = np.abs(R - Rs) >= band
    agree = (R > Rs) == ds.survived.values.astype(bool)
    return significant(agree[keep].mean(), SHARE), int(keep.sum()), int(keep.size)


def growth_record(launch, theta):
    """How many times the perturbed orbit launched at ``theta`` moves away from its periodic orbit over the run,
    and that this growth is linear in the collision number (a near-Jordan block), not |lambda|^(k/2)."""
    perturbed = launch.isel(orbit=slice(launch.sizes["orbit"] // 2, None))
    orbit = perturbed.isel(orbit=int(np.argmin(np.abs(perturbed.theta.values - theta))))
    dev = orbit.deviation.values
    k = np.flatnonzero(np.isfinite(dev) & (dev > 0))
    slope = dev[k[10:]] / k[10:]   # past a short transient, delta_k / k is constant if the growth is linear
    return dict(
        description=f"wedge of half-angle π/7, θ = {float(orbit.theta):g}: how many times the perturbed orbit's "
                    f"distance from the periodic one grows over its {k.size} collisions",
        # one orbit of a few hundred collisions: its distance is known far beyond 6 significant digits
        value=significant(dev[k[-1]] / dev[k[0]], SHARE), format=".0f",
        paper="1.122 remains stable (close to its periodic orbit)",
        note=(f"δ from {dev[k[0]]:.2e} to {dev[k[-1]]:.3f}; δ_k/k within {np.ptp(slope) / np.mean(slope):.0%} of its "
              "mean past collision 10: linear growth (next to the parabolic point the monodromy is nearly a Jordan "
              f"block), where |λ|^(k/2) alone predicts {float(orbit.lambda_max) ** ((k[-1] - k[0]) / 2):.2f}"))


numbers = {}
share, kept, total = threshold_side(grid["noforce"])
numbers["noforce_threshold_side"] = dict(
    description="no force: share of the R × φ grid whose survival lies on the side of the ellipticity threshold "
                "that the theory predicts", value=share, format=".1%", paper="results as expected",
    note=f"{kept} of {total} points, |R - R*(φ)| < {band:g} left out; nearly tangent orbits (φ near π/2) included")
numbers["noforce_monodromy_agreement"] = dict(
    description="no force: share of the grid where survival agrees with the monodromy's class",
    value=significant(grid["noforce"].attrs["agreement_share"], SHARE), format=".1%", paper="(not computed)",
    note=f"{grid['noforce'].attrs['n_decided']} elliptic or hyperbolic points")
theta_f = grid["force"].attrs["theta"]
numbers["force_monodromy_agreement"] = dict(
    description=f"force, θ = {theta_f:g}: share of the R × φ grid where survival agrees with the class of the "
                "monodromy under gravity", value=significant(grid["force"].attrs["agreement_share"], SHARE),
    format=".1%", paper="(not computed)", note=f"{grid['force'].attrs['n_decided']} elliptic or hyperbolic points")
share, kept, total = threshold_side(grid["force"])
numbers["force_threshold_side"] = dict(
    description=f"force, θ = {theta_f:g}: share of the grid on the side of the force-free threshold", value=share,
    format=".1%", paper="the stability threshold is unaltered",
    note=f"{kept} of {total} points; holds at small θ only: the R × θ grid shows R* falling to 0 at θ = π/2 - φ")

same = grid["force"].linear_kind.values == grid["noforce"].linear_kind.values
edge = {k: elliptic_boundary(grid[k]).attrs for k in ("noforce", "force")}
numbers["force_threshold_shift_mean"] = dict(
    description=f"force, θ = {theta_f:g}: mean of R*(φ) - R_e(φ) over the φ columns not next to the parabolic "
                "line", value=rounded(edge["force"]["mean_shift"], 10), format=".3f",
    paper="the stability threshold is unaltered", note=f"φ ≤ {edge['force']['phi_max']:.2f}")
numbers["force_class_equals_noforce"] = dict(
    description=f"force, θ = {theta_f:g}: share of the R × φ grid whose linear class under gravity is the "
                "force-free one", value=significant(same.mean(), SHARE), format=".0%",
    paper="the stability threshold is unaltered",
    note=f"{grid['force'].sizes['radius']} × {grid['force'].sizes['phi']} grid; the share falls as θ grows "
         "(config/README.md)")
# R*(φ) - R_e(φ) is a difference of nearly equal radii (~0.5, each interpolated from monodromy traces known to
# ~1e-14): it is known to an absolute ~1e-14 (another machine moved its 15th digit), so 10 decimals
numbers["force_threshold_shift"] = dict(
    description=f"force, θ = {theta_f:g}: how far below the force-free threshold R*(φ) the elliptic region "
                "begins (largest R*(φ) - R_e(φ), R_e where λ + 1/λ crosses 2)",
    value=rounded(edge["force"]["max_shift"], 10),
    format=".3f", paper="the stability threshold is unaltered",
    note=(f"at φ = {edge['force']['phi_of_max']:.2f}; mean {edge['force']['mean_shift']:.3f} over φ ≤ "
          f"{edge['force']['phi_max']:.2f} (φ + θ within 0.05 of π/2 left out); the same measure without force: "
          f"{edge['noforce']['max_shift']:.1e} (interpolation error)"))
ds = grid["noforce"]
delta = json.loads(ds.attrs["perturbation"])["angle"]
R, P = ds.radius.values[:, None], ds.phi.values[None, :]
clears = delta * (1.0 - R * np.cos(P)) > R * (1.0 - np.sin(P))
elliptic = ds.linear_kind.values == "elliptic"
escaped_elliptic = elliptic & (ds.survived.values == 0)
near_13 = np.abs(ds.eigen_sum.values + 1.0) < 0.2
numbers["noforce_clears_far_disk"] = dict(
    description="no force: grid points where the velocity turned up by the perturbation passes over the far disk, "
                "δ(1 - R cos φ) > R(1 - sin φ) (the white strip near φ = π/2 and the grazing corner), that end "
                "with 0 collisions",
    value=significant((ds.n_collisions.values[clears] == 0).mean(), SHARE) if clears.any()
    else "no such point in this grid",
    format=".1%",
    paper="samples near φ = π/2, nearly tangent, have a noticeable experimental error",
    note=(f"{int(clears.sum())} points; they are {int((escaped_elliptic & clears).sum())} of the "
          f"{int(escaped_elliptic.sum())} elliptic points that escape; of the rest, "
          f"{int((escaped_elliptic & ~clears & near_13).sum())} lie at |λ + 1/λ + 1| < 0.2, the 1:3 resonance "
          "(the white diagonal streak)"))
decided = (ds.linear_kind.values == "elliptic") | (ds.linear_kind.values == "hyperbolic")
misses = decided & (elliptic != ds.survived.values.astype(bool))
numbers["noforce_misses_clearing_far_disk"] = dict(
    description="no force: share of the misses (survival disagrees with the monodromy's class) whose turned "
                "velocity passes over the far disk at once",
    value=significant((misses & clears).sum() / misses.sum(), SHARE) if misses.any() else "no miss in this grid",
    format=".1%",
    paper="samples near φ = π/2, nearly tangent, have a noticeable experimental error",
    note=(f"{int((misses & clears).sum())} of {int(misses.sum())} misses; {int((misses & (P >= 1.45)).sum())} "
          f"lie at φ ≥ 1.45; {int((misses & ~elliptic).sum())} are hyperbolic points that survive"))

ds = grid["theta"]
phi = ds.attrs["phi"]
rows = survival_pattern(ds, dim="theta", min_run=min_run)
patterns = [r["pattern"] for r in rows]
radii = np.array([r["radius"] for r in rows])
sus = [r for r in rows if "s-u-s" in r["pattern"]]
usu = radii[[p == "u-s-u" for p in patterns]]
su = radii[[p == "s-u" for p in patterns]]
upper = [r["intervals"][-1][1] for r in rows if r["intervals"] and r["intervals"][-1][1] < ds.theta.values[-1]]
elliptic_high = int(((ds.linear_kind == "elliptic") & (ds.theta > math.pi / 2 - phi)).sum())
seen = "seen at R = " + ", ".join(f"{r['radius']:.2f}" for r in sus) if sus else "not seen"
span = lambda r: f"R {r.min():.2f}-{r.max():.2f} ({r.size} radii)" if r.size else "no radius"  # noqa: E731
numbers["theta_pattern"] = dict(
    description=f"stable → unstable → stable along θ at φ = {phi:g} (survival, each radius)",
    value=f"{seen}; unstable → stable → unstable at {span(usu)}, stable → unstable at {span(su)}",
    paper="stable → unstable → stable, a stable region near θ ≈ 1.3",
    note=(f"the survived interval ends at θ = {np.mean(upper):.3f} ± {np.std(upper):.3f} "
          f"(π/2 - φ = {math.pi / 2 - phi:.3f}); {elliptic_high} elliptic orbits above π/2 - φ") if upper else "")
numbers["theta_grid_monodromy_agreement"] = dict(
    description=f"R × θ at φ = {phi:g}: share where survival agrees with the monodromy's class",
    value=significant(ds.attrs["agreement_share"], SHARE), format=".1%", paper="(not computed)")

launch_phi = float(scan.phi.values[0])
# bisected to an absolute xtol (1e-13): 3 decimals fewer than it determines, so its last bits never reach them
t_star = rounded(scan.theta_transition.sel(phi=launch_phi), round(-math.log10(scan.attrs["xtol"])) - 3)
lam = scan.lambda_max.sel(phi=launch_phi)
at = {t: float(lam.sel(theta=t, method="nearest")) for t in snakemake.params.thetas}
numbers["wedge_transition_theta"] = dict(
    description="wedge of half-angle π/7 (full angle 2π/7): launch angle where the 2-periodic orbit turns from "
                "elliptic to hyperbolic", value=t_star, format=".6f",
    paper="between 1.122 (stable) and 1.126 (markedly unstable)",
    note=(f"= π/2 - π/7 = {math.pi / 2 - launch_phi:.6f}; |λ| per period "
          + ", ".join(f"{v:.4f} at {t:g}" for t, v in at.items())
          + "; with half-angle 2π/7 (the paper's own definition) at "
          + ", ".join(f"{float(t):.4f}" for p, t in zip(scan.phi.values, scan.theta_transition.values)
                      if not np.isclose(p, launch_phi))))
numbers["wedge_lambda_at_launch_angles"] = dict(
    description="wedge of half-angle π/7: |λ| per period (2 collisions) of the 2-periodic orbit at the paper's five "
                "launch angles", value=", ".join(f"{v:.4f}" for v in at.values()),
    paper="1.122 remains stable; the instability at 1.126 is more significant",
    note=("at θ = " + ", ".join(f"{t:g}" for t in at) + f"; all five lie above θ* = {t_star:.6f}, 1.122 by "
          f"{min(at) - t_star:.1e}: |λ| > 1 at each, so 1.122 is hyperbolic too (wedge_growth_near_transition: "
          "how much a perturbation grows there)"))
numbers["wedge_growth_near_transition"] = growth_record(launch, min(at))
for i in range(wedge.sizes["orbit"]):
    o = wedge.isel(orbit=i)
    case = str(o.case.values)
    if case.startswith("path-reversing"):
        continue
    ev = o.eigenvalue_real.values + 1j * o.eigenvalue_imag.values
    key = "wedge_" + "_".join("".join(c if c.isalnum() else " " for c in case.lower()).split())
    # the residual as the finder's tolerance (its value is rounding noise); the eigenvalues in one canonical
    # order (the solver's order of three unit eigenvalues follows the last bits)
    facts = (f"residual {below(o.residual, wedge.attrs['tol'])}; {o.linear_kind.values}, eigenvalues "
             + eigenvalues_text(ev)
             + f"; max |v_t - γw|/|V| at impacts {float(o.reversal_mismatch):.3f}")
    if int(o.unit_count):
        facts += (f"; eigenvalue 1: restarted {wedge.attrs['family_step']:g} along it, the finder lands on another "
                  f"period-{int(o.period)} orbit {float(o.family_distance):.3g} away (a one-parameter family)")
    numbers[key] = dict(description=f"wedge under gravity, {case} orbit (minimal period {int(o.minimal_period)})",
                        value="periodic, " + ("path reversing" if int(o.path_reversing) else "not path reversing"),
                        paper="isolated period 8" if int(o.period) == 8 else "2-periodic, not path reversing",
                        note=facts)
with open(snakemake.output.numbers, "w") as fh:
    json.dump(numbers, fh, indent=1, ensure_ascii=False)

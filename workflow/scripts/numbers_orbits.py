"""The orbit figures' numbers, computed: exit angles of Figure 1, the 14-periodic pentagon orbit,
drifts, two-disk stability."""
import json
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import numpy as np
import xarray as xr

from noslipsim import theory
from noslipsim.plot.numbers import below, rounded, significant

spec = xr.load_dataset(snakemake.input.specnoslip).set_index(orbit="role")
pent = xr.load_dataset(snakemake.input.pentagons)
bounce = xr.load_dataset(snakemake.input.bounce)
disks = xr.load_dataset(snakemake.input.twodisks).set_index(orbit="role")
sphere = xr.load_dataset(snakemake.input.sphere)

# Each value is kept to the digits its computation determines (docs/figures.md, "Which numbers and figures are the
# same on every machine"): a few flights and collisions in double precision determine an angle, a drift or a
# 3 x 3 monodromy's trace to ~1e-14, so 10 significant digits leave a wide margin over the last bits.
FEW_COLLISIONS = 10
numbers = {
    "specular_exit_from_vertical": dict(
        description="Figure 1: specular orbit leaving the scatterer, angle from the vertical (degrees)",
        value=significant(spec.exit_from_vertical.sel(orbit="specular"), FEW_COLLISIONS), format=".1f",
        paper="reflects nearly vertically"),
    "noslip_exit_to_corner": dict(
        description="Figure 1: no-slip orbit leaving the scatterer, angle off the upper left corner (degrees)",
        value=significant(spec.exit_to_corner.sel(orbit="no-slip"), FEW_COLLISIONS), format=".1f",
        paper="heads towards the upper left corner"),
    # a converged Newton residual is rounding noise (3.1e-16 here, 3.6e-16 on another machine): the finder
    # guarantees its tolerance, so that is the number
    "pentagon_periodic_residual": dict(
        description=f"Figure 4: residual of the {pent.attrs['period']}-periodic no-slip pentagon orbit",
        value=below(pent.periodic_residual, pent.attrs["tol"]), paper="a 14-periodic point",
        note=f"{int(pent.periodic_iterations)} Newton steps (find_periodic_orbit), its tolerance as the bound"),
    "pentagon_periodic_kind": dict(
        description="Figure 4: linear class of that orbit (rotation angle of its monodromy, rad)",
        value=f"{pent.periodic_kind.values!s} ({float(pent.rotation_angle):.4f})",
        paper="orbit restricted to a corridor"),
    # the orbit starts at the periodic point, known to the finder's tolerance (1e-12), and the distance grows about
    # linearly over 2000 collisions near the elliptic orbit (to ~1e-9; another machine moved the 10th digit):
    # 6 significant digits
    "pentagon_corridor_width": dict(
        description=f"Figure 4: corridor width after {int(pent.n_collisions[2])} collisions, velocity turned "
                    f"{pent.attrs['perturbation']:g} rad", value=significant(pent.corridor_width, 6), format=".3f",
        note="largest distance of a collision point from the periodic orbit's"),
}
for i in range(bounce.sizes["orbit"]):
    o = bounce.isel(orbit=i)
    g = bounce.attrs["gravity"]
    u = float(np.sqrt(2 * g * float(o.y_start)))                  # the start is a flight's apex
    want = float(theory.half_plane_drift(float(o.vx_start), float(o.spin_start), u, bounce.attrs["gamma"], g))
    numbers[f"bounce_drift_{i}"] = dict(
        description=f"Figure 5: drift per two bounces, γw/v_x = {float(o.spin_ratio):g}",
        # the drift is 0 exactly when v_x = γw: a relative cut or format would print its rounding noise
        # (1e-17) there, so an absolute one (a few bounces determine it to ~1e-14)
        value=rounded(o.drift, FEW_COLLISIONS), format=".6f", paper="0 iff v_x = γw (Theorem 1)",
        note=f"formula 4u(v_x - γw)/(g(1+γ²)) = {rounded(want, FEW_COLLISIONS):.6f}")
numbers["twodisk_eigen_sum"] = dict(
    description=f"Figure 8: λ + 1/λ of the 2-periodic orbit between the disks ({disks.kind.values!s})",
    value=significant(disks.eigen_sum, FEW_COLLISIONS), format=".10f", paper="elliptic below the threshold",
    note=f"closed form {float(disks.eigen_sum_theory):.10f}")
# The disks' centres are 2 apart and the collision points at angle phi on each: d = 2 - 2 R cos(phi), so
# kappa d = 2/R - 2 cos(phi); both are closed forms of the configuration, known to the last bits.
kappa_d = 2.0 / disks.attrs["radius"] - 2.0 * np.cos(disks.attrs["phi"])
numbers["twodisk_kappa_d"] = dict(
    description="Figure 8: κd of the 2-periodic orbit between the disks (curvature × distance of the collision "
                "points)", value=significant(kappa_d, FEW_COLLISIONS), format=".2f",
    paper="below the ellipticity threshold", note=f"R = {disks.attrs['radius']:g}, φ = {disks.attrs['phi']:g}")
numbers["twodisk_threshold"] = dict(
    description="Figure 8: the ellipticity threshold on κd at that φ (equation ellipticity)",
    value=significant(theory.ellipticity_threshold(disks.attrs["phi"], disks.attrs["gamma"]), FEW_COLLISIONS),
    format=".2f", paper="elliptic iff κd lies below it")
numbers["twodisk_box_collisions"] = dict(
    description="Figure 8: collisions with the box, specular / no-slip",
    value=f"{int(disks.box_collisions.sel(orbit='specular'))} of {int(disks.n_collisions.sel(orbit='specular'))}"
          f" / {int(disks.box_collisions.sel(orbit='no-slip'))} of {int(disks.n_collisions.sel(orbit='no-slip'))}",
    paper="specular scatters, no-slip stays between the disks")
numbers["sphere_drift"] = dict(
    description="Figure 16: 3D drift per two bounces, measured",
    value=significant(np.hypot(*sphere.drift.values[:2]), FEW_COLLISIONS), format=".10f",
    paper="drift along e1, 2-periodic along e2",
    note=f"formula |4u(v_T - γ n×W_T)/(g(1+γ²))| = {float(np.hypot(*sphere.drift_theory.values[:2])):.10f}")

with open(snakemake.output.numbers, "w") as fh:
    json.dump(numbers, fh, indent=1, ensure_ascii=False)

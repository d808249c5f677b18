"""Datasets of Figure 15: a stability grid of the two-disk 2-periodic orbits (R x phi or R x theta)."""
import sys

import numpy as np

sys.stderr = open(snakemake.log[0], "w", buffering=1)

from noslipsim import write_dataset
from noslipsim.analysis import stability_grid, stability_grid_theta

common, shared, grid, kind = (snakemake.params.common, snakemake.params.shared, snakemake.params.grid,
                              snakemake.params.kind)
axis = lambda a: np.linspace(a["min"], a["max"], a["n"])  # noqa: E731
# one serial compiled kernel per job (rule compile_kernels built it): jobs run side by side on -j2
run = dict(perturbation=shared["perturbation"], max_collisions=shared["max_collisions"], scheduler="sync",
           progress=True)
radii, gamma, g = axis(shared["radius"]), common["gamma"], common["gravity"]
if kind == "theta":
    ds = stability_grid_theta(radii, axis(grid["theta"]), gamma, phi=grid["phi"], gravity=g, **run)
elif kind == "force":
    ds = stability_grid(radii, axis(grid["phi"]), gamma, gravity=g, theta=grid["theta"], **run)
else:
    ds = stability_grid(radii, axis(grid["phi"]), gamma, **run)
print(f"{kind}: agreement with the linear class {ds.attrs['agreement_share']:.4f} "
      f"({ds.attrs['n_decided']} points decided)", file=sys.stderr)
write_dataset(ds, snakemake.output.grid, config={"stability": {**common, "grids": {"shared": shared, kind: grid}}},
              history=f"snakemake rule {snakemake.rule} (workflow/scripts/stability_grid.py, {kind})")

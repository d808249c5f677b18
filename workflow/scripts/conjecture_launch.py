"""Dataset of Figure S4: the linear class of the two-disk 2-periodic orbits over R x phi x theta."""
import sys

import numpy as np

sys.stderr = open(snakemake.log[0], "w", buffering=1)

from noslipsim import write_dataset
from noslipsim.cluster import ensemble_options
from noslipsim.experiments import launch_angle_classes

common, run = snakemake.params.common, snakemake.params.run
axis = lambda a: np.linspace(a["min"], a["max"], a["n"])  # noqa: E731
with ensemble_options(snakemake.config.get("runtime"), snakemake.threads) as how:
    ds = launch_angle_classes(axis(run["radius"]), axis(run["phi"]), axis(run["theta"]), common["gamma"],
                              gravity=common["gravity"], margin=run["margin"], scheduler=how["scheduler"],
                              num_workers=how["num_workers"])
print(f"{ds.attrs['n_changing']} of {ds.attrs['n_columns']} (R, phi) columns change class with theta "
      f"({ds.attrs['n_elliptic_hyperbolic']} between elliptic and hyperbolic); {ds.attrs['n_missing']} points "
      "without orbit", file=sys.stderr)
write_dataset(ds, snakemake.output.launch, config={"stability": common, "conjectures": {"launch": run}},
              history=f"snakemake rule {snakemake.rule} (workflow/scripts/conjecture_launch.py)")

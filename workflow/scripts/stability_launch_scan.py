"""Dataset of Figure 14 (bottom): lambda + 1/lambda of the 2-periodic wedge orbit along the launch angle."""
import sys

import numpy as np

sys.stderr = open(snakemake.log[0], "w", buffering=1)

from noslipsim import write_dataset
from noslipsim.experiments import wedge_launch_scan

common, run = snakemake.params.common, snakemake.params.run
scan = run["scan"]
thetas = np.union1d(np.linspace(scan["theta_min"], scan["theta_max"], scan["n_theta"]),
                    np.linspace(*scan["zoom"], scan["n_zoom"]))
ds = wedge_launch_scan(scan["phis"], np.union1d(thetas, run["thetas"]), common["gamma"],
                       gravity=common["gravity"], ell=run["ell"])
for phi, t in zip(ds.phi.values, ds.theta_transition.values):
    print(f"phi {phi:.6f}: elliptic -> hyperbolic at theta = {t:.12f} (pi/2 - phi = {np.pi / 2 - phi:.12f})",
          file=sys.stderr)
write_dataset(ds, snakemake.output.scan, config={"stability": {**common, "launch": run}},
              history=f"snakemake rule {snakemake.rule} (workflow/scripts/stability_launch_scan.py)")

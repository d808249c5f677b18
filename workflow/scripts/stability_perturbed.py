"""Datasets of Figures 9 and 14: path-reversing 2-periodic wedge orbits and identically perturbed copies."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

from noslipsim import write_dataset
from noslipsim.experiments import perturbed_wedge_orbits

common, run = snakemake.params.common, snakemake.params.run
cases = run["cases"] if "cases" in run else [{"opening": "up", "theta": t, "ell": run["ell"]} for t in run["thetas"]]
ds = perturbed_wedge_orbits(cases, phi=run["phi"], gamma=common["gamma"], gravity=common["gravity"],
                            perturbation=run["perturbation"], n_collisions=run["n_collisions"])
n = len(cases)
for i in range(n):
    print(f"theta {float(ds.theta[i]):.4f} ({ds.opening.values[i]}): {ds.linear_kind.values[i]}, "
          f"lambda + 1/lambda {float(ds.eigen_sum[i]):.6f}, perturbed run: {int(ds.n_collisions[n + i])} "
          f"collisions ({ds.stop_reason.values[n + i]})", file=sys.stderr)
write_dataset(ds, snakemake.output.orbits, config={"stability": {**common, snakemake.params.section: run}},
              history=f"snakemake rule {snakemake.rule} (workflow/scripts/stability_perturbed.py)")

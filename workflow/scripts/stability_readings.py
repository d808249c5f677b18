"""Dataset of Figure 15's readings: survival scans along theta under every reading of the paper's experiment."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

from noslipsim import write_dataset
from noslipsim.experiments import stability_readings

run = snakemake.params.run
ds = stability_readings(radii=run["radii"], n_theta=run["n_theta"])
print(f"{ds.sizes['reading']} readings x {ds.sizes['radius']} radii x {ds.sizes['theta_read']} launch angles",
      file=sys.stderr)
write_dataset(ds, snakemake.output.readings, config={"stability": {"readings": run}},
              history=f"snakemake rule {snakemake.rule} (workflow/scripts/stability_readings.py)")

"""Dataset of Figure S3: exponents and attracting cycles of Figure 13's readings against the force strength."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

from noslipsim import write_dataset
from noslipsim.experiments import hex_force_readings

run = snakemake.params.run
ds = hex_force_readings(**run, num_workers=snakemake.threads, progress=True)
write_dataset(ds, snakemake.output.portraits,
              config={"portraits": {"hex_readings": run}},
              history=f"snakemake rule {snakemake.rule} (workflow/scripts/portraits_hex_readings.py)")

"""Dataset of Figure 13: velocity portraits of a disk in a closed hexagonal cell, two gammas, three forces.

Also holds the kinetic energy after the run in the closed cell and in the periodic Lorentz gas from the
same starts, the evidence for the choice of table (config/README.md).
"""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

from noslipsim import write_dataset
from noslipsim.cluster import ensemble_options
from noslipsim.experiments import hex_force_portraits

run = snakemake.params.run
with ensemble_options(snakemake.config.get("runtime"), snakemake.threads) as how:
    ds = hex_force_portraits(**run, **how)
write_dataset(ds, snakemake.output.portraits,
              config={"portraits": {"hex_force": run}},
              history=f"snakemake rule {snakemake.rule} (workflow/scripts/portraits_hex_force.py)")

"""Dataset of Figure 1: specular and no-slip orbits from one start in a rectangle with a scatterer."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

from noslipsim import write_dataset
from noslipsim.experiments import specular_noslip_orbits

params = snakemake.params.specnoslip
ds = specular_noslip_orbits(**params)
write_dataset(ds, snakemake.output.specnoslip, config={"orbits": {"specnoslip": params}},
              history=f"snakemake rule {snakemake.rule} (workflow/scripts/orbits_specnoslip.py)")

"""Dataset of Figure 4: generic specular pentagon orbits and a no-slip orbit in a corridor near a 14-periodic point."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

from noslipsim import write_dataset
from noslipsim.experiments import pentagon_orbits

params = snakemake.params.pentagons
ds = pentagon_orbits(**params)
write_dataset(ds, snakemake.output.pentagons, config={"orbits": {"pentagons": params}},
              history=f"snakemake rule {snakemake.rule} (workflow/scripts/orbits_pentagons.py)")

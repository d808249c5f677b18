"""Dataset of Figure 16: a no-slip sphere bouncing on a plane in 3D."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

from noslipsim import write_dataset
from noslipsim.experiments import sphere_bounce

params = snakemake.params.sphere
ds = sphere_bounce(**params)
write_dataset(ds, snakemake.output.sphere, config={"orbits": {"sphere": params}},
              history=f"snakemake rule {snakemake.rule} (workflow/scripts/orbits_sphere.py)")

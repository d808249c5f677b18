"""Dataset of Figure 5: the no-slip bouncing ball, 2-periodic, back and forth with drift, steady drift."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

from noslipsim import write_dataset
from noslipsim.experiments import bounce_orbits

params = snakemake.params.bounce
ds = bounce_orbits(**params)
write_dataset(ds, snakemake.output.bounce, config={"orbits": {"bounce": params}},
              history=f"snakemake rule {snakemake.rule} (workflow/scripts/orbits_bounce.py)")

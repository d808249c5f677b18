"""Dataset of Figure 6: the 2-periodic flights of a wedge and of a tangential wedge (two disks)."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

from noslipsim import write_dataset
from noslipsim.experiments import newwedge_orbits

params = snakemake.params.newwedge
ds = newwedge_orbits(**params)
write_dataset(ds, snakemake.output.newwedge, config={"orbits": {"newwedge": params}},
              history=f"snakemake rule {snakemake.rule} (workflow/scripts/orbits_newwedge.py)")

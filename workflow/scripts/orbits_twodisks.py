"""Dataset of Figure 8: two disks in a box, specular and no-slip from one start near a stable 2-periodic orbit."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

from noslipsim import write_dataset
from noslipsim.experiments import two_disk_box_orbits

params = snakemake.params.twodisks
ds = two_disk_box_orbits(**params)
write_dataset(ds, snakemake.output.twodisks, config={"orbits": {"twodisks": params}},
              history=f"snakemake rule {snakemake.rule} (workflow/scripts/orbits_twodisks.py)")

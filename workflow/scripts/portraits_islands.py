"""Dataset of Figure 12 (bottom) and of the onset gamma: the regular share of the Sinai torus against gamma."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

from noslipsim import write_dataset
from noslipsim.experiments import sinai_islands_sweep

run = snakemake.params.run
ds = sinai_islands_sweep(**run, progress=True)
write_dataset(ds, snakemake.output.islands, config={"portraits": {"islands": run}},
              history=f"snakemake rule {snakemake.rule} (workflow/scripts/portraits_islands.py)")

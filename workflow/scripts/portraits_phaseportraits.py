"""Dataset of Figure 10: the specular lemon (Birkhoff coordinates) and the no-slip Sinai torus (reduced portrait)."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

from noslipsim import write_dataset
from noslipsim.cluster import ensemble_options
from noslipsim.experiments import lemon_sinai_portraits

run = snakemake.params.run
with ensemble_options(snakemake.config.get("runtime"), snakemake.threads) as how:
    ds = lemon_sinai_portraits(**run, **how)
write_dataset(ds, snakemake.output.portraits,
              config={"portraits": {"phaseportraits": run}},
              history=f"snakemake rule {snakemake.rule} (workflow/scripts/portraits_phaseportraits.py)")
